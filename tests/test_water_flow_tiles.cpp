// WaterFlow across tiles (nodes/hydrology/water_flow_across_tiles.cpp): each tile iterates on its samples with a
// 2k-sample halo of water exchanged every k iterations, and every sum over the domain is exact; put together, the
// tiles' depth and flux must equal the whole-domain run bit for bit, and their report must be its report, on every
// tiling (tiles of 2 and 3 samples included), for k = 1, 3, 8 and the chosen one, with rainfall and sinks linked or
// not, stopping by threshold (inside a block too) and by max_iterations. A run with one stale halo must not.
#include <cmath>
#include <functional>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/report.h"
#include "graph/tile_graph.h"
#include "nodes/common/exact_double_sum.h"
#include "nodes/hydrology/water_flow.h"
#include "nodes/hydrology/water_flow_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::same_bits;

struct Fields {
  Domain domain;
  HeightfieldPtr in, rainfall, sinks;
};

// Hills and hollows with rough noise (so water pools and runs), rainfall from 0 to 80 mm and a few sink cells.
Fields fields(glm::ivec2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Fields f;
  f.domain = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 10.0 * (size.y - 1)}, size);
  auto in = std::make_shared<Heightfield>(f.domain), rain = std::make_shared<Heightfield>(f.domain),
       sinks = std::make_shared<Heightfield>(f.domain);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      const std::size_t k = in->index(i, j);
      in->data[k] =
          3.0f * std::sin(0.31f * i) * std::cos(0.23f * j) + 0.02f * static_cast<float>(i + j) + 0.05f * u(rng);
      rain->data[k] = 80.0f * u(rng);
      sinks->data[k] = u(rng) < 0.01f ? 1.0f : 0.0f;
    }
  f.in = in, f.rainfall = rain, f.sinks = sinks;
  return f;
}

struct Outputs {
  std::vector<float> depth, flux;
  std::string report;
};

Outputs whole_domain(const Fields& f, const WaterFlowParams& p, bool rain, bool sinks, int* iterations) {
  const WaterFlowResult r =
      water_flow(*f.in, rain ? f.rainfall.get() : nullptr, sinks ? f.sinks.get() : nullptr, p, nullptr);
  if (iterations) *iterations = r.iterations;
  return {r.depth->data, r.flux->data, r.json()};
}

// The tiles' rounds as the driver runs them (messages through their bytes); `hook` may change an answer (the
// mutation). `disagreements` counts the shared samples on which two tiles differ (none in a correct run).
Outputs across_tiles(const TileGraphAlgorithm& algorithm, const Fields& f, glm::ivec2 counts, bool rain, bool sinks,
                     int* rounds_run = nullptr, const test::AnswerHook& hook = {}, int* disagreements = nullptr) {
  auto tiles =
      test::start_tiles(algorithm, f.domain, counts, {f.in, rain ? f.rainfall : nullptr, sinks ? f.sinks : nullptr});
  const int rounds = test::run_rounds(algorithm, tiles, hook);
  if (rounds_run) *rounds_run = rounds;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Outputs joined{std::vector<float>(f.in->data.size(), nan), std::vector<float>(f.in->data.size(), nan), {}};
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    test::join_tile_map(joined.depth, *std::get<HeightfieldPtr>(outputs[0]), f.domain.resolution.x, disagreements);
    test::join_tile_map(joined.flux, *std::get<HeightfieldPtr>(outputs[1]), f.domain.resolution.x, disagreements);
    const std::string report = std::get<ReportPtr>(outputs[2])->json;
    if (joined.report.empty()) joined.report = report;
    EXPECT_EQ(report, joined.report) << "every tile holds the whole domain's report";
  }
  return joined;
}

void expect_same(const Outputs& tiled, const Outputs& whole) {
  EXPECT_TRUE(same_bits(tiled.depth, whole.depth)) << "depth";
  EXPECT_TRUE(same_bits(tiled.flux, whole.flux)) << "flux";
  EXPECT_EQ(tiled.report, whole.report) << "report";
}

WaterFlowParams params(double threshold, int max_iterations) {
  WaterFlowParams p;
  p.rainfall = 40.0, p.infiltration = 10.0, p.threshold = threshold, p.max_iterations = max_iterations;
  return p;
}

// The registered algorithm (iterations per exchange from the tiles: 1 on these small tiles) and ones exchanging every
// 1, 3 and 8 iterations (halos of 2, 6 and 16 samples, wider than the smallest tiles below).
std::vector<std::pair<int, std::unique_ptr<TileGraphAlgorithm>>> algorithms(const WaterFlowParams& p,
                                                                            const Domain& whole) {
  std::vector<std::pair<int, std::unique_ptr<TileGraphAlgorithm>>> all;
  all.emplace_back(0, test::algorithm_of("WaterFlow",
                                         {{"rainfall", p.rainfall},
                                          {"infiltration", p.infiltration},
                                          {"threshold", p.threshold},
                                          {"max_iterations", static_cast<std::int64_t>(p.max_iterations)}},
                                         whole));
  for (const int k : {1, 3, 8}) all.emplace_back(k, water_flow_across_tiles(p, whole, k));
  return all;
}

// The rounds of a run of `iterations` exchanging every k iterations: the iterations per exchange, the static bands,
// a round per block, the report's sums.
int expected_rounds(int k, int iterations) {
  const int block = k > 0 ? k : 1;
  return 3 + std::max(1, (iterations + block - 1) / block);
}

const std::vector<glm::ivec2> kTilings{{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}};

TEST(WaterFlowAcrossTiles, EveryTilingEqualsTheWholeDomainRunBitForBitStoppingByThreshold) {
  const Fields f = fields({97, 81}, 3);
  const WaterFlowParams p = params(5e-3, 1000);
  const auto all = algorithms(p, f.domain);
  int inside_a_block = 0;  // runs stopping inside a block of 3
  for (const bool rain : {false, true})
    for (const bool sinks : {false, true}) {
      int iterations = 0;
      const Outputs whole = whole_domain(f, p, rain, sinks, &iterations);
      ASSERT_GT(iterations, 10);
      ASSERT_LT(iterations, p.max_iterations) << "the run must stop by threshold";
      inside_a_block += iterations % 3 != 0;
      for (const auto& [k, algorithm] : all) {
        ASSERT_TRUE(algorithm);
        for (const glm::ivec2 counts : kTilings) {
          SCOPED_TRACE("rainfall " + std::to_string(rain) + " sinks " + std::to_string(sinks) + " every " +
                       std::to_string(k) + " iterations (" + std::to_string(iterations) + " in all), tiles " +
                       test::tiles_text(counts));
          int rounds = 0, disagreements = 0;
          expect_same(across_tiles(*algorithm, f, counts, rain, sinks, &rounds, {}, &disagreements), whole);
          EXPECT_EQ(disagreements, 0);
          EXPECT_EQ(rounds, expected_rounds(k, iterations));
        }
      }
    }
  EXPECT_GT(inside_a_block, 0) << "a run must stop inside a block of 3";
}

TEST(WaterFlowAcrossTiles, EveryTilingEqualsTheWholeDomainRunStoppingByMaxIterations) {
  const Fields f = fields({97, 81}, 4);
  const WaterFlowParams p = params(0.0, 20);
  for (const bool rain : {false, true}) {
    int iterations = 0;
    const Outputs whole = whole_domain(f, p, rain, true, &iterations);
    ASSERT_EQ(iterations, 20);
    for (const auto& [k, algorithm] : algorithms(p, f.domain))
      for (const glm::ivec2 counts : kTilings) {
        SCOPED_TRACE("rainfall " + std::to_string(rain) + " every " + std::to_string(k) + " iterations, tiles " +
                     test::tiles_text(counts));
        int rounds = 0;
        expect_same(across_tiles(*algorithm, f, counts, rain, true, &rounds), whole);
        EXPECT_EQ(rounds, expected_rounds(k, iterations));
      }
  }
}

// Tiles of 2 and 3 samples: a halo sample then lies in a tile beyond the neighbor (up to 8 tiles away for a halo of
// 16 samples).
TEST(WaterFlowAcrossTiles, TilesNarrowerThanTheHaloTakeItFromTilesFurtherOn) {
  const Fields f = fields({41, 33}, 5);
  const WaterFlowParams p = params(1e-2, 1000);
  int iterations = 0;
  const Outputs whole = whole_domain(f, p, true, true, &iterations);
  ASSERT_LT(iterations, p.max_iterations);
  for (const auto& [k, algorithm] : algorithms(p, f.domain))
    for (const glm::ivec2 counts : {glm::ivec2(40, 1), glm::ivec2(20, 16), glm::ivec2(13, 32)}) {
      SCOPED_TRACE("every " + std::to_string(k) + " iterations, tiles " + test::tiles_text(counts));
      expect_same(across_tiles(*algorithm, f, counts, true, true), whole);
    }
}

// Dry terrain: the first iteration moves nothing, so the whole-domain run stops before it (0 iterations); so do the
// tiles, which ran it and go back.
TEST(WaterFlowAcrossTiles, ARunThatMovesNothingStopsBeforeItsFirstIteration) {
  const Fields f = fields({41, 33}, 6);
  WaterFlowParams p = params(1e-3, 100);
  p.rainfall = 5.0;  // below the infiltration
  int iterations = -1;
  const Outputs whole = whole_domain(f, p, false, false, &iterations);
  ASSERT_EQ(iterations, 0);
  for (const auto& [k, algorithm] : algorithms(p, f.domain)) {
    SCOPED_TRACE("every " + std::to_string(k) + " iterations");
    expect_same(across_tiles(*algorithm, f, {3, 2}, false, false), whole);
  }
}

// The mutation check: one tile keeping its halo of the block before instead of the new one (one water exchange left
// out) changes the result, so the equality above depends on every exchange.
TEST(WaterFlowAcrossTiles, AStaleHaloBreaksTheEquality) {
  const Fields f = fields({97, 81}, 3);
  const WaterFlowParams p = params(0.0, 12);
  const Outputs whole = whole_domain(f, p, true, true, nullptr);
  for (const int k : {1, 3}) {
    const auto algorithm = water_flow_across_tiles(p, f.domain, k);
    expect_same(across_tiles(*algorithm, f, {3, 2}, true, true), whole);
    // A block round's answer: the verdict (iterations kept, stop, total moved), then the halo.
    const std::size_t verdict = 2 * sizeof(std::int32_t) + ExactDoubleSum::kBytes;
    std::string previous;
    const test::AnswerHook stale = [&](std::size_t tile, int round, std::string& answer) {
      if (tile != 4 || round < 2) return true;
      if (round == 3) answer.replace(verdict, std::string::npos, previous.substr(verdict));
      previous = answer;
      return true;
    };
    SCOPED_TRACE("every " + std::to_string(k) + " iterations");
    int disagreements = 0;
    const Outputs mutated = across_tiles(*algorithm, f, {3, 2}, true, true, nullptr, stale, &disagreements);
    EXPECT_FALSE(same_bits(mutated.depth, whole.depth));
    EXPECT_GT(disagreements, 0) << "the stale tile's border must differ from its neighbors'";
  }
}

// What travels per exchange is the tiles' border bands, not the tiles; damaged bytes are refused.
TEST(WaterFlowAcrossTiles, BandsAreSmallAndTheirBytesAreChecked) {
  const Fields f = fields({97, 81}, 3);
  const auto algorithm = water_flow_across_tiles(params(1e-3, 100), f.domain, 1);
  auto tiles = test::start_tiles(*algorithm, f.domain, {2, 2}, {f.in, nullptr, nullptr});
  for (int round = 0; round < 3; ++round) {
    std::vector<std::string> messages;
    for (auto& tile : tiles) messages.push_back(tile->message(round));
    if (round == 2) {
      // Tile (0, 0) is 49 x 41 samples with neighbors right and below: 2 rows of 49 and 2 columns of 41 depths, as
      // doubles, after a header and two exact sums.
      const std::size_t header = 16 + 6 * 4 + 2 * ExactDoubleSum::kBytes;
      EXPECT_EQ(messages[0].size(), header + 8u * (2 * 49 + 2 * 41));
      test::expect_damaged_bytes_refused(*algorithm, tiles, round, messages);
    }
    const auto answers = algorithm->solve(round, messages);
    for (std::size_t t = 0; t < tiles.size(); ++t) tiles[t]->answer(round, answers[t]);
  }
}

// Exact sums do not depend on the order of addition, subnormals and cancellation included.
TEST(ExactDoubleSum, AnyOrderGivesTheSameCorrectlyRoundedSum) {
  std::mt19937_64 rng(7);
  std::vector<double> v;
  for (int k = 0; k < 2000; ++k) {
    const double m = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
    v.push_back(std::ldexp(m, static_cast<int>(rng() % 200) - 100));
  }
  v.push_back(1e300), v.push_back(-1e300), v.push_back(4.9e-324), v.push_back(0x1p-1022);
  ExactDoubleSum a, b;
  for (const double d : v) a.add(d);
  std::shuffle(v.begin(), v.end(), rng);
  ExactDoubleSum half1, half2;
  for (std::size_t k = 0; k < v.size(); ++k) (k % 2 ? half1 : half2).add(v[k]);
  b.add(half1), b.add(half2);
  EXPECT_EQ(a.value(), b.value());
  // 1 + 2^-60 - 1 is 2^-60 exactly; 2^53 + 1 + 1 rounds once to 2^53 + 2.
  ExactDoubleSum c;
  c.add(1.0), c.add(0x1p-60), c.add(-1.0);
  EXPECT_EQ(c.value(), 0x1p-60);
  ExactDoubleSum d;
  d.add(0x1p53), d.add(1.0), d.add(1.0);
  EXPECT_EQ(d.value(), 0x1p53 + 2.0);
  ExactDoubleSum e;
  e.add(0x1p53), e.add(1.0);  // a tie, to even
  EXPECT_EQ(e.value(), 0x1p53);
  ExactDoubleSum s;
  s.add(4.9e-324), s.add(4.9e-324);
  EXPECT_EQ(s.value(), 2 * 4.9e-324);
  ExactDoubleSum n;
  n.add(-3.5), n.add(1.25);
  EXPECT_EQ(n.value(), -2.25);
  std::string bytes;
  a.put(bytes);
  std::string_view view(bytes);
  ExactDoubleSum back;
  ASSERT_TRUE(back.take(view));
  EXPECT_EQ(back.value(), a.value());
}

}  // namespace
}  // namespace orogen::hydrology
