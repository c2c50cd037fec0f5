// Worley noise: exactness of the searched neighbourhood against brute force over all feature points,
// ordering of F1..F4, zeros at the feature points, and the ordering of the metrics.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_reference.h"
#include "nodes/noise/worley.h"
#include "nodes/noise/worley_neighbourhood.h"

namespace orogen {
namespace {

using noise::WorleyMetric;
using noise::WorleyOutput;
namespace ref = noise::reference;

constexpr WorleyMetric kMetrics[] = {WorleyMetric::Euclidean, WorleyMetric::Manhattan, WorleyMetric::Chebyshev};
constexpr WorleyOutput kOutputs[] = {WorleyOutput::F1, WorleyOutput::F2, WorleyOutput::F2MinusF1,
                                     WorleyOutput::F1TimesF2, WorleyOutput::MeanF1ToF4};
constexpr float kJitters[] = {0.0f, 0.25f, 0.5f, 0.8f, 1.0f};

HeightfieldPtr worley_node(const Domain& d, WorleyMetric m, WorleyOutput o, double jitter, double fs,
                           std::uint64_t seed = 3) {
  return run_node("Worley", d,
                  {{"metric", std::string(noise::kWorleyMetricNames[static_cast<int>(m)])},
                   {"output", std::string(noise::kWorleyOutputNames[static_cast<int>(o)])},
                   {"jitter", jitter},
                   {"feature_size", fs},
                   {"amplitude", 1.0},
                   {"seed", seed}})
      .get<Heightfield>();
}

// The node, for every metric, output and jitter, equals the brute-force search over all feature points of
// the 13 x 13 cells around each sample, at every sample of a domain far from the origin.
TEST(Worley, EqualsBruteForceForEveryMetricOutputAndJitter) {
  const double fs = 7.31;  // samples land at irregular fractions of a cell
  const Domain d = Domain::from_extent({-2.5e5, 4.0e5}, {fs * 12, fs * 9}, {67, 41});
  for (WorleyMetric m : kMetrics)
    for (WorleyOutput o : kOutputs)
      for (float jitter : kJitters) {
        const auto h = worley_node(d, m, o, jitter, fs);
        const std::uint32_t key = noise::stream_key(3, noise::Stream::Worley);
        int bad = 0;
        for (int j = 0; j < d.height(); ++j)
          for (int i = 0; i < d.width(); ++i) {
            const auto brute = ref::worley_brute_force(d.x(i) / fs, d.y(j) / fs, key, m, jitter);
            const float expected = ref::worley_select(brute, o);
            if (std::fabs(h->at(i, j) - expected) > 1e-5f && ++bad < 5)
              ADD_FAILURE() << "metric " << int(m) << " output " << int(o) << " jitter " << jitter << " at " << i << ","
                            << j << ": " << h->at(i, j) << " vs brute force " << expected;
          }
      }
}

// The proof in worley_neighbourhood.h, checked directly: for many random samples, the cells holding the
// four nearest points (found by brute force) are always in the (mirrored) neighbourhood.
TEST(Worley, NeighbourhoodContainsTheCellsOfTheNearestPoints) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> pos(-1e4, 1e4);
  for (WorleyMetric m : kMetrics)
    for (float jitter : {0.5f, 1.0f})
      for (int rank : {1, 2, 4}) {
        const auto n = noise::worley_neighbourhood(m, jitter, rank);
        std::set<std::pair<int, int>> cells;
        for (int k = 0; k < n.size(); ++k)
          cells.insert({n.dx[static_cast<std::size_t>(k)], n.dy[static_cast<std::size_t>(k)]});
        const std::uint32_t key = noise::stream_key(rank, noise::Stream::Worley);
        int missing = 0;
        for (int s = 0; s < 20000; ++s) {
          const double u = pos(rng), v = pos(rng);
          const auto x = ref::split(u), y = ref::split(v);
          std::vector<std::pair<float, std::pair<int, int>>> all;
          for (int dy = -6; dy <= 6; ++dy)
            for (int dx = -6; dx <= 6; ++dx) {
              const auto p = ref::worley_offset(x.cell, y.cell, x.frac, y.frac, dx, dy, key, jitter);
              all.push_back({ref::worley_distance(m, p[0], p[1]), {dx, dy}});
            }
          std::partial_sort(all.begin(), all.begin() + rank, all.end());
          for (int r = 0; r < rank; ++r) {
            auto [dx, dy] = all[static_cast<std::size_t>(r)].second;
            if (x.frac < 0.5f) dx = -dx;  // into the mirrored frame of the list
            if (y.frac < 0.5f) dy = -dy;
            if (!cells.count({dx, dy}) && ++missing < 5)
              ADD_FAILURE() << "metric " << int(m) << " jitter " << jitter << " rank " << rank << ": cell (" << dx
                            << "," << dy << ") of the " << r + 1 << "-th nearest point is not searched";
          }
        }
      }
}

TEST(Worley, NeighbourhoodSizesAreModest) {
  // Exactness must not cost a huge search: the largest case (F4, Manhattan, jitter 1) stays small.
  for (WorleyMetric m : kMetrics) {
    EXPECT_LE(noise::worley_neighbourhood(m, 1.0f, 1).size(), 20);  // 15, 19, 9
    EXPECT_LE(noise::worley_neighbourhood(m, 1.0f, 4).size(), 36);  // 30, 34, 16
  }
  // Jitter 0: the points are the cell centres; for a sample in the upper-right quarter of its cell the
  // nearest centre is its own or the one right of it or above it (the diagonal one can only tie).
  EXPECT_EQ(noise::worley_neighbourhood(WorleyMetric::Euclidean, 0.0f, 1).size(), 3);
}

TEST(Worley, DistancesAreOrdered) {
  const double fs = 9.7;
  const Domain d = Domain::from_extent({13, 17}, {fs * 20, fs * 20}, {120, 120});
  for (WorleyMetric m : kMetrics) {
    const auto f1 = worley_node(d, m, WorleyOutput::F1, 1.0, fs);
    const auto f2 = worley_node(d, m, WorleyOutput::F2, 1.0, fs);
    const auto diff = worley_node(d, m, WorleyOutput::F2MinusF1, 1.0, fs);
    const auto mean = worley_node(d, m, WorleyOutput::MeanF1ToF4, 1.0, fs);
    for (std::size_t k = 0; k < f1->data.size(); ++k) {
      ASSERT_GE(f1->data[k], 0.0f);
      ASSERT_LE(f1->data[k], f2->data[k]);
      ASSERT_GE(diff->data[k], 0.0f);
      ASSERT_NEAR(diff->data[k], f2->data[k] - f1->data[k], 1e-6f);
      ASSERT_GE(mean->data[k], f1->data[k]);  // mean of F1..F4 lies between F1 and F4
    }
  }
  // F1 <= F2 <= F3 <= F4 by brute force at random points, for each metric.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(-100, 100);
  for (WorleyMetric m : kMetrics)
    for (int s = 0; s < 2000; ++s) {
      const auto f = ref::worley_brute_force(pos(rng), pos(rng), 77, m, 1.0f).f;
      ASSERT_LE(0.0f, f[0]);
      ASSERT_LE(f[0], f[1]);
      ASSERT_LE(f[1], f[2]);
      ASSERT_LE(f[2], f[3]);
    }
}

TEST(Worley, F1IsZeroAtTheFeaturePoints) {
  const double fs = 50.0;
  const std::uint64_t seed = 8;
  const std::uint32_t key = noise::stream_key(seed, noise::Stream::Worley);
  for (WorleyMetric m : kMetrics)
    for (int cx = -4; cx <= 4; ++cx)
      for (int cy = -4; cy <= 4; ++cy) {
        // The feature point of cell (cx, cy) in world metres, and a 1-sample domain sitting on it.
        const auto off = ref::worley_offset(static_cast<std::uint32_t>(cx), static_cast<std::uint32_t>(cy), 0.0f, 0.0f,
                                            0, 0, key, 1.0f);
        const glm::dvec2 p{(cx + off[0]) * fs, (cy + off[1]) * fs};
        const Domain d = Domain::from_extent(p, {1.0, 1.0}, {1, 1});
        const auto h = worley_node(d, m, WorleyOutput::F1, 1.0, fs, seed);
        EXPECT_NEAR(h->at(0, 0), 0.0f, 1e-5f) << cx << "," << cy;
        // A little away from it F1 is not 0.
        const Domain beside = Domain::from_extent(p + glm::dvec2(0.2 * fs, 0.0), {1.0, 1.0}, {1, 1});
        EXPECT_GT(worley_node(beside, m, WorleyOutput::F1, 1.0, fs, seed)->at(0, 0), 0.05f);
      }
}

TEST(Worley, ChebyshevAtMostEuclideanAtMostManhattan) {
  const double fs = 11.3;
  const Domain d = Domain::from_extent({-300, 200}, {fs * 15, fs * 15}, {100, 100});
  for (WorleyOutput o : {WorleyOutput::F1, WorleyOutput::F2, WorleyOutput::MeanF1ToF4})
    for (float jitter : {0.5f, 1.0f}) {
      const auto cheb = worley_node(d, WorleyMetric::Chebyshev, o, jitter, fs);
      const auto eucl = worley_node(d, WorleyMetric::Euclidean, o, jitter, fs);
      const auto manh = worley_node(d, WorleyMetric::Manhattan, o, jitter, fs);
      std::size_t strict = 0;
      for (std::size_t k = 0; k < eucl->data.size(); ++k) {
        ASSERT_LE(cheb->data[k], eucl->data[k] + 1e-6f);
        ASSERT_LE(eucl->data[k], manh->data[k] + 1e-6f);
        strict += cheb->data[k] < eucl->data[k] && eucl->data[k] < manh->data[k];
      }
      EXPECT_GT(strict, eucl->data.size() / 2);
    }
}

TEST(Worley, JitterZeroIsTheGridOfCellCentres) {
  const double fs = 10.0;
  // Samples at cell centres (F1 = 0) and cell corners (F1 = distance to the 4 surrounding centres).
  const Domain d = Domain::from_extent({0, 0}, {fs * 8, fs * 8}, {17, 17});  // every half cell
  for (WorleyMetric m : kMetrics) {
    const auto f1 = worley_node(d, m, WorleyOutput::F1, 0.0, fs);
    const auto f4 = worley_node(d, m, WorleyOutput::MeanF1ToF4, 0.0, fs);
    const float corner = static_cast<float>(noise::worley_metric(m, 0.5, 0.5));
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i) {
        if (i % 2 == 1 && j % 2 == 1) {
          EXPECT_NEAR(f1->at(i, j), 0.0f, 1e-6f);
        }
        if (i % 2 == 0 && j % 2 == 0) {
          EXPECT_NEAR(f1->at(i, j), corner, 1e-6f);
          EXPECT_NEAR(f4->at(i, j), corner, 1e-6f);  // four centres at the same distance
        }
      }
  }
}

TEST(Worley, RejectsJitterOutsideZeroToOne) {
  noise::WorleyParams p;
  p.jitter = 1.5;
  EXPECT_ANY_THROW(noise::worley_plan(p));
}

}  // namespace
}  // namespace orogen
