// KMeansClusters across tiles (nodes/climate/kmeans_across_tiles.cpp): the tiles' tallies of exact sums
// (nodes/common/exact_float_sum.h) add up to the whole domain's, so the labels, colors and report put together from
// the tiles must equal the whole-domain node's bit for bit on every tiling (tiles two samples wide included), with
// NaN features, zero weights and a tolerance that stops early. Runs that drop one tile's answer in one round, or
// count the samples tiles share twice, must not.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <random>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "graph/tile_graph.h"
#include "nodes/climate/kmeans.h"
#include "nodes/climate/kmeans_across_tiles.h"
#include "nodes/climate/kmeans_steps.h"
#include "nodes/common/exact_float_sum.h"
#include "support/tile_graph_run.h"
#include "support/tile_windows.h"

namespace orogen::climate {
namespace {

using test::edge;
using test::same_bits;

TEST(ExactFloatSum, IndependentOfOrderAndCorrectlyRounded) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> v;
  for (int i = 0; i < 5000; ++i) v.push_back(std::ldexp(u(rng), static_cast<int>(rng() % 120) - 60));
  v.push_back(std::numeric_limits<float>::denorm_min());
  v.push_back(-3e38f);
  v.push_back(3e38f);
  ExactFloatSum a;
  for (float x : v) a.add(x);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(v.begin(), v.end(), rng);
    ExactFloatSum b, c;
    for (std::size_t i = 0; i < v.size(); ++i) (i % 3 ? b : c).add(v[i]);
    b.add(c);
    const double x = a.value(), y = b.value();
    EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0);
  }
  // Sums a double holds exactly come out exactly; halfway cases round to even; anything below breaks the tie.
  ExactFloatSum s;
  for (float x : {1e30f, 1.0f, -1e30f, 0.25f}) s.add(x);
  EXPECT_EQ(s.value(), 1.25);
  ExactFloatSum tie;
  for (float x : {9007199254740992.0f, 1.0f}) tie.add(x);  // 2^53 + 1: halfway, to even
  EXPECT_EQ(tie.value(), 9007199254740992.0);
  tie.add(std::ldexp(1.0f, -100));  // just above halfway
  EXPECT_EQ(tie.value(), 9007199254740994.0);
  ExactFloatSum neg;
  for (float x : {-9007199254740992.0f, -3.0f}) neg.add(x);  // -(2^53 + 3): halfway, to even
  EXPECT_EQ(neg.value(), -9007199254740996.0);
  ExactFloatSum inf;
  inf.add(std::numeric_limits<float>::infinity());
  inf.add(1.0f);
  EXPECT_EQ(inf.value(), std::numeric_limits<double>::infinity());
  // The bytes round-trip.
  std::string bytes;
  a.put(bytes);
  std::string_view in(bytes);
  ExactFloatSum back;
  ASSERT_TRUE(back.take(in));
  EXPECT_TRUE(in.empty());
  EXPECT_EQ(back.value(), a.value());
}

// Five named channels (the node's weight groups) with planted blobs and noise, and a few NaN cells.
// With `wide`, one channel spans 2^-20 .. 2^20 times its values, so the sums of its members in double depend on the
// order of addition.
std::shared_ptr<Image> features(glm::ivec2 size, unsigned seed, bool with_nan, bool wide = false) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.5f);  // blobs that overlap: many iterations
  const Domain d = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 10.0 * (size.y - 1)}, size);
  auto img = std::make_shared<Image>(d, 5);
  img->channel_names = {"slope", "temperature_jan", "illumination_jun", "humidity_jul", "rock"};
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      const int blob = (i * 3 / size.x) + 3 * (j * 2 / size.y);
      float* p = img->pixel(i, j);
      for (int c = 0; c < 5; ++c) p[c] = static_cast<float>((blob * (c + 2)) % 7) + noise(rng);
      if (wide) p[4] = std::ldexp(p[4], (i * 7 + j * 3) % 41 - 20);
      if (with_nan && (i * 7 + j * 13) % 97 == 5) p[(i + j) % 5] = std::numeric_limits<float>::quiet_NaN();
    }
  return img;
}

struct Joined {
  std::vector<float> ids, color;
  std::vector<std::string> reports;  // one per tile
  int rounds = 0;
};

std::string report_of(const PortValue& v) { return std::get<ReportPtr>(v)->json; }

// The tiles' rounds as the driver runs them (messages through their bytes); `skip(tile, round)` drops that tile's
// answer of that round (a lost exchange: the mutation). With `overlap`, each tile's window reaches one sample further
// right and up where it can, so every tile tallies the samples it shares with the tiles after it (a mutation: those
// count twice).
Joined across_tiles(const TileGraphAlgorithm& algorithm, const Image& img, glm::ivec2 counts,
                    const std::function<bool(std::size_t, int)>& skip = {}, bool overlap = false) {
  const glm::ivec2 size = img.domain.resolution;
  std::vector<std::unique_ptr<TileGraphTile>> tiles;
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti) {
      const glm::ivec2 first{edge(ti, size.x, counts.x), edge(tj, size.y, counts.y)};
      glm::ivec2 n = glm::ivec2(edge(ti + 1, size.x, counts.x), edge(tj + 1, size.y, counts.y)) - first + 1;
      if (overlap) n = glm::min(n + 1, size - first);
      auto c = std::make_shared<Image>(img.domain.subdomain(first.x, first.y, n.x, n.y), img.channels);
      c->channel_names = img.channel_names;
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) std::copy_n(img.pixel(first.x + i, first.y + j), img.channels, c->pixel(i, j));
      tiles.push_back(algorithm.start({ImagePtr(c)}));
    }
  Joined joined;
  joined.rounds = test::run_rounds(algorithm, tiles, test::dropping(skip));
  const std::size_t n = img.domain.sample_count();
  joined.ids.assign(n, -1.0f);
  joined.color.assign(n * 4, -1.0f);
  for (auto& tile : tiles) {
    const auto out = tile->outputs();
    const Heightfield& ids = *std::get<HeightfieldPtr>(out[0]);
    const Image& color = *std::get<ImagePtr>(out[2]);
    joined.reports.push_back(report_of(out[1]));
    for (int j = 0; j < ids.height(); ++j)
      for (int i = 0; i < ids.width(); ++i) {
        const std::size_t q = static_cast<std::size_t>(ids.domain.first.y + j) * size.x + ids.domain.first.x + i;
        joined.ids[q] = ids.at(i, j);
        std::copy_n(color.pixel(i, j), 4, joined.color.data() + q * 4);
      }
  }
  return joined;
}

struct Case {
  int k = 6, max_iterations = 100;
  double tolerance = 0.0;
  KMeansGroupWeights weights;
};

KMeansParams params_of(const Case& c, const Image& img) {
  KMeansParams p;
  p.k = c.k, p.max_iterations = c.max_iterations, p.tolerance = c.tolerance;
  p.weights = group_weights(img.channel_names, img.channels, c.weights.slope, c.weights.temperature,
                            c.weights.illumination, c.weights.humidity, c.weights.other);
  return p;
}

void expect_every_tiling(const Image& img, const Case& c) {
  const KMeansParams p = params_of(c, img);
  const KMeansResult whole = kmeans(img, p);
  const KMeansMaps maps = kmeans_maps(whole, img.domain);
  const std::string report = kmeans_report(whole, img.channel_names);
  const auto algorithm = kmeans_across_tiles(p, c.weights, img.domain);
  std::vector<glm::ivec2> tilings;
  for (int ny = 1; ny <= 6; ++ny)
    for (int nx = 1; nx <= 7; ++nx) tilings.push_back({nx, ny});
  tilings.push_back({img.width() - 1, 1});   // tiles two samples wide
  tilings.push_back({2, img.height() - 1});  // and two samples high
  for (const glm::ivec2 counts : tilings) {
    const Joined j = across_tiles(*algorithm, img, counts);
    EXPECT_TRUE(same_bits(j.ids, maps.ids->data)) << test::tiles_text(counts);
    EXPECT_TRUE(same_bits(j.color, maps.color->data)) << test::tiles_text(counts);
    EXPECT_EQ(j.rounds, whole.iterations + 1) << test::tiles_text(counts);
    for (const auto& r : j.reports) EXPECT_EQ(r, report) << test::tiles_text(counts);
  }
}

TEST(KMeansTiles, EqualsTheWholeDomainOnEveryTiling) {
  const auto img = features({33, 29}, 1, false);
  expect_every_tiling(*img, Case{});
}

TEST(KMeansTiles, NaNFeaturesZeroWeightsAndEarlyStop) {
  const auto img = features({41, 37}, 2, true);
  Case c;
  c.k = 9;
  c.tolerance = 0.02;
  c.weights.humidity = 0.0;  // a zero-weight channel: its center is the plain mean of the members
  expect_every_tiling(*img, c);
}

TEST(KMeansTiles, FeaturesWhoseDoubleSumsDependOnTheOrder) {
  const auto img = features({37, 31}, 5, false, true);
  Case c;
  c.k = 5;
  c.weights.other = 1e-6;
  expect_every_tiling(*img, c);
}

TEST(KMeansTiles, StopsAtTheIterationCap) {
  const auto img = features({35, 33}, 3, true);
  Case c;
  c.k = 13;
  c.max_iterations = 2;
  const KMeansResult whole = kmeans(*img, params_of(c, *img));
  ASSERT_FALSE(whole.converged);
  expect_every_tiling(*img, c);
}

TEST(KMeansTiles, MoreClustersThanSamplesAndOneSampleWideDomains) {
  Case c;
  c.k = 64;
  expect_every_tiling(*features({9, 7}, 4, false), c);
}

// The mutations: a tile that misses one round's new centres gives another report, and so do tiles whose tallies count
// the samples they share twice (so the tests above can fail); a tally leaves out the samples a tile shares with the
// tiles after it.
TEST(KMeansTiles, ALostAnswerOrSharedSamplesCountedTwiceChangeTheReportAndTalliesLeaveOutSharedSamples) {
  const auto img = features({33, 29}, 1, false);
  const Case c;
  const KMeansParams p = params_of(c, *img);
  const KMeansResult whole = kmeans(*img, p);
  const KMeansMaps maps = kmeans_maps(whole, img->domain);
  const auto algorithm = kmeans_across_tiles(p, c.weights, img->domain);
  ASSERT_GE(whole.iterations, 3);
  const std::string report = kmeans_report(whole, img->channel_names);
  const Joined lost =
      across_tiles(*algorithm, *img, {3, 2}, [](std::size_t tile, int round) { return tile == 0 && round == 2; });
  // Lloyd's iterations heal a lost round here (the same labels in the end), but not the figures on the way: a tile
  // that got every answer reports other objectives.
  EXPECT_NE(lost.reports[1], report);
  // Tiles of 2 x 1 whose tallies count their shared column twice (no initial centre on it: each is owned once).
  for (int k = 0; k < c.k; ++k) ASSERT_NE(kmeans_diagonal_cell(k, c.k, 33, 29).x, edge(1, 33, 2));
  const Joined twice = across_tiles(*algorithm, *img, {2, 1}, {}, true);
  for (const auto& r : twice.reports) EXPECT_NE(r, report);
  // The sums of a tiling whose tiles count every sample they hold (the shared ones twice) differ from the whole's.
  const KMeansFeatures f = kmeans_features(*img, p.weights);
  std::vector<double> centres(static_cast<std::size_t>(c.k) * 5);
  for (int k = 0; k < c.k; ++k) {
    const glm::ivec2 cell = kmeans_diagonal_cell(k, c.k, 33, 29);
    for (int ch = 0; ch < 5; ++ch)
      centres[static_cast<std::size_t>(k * 5 + ch)] = f.x[(static_cast<std::size_t>(cell.y) * 33 + cell.x) * 5 + ch];
  }
  std::vector<std::int32_t> labels(f.valid.size(), -1);
  const KMeansTally all = kmeans_assign(f, centres, c.k, labels);
  std::vector<std::int32_t> again(f.valid.size(), -1);
  const KMeansTally fewer = kmeans_assign(kmeans_features(*img, p.weights, {32, 29}), centres, c.k, again);
  std::int64_t n_all = 0, n_fewer = 0;
  for (auto v : all.counts) n_all += v;
  for (auto v : fewer.counts) n_fewer += v;
  EXPECT_EQ(n_all, 33 * 29);
  EXPECT_EQ(n_fewer, 32 * 29);
  EXPECT_EQ(labels, again);  // every cell is assigned; only the tally leaves the column out
}

TEST(KMeansTiles, RegisteredForDiagonalInitOnly) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  EXPECT_NE(test::algorithm_of("KMeansClusters", {}, d), nullptr);
  EXPECT_EQ(test::algorithm_of("KMeansClusters", {{"init", ParamValue(std::string("kmeans++"))}}, d), nullptr);
}

}  // namespace
}  // namespace orogen::climate
