// KMeansClusters: planted clusters recovered exactly, objective never increases, counts, a brute-force
// Lloyd reference, determinism across thread counts, the node and its keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>
#include <map>
#include <set>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "evaluator/run_node.h"
#include "graph/report.h"
#include "nodes/climate/kmeans.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/hash.h"

using orogen::hash01;
using orogen::hash64;
#include "support/key_checks.h"

namespace orogen::climate {
namespace {

// k blobs in a 3-channel feature space; the planted label of cell q is planted(q).
Image blobs(int w, int h, int k, int (*planted)(int i, int j, int w, int h, int k), std::vector<int>& truth) {
  Image img(Domain::from_extent({0, 0}, {w - 1.0, h - 1.0}, {w, h}), 3);
  img.channel_names = {"a", "b", "c"};
  truth.assign(std::size_t(w) * std::size_t(h), 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t q = std::size_t(j) * std::size_t(w) + std::size_t(i);
      const int c = planted(i, j, w, h, k);
      truth[q] = c;
      float* px = img.pixel(i, j);
      for (int ch = 0; ch < 3; ++ch)
        px[ch] =
            static_cast<float>(100.0 * ((c * (ch + 1) * 7) % 11) + 10.0 * (hash01(3, q * 3 + std::size_t(ch)) - 0.5));
    }
  return img;
}

int bands(int i, int j, int w, int h, int k) { return std::min(k - 1, (i + j) * k / (w + h - 1)); }
int scattered(int i, int j, int w, int, int k) {
  return int(hash64(11, std::uint64_t(j) * std::uint64_t(w) + std::uint64_t(i)) % std::uint64_t(k));
}

// Same partition up to a renumbering of the clusters.
void expect_same_partition(const std::vector<std::int32_t>& got, const std::vector<int>& truth) {
  std::map<int, int> to_truth;
  std::set<int> used;
  for (std::size_t q = 0; q < got.size(); ++q) {
    auto [it, inserted] = to_truth.emplace(got[q], truth[q]);
    if (inserted) {
      EXPECT_TRUE(used.insert(truth[q]).second) << "two clusters map to planted blob " << truth[q];
    }
    ASSERT_EQ(it->second, truth[q]) << "cell " << q;
  }
}

TEST(KMeans, RecoversPlantedBlobsDiagonalInit) {
  std::vector<int> truth;
  const Image img = blobs(61, 47, 4, bands, truth);
  KMeansParams p;
  p.k = 4;
  const auto r = kmeans(img, p);
  EXPECT_TRUE(r.converged);
  expect_same_partition(r.labels, truth);
}

TEST(KMeans, RecoversPlantedBlobsKMeansPlusPlus) {
  std::vector<int> truth;
  const Image img = blobs(64, 64, 5, scattered, truth);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    KMeansParams p;
    p.k = 5;
    p.init = KMeansInit::PlusPlus;
    p.seed = seed;
    const auto r = kmeans(img, p);
    EXPECT_TRUE(r.converged);
    expect_same_partition(r.labels, truth);
  }
}

// Straightforward serial Lloyd with the same initial centres: the reference for labels and centres.
TEST(KMeans, MatchesBruteForceLloydAndObjectiveNeverIncreases) {
  Image img(Domain::from_extent({0, 0}, {50, 40}, {51, 41}), 4);
  for (std::size_t q = 0; q < img.data.size(); ++q)
    img.data[q] = static_cast<float>(std::sin(0.37 * q) * 10.0 + (q % 7));
  KMeansParams p;
  p.k = 7;
  p.max_iterations = 500;
  p.tolerance = 0.0;
  p.weights = {1.0, 0.5, 2.0, 0.1};
  const auto r = kmeans(img, p);
  for (std::size_t t = 1; t < r.objective.size(); ++t)
    EXPECT_LE(r.objective[t], r.objective[t - 1] * (1 + 1e-6)) << t;  // float distances
  std::int64_t total = 0;
  for (auto c : r.counts) total += c;
  EXPECT_EQ(total, 51 * 41);

  const int W = 51, H = 41, C = 4, k = 7;
  const std::size_t n = std::size_t(W) * H;
  std::vector<double> cen(std::size_t(k) * C);
  for (int c = 0; c < k; ++c) {
    const double t = (c + 0.5) / k;
    const std::size_t q = std::size_t(std::lround(t * (H - 1))) * W + std::size_t(std::lround(t * (W - 1)));
    for (int ch = 0; ch < C; ++ch)
      cen[std::size_t(c * C + ch)] = float(img.data[q * C + std::size_t(ch)] * std::sqrt(p.weights[std::size_t(ch)]));
  }
  std::vector<int> lab(n, -1);
  for (int it = 0; it < 500; ++it) {
    bool changed = false;
    for (std::size_t q = 0; q < n; ++q) {
      int best = 0;
      float bd = 3e38f;
      for (int c = 0; c < k; ++c) {
        float d = 0;  // float, channel by channel, as the implementation
        for (int ch = 0; ch < C; ++ch) {
          const float e = float(img.data[q * C + std::size_t(ch)] * std::sqrt(p.weights[std::size_t(ch)])) -
                          float(cen[std::size_t(c * C + ch)]);
          d += e * e;
        }
        if (d < bd) {
          bd = d;
          best = c;
        }
      }
      changed |= lab[q] != best;
      lab[q] = best;
    }
    if (!changed) break;
    std::vector<double> s(std::size_t(k) * C, 0.0);
    std::vector<int> cnt(std::size_t(k), 0);
    for (std::size_t q = 0; q < n; ++q) {
      ++cnt[std::size_t(lab[q])];
      for (int ch = 0; ch < C; ++ch)
        s[std::size_t(lab[q] * C + ch)] +=
            float(img.data[q * C + std::size_t(ch)] * std::sqrt(p.weights[std::size_t(ch)]));
    }
    for (int c = 0; c < k; ++c)
      if (cnt[std::size_t(c)])
        for (int ch = 0; ch < C; ++ch) cen[std::size_t(c * C + ch)] = s[std::size_t(c * C + ch)] / cnt[std::size_t(c)];
  }
  ASSERT_TRUE(r.converged);
  for (std::size_t q = 0; q < n; ++q) ASSERT_EQ(r.labels[q], lab[q]) << q;
  for (int c = 0; c < k; ++c)
    for (int ch = 0; ch < C; ++ch)
      EXPECT_NEAR(r.centres[std::size_t(c * C + ch)],
                  cen[std::size_t(c * C + ch)] / std::sqrt(p.weights[std::size_t(ch)]), 1e-6);
}

TEST(KMeans, BitIdenticalAcrossThreadCounts) {
  Image img(Domain::from_extent({0, 0}, {200, 150}, {201, 151}), 5);
  for (std::size_t q = 0; q < img.data.size(); ++q)
    img.data[q] = static_cast<float>(std::sin(0.013 * q) * 50.0 + std::cos(0.7 * q));
  for (auto init : {KMeansInit::Diagonal, KMeansInit::PlusPlus}) {
    KMeansParams p;
    p.k = 9;
    p.init = init;
    p.seed = 42;
    KMeansResult a, b;
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      a = kmeans(img, p);
    }
    {
      tbb::global_control many(tbb::global_control::max_allowed_parallelism, 4);
      b = kmeans(img, p);
    }
    EXPECT_EQ(a.labels, b.labels);
    EXPECT_EQ(a.centres, b.centres);
    EXPECT_EQ(a.objective, b.objective);
  }
}

TEST(KMeans, GroupWeightsByChannelName) {
  const auto w =
      group_weights({"slope", "temperature_jan", "illumination_feb", "humidity_mar", "other"}, 6, 1, 2, 3, 0.1, 5);
  EXPECT_EQ(w, (std::vector<double>{1, 2, 3, 0.1, 5, 5}));
}

KMeansResult three_cells() {
  KMeansResult r;
  r.k = 2;
  r.channels = 3;
  r.labels = {1, 0, 1};
  r.centres = {1.5, -2.0, 0.25, 7.0, std::nan(""), 3.0};
  r.counts = {1, 2};
  r.objective = {10.5, std::numeric_limits<double>::infinity(), 4.0};
  r.iterations = 3;
  r.converged = true;
  return r;
}

TEST(KMeans, MapsHoldTheLabelsAndTheirCategoricalColors) {
  const Domain d = Domain::from_extent({5, 6}, {2, 0}, {3, 1});
  const KMeansMaps m = kmeans_maps(three_cells(), d);
  EXPECT_EQ(m.ids->domain.resolution, d.resolution);
  EXPECT_EQ(m.ids->data, (std::vector<float>{1, 0, 1}));
  ASSERT_EQ(m.color->channels, 4);
  EXPECT_EQ(m.color->channel_names, (std::vector<std::string>{"R", "G", "B", "A"}));
  for (int i = 0; i < 3; ++i) {
    const glm::vec4 c = categorical_linear(i == 1 ? 0 : 1);
    for (int ch = 0; ch < 4; ++ch) EXPECT_EQ(m.color->pixel(i, 0)[ch], c[ch]) << i << " " << ch;
  }
  EXPECT_NE(categorical_linear(0), categorical_linear(1));
}

// A non-finite figure is null in the report (report_number): a NaN centre is not a centre at 0.
TEST(KMeans, ReportNamesCentresByChannelAndNullsNonFiniteNumbers) {
  const auto j = nlohmann::json::parse(kmeans_report(three_cells(), {"slope", "temperature_jan"}));
  EXPECT_EQ(j["k"], 2);
  EXPECT_EQ(j["iterations"], 3);
  EXPECT_EQ(j["converged"], true);
  EXPECT_EQ(j["objective"], nlohmann::json::parse("[10.5, null, 4.0]"));
  ASSERT_EQ(j["clusters"].size(), 2u);
  for (int c = 0; c < 2; ++c) {
    const auto& cl = j["clusters"][static_cast<std::size_t>(c)];
    EXPECT_EQ(cl["id"], c);
    const glm::vec4 col = categorical_linear(c);
    EXPECT_EQ(cl["color"], nlohmann::json({col.r, col.g, col.b}));
  }
  EXPECT_EQ(j["clusters"][0]["count"], 1);
  EXPECT_EQ(j["clusters"][1]["count"], 2);
  // The third channel has no name: channel_2.
  EXPECT_EQ(j["clusters"][0]["center"],
            nlohmann::json::parse(R"({"slope": 1.5, "temperature_jan": -2.0, "channel_2": 0.25})"));
  EXPECT_EQ(j["clusters"][1]["center"],
            nlohmann::json::parse(R"({"slope": 7.0, "temperature_jan": null, "channel_2": 3.0})"));
}

TEST(KMeans, NodeOutputsAndKeys) {
  std::vector<int> truth;
  auto img = std::make_shared<Image>(blobs(33, 33, 3, bands, truth));
  const Domain d = img->domain;
  const auto r = run_node("KMeansClusters", d, {{"k", std::int64_t{3}}}, {{"in", PortValue(ImagePtr(img))}});
  const auto ids = r.get<Heightfield>(0);
  const auto report = nlohmann::json::parse(r.get<Report>(1)->json);
  EXPECT_EQ(report["k"], 3);
  std::int64_t total = 0;
  for (const auto& c : report["clusters"]) total += c["count"].get<std::int64_t>();
  EXPECT_EQ(total, 33 * 33);
  for (float v : ids->data) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 2.0f);
  }
  expect_every_param_changes_key("KMeansClusters", d);
  expect_every_input_changes_key("KMeansClusters", d);
}

}  // namespace
}  // namespace orogen::climate
