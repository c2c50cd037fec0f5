// ThermalErosion across tiles (nodes/erosion/thermal_across_tiles.cpp): each tile iterates on its samples with a
// 2k-sample halo exchanged every k iterations; put together, the tiles must equal the whole-domain run bit for bit on
// every tiling (tiles of 2 samples included), for k = 1, 3, 8 and the chosen one, with mask and hardness linked or
// not, stopping at the same iteration (inside a block too). A run that skips one halo exchange must not.
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/thermal.h"
#include "nodes/erosion/thermal_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::erosion {
namespace {

using test::same_bits;

struct Fields {
  Domain domain;
  HeightfieldPtr in, mask, hardness;
};

// Rough random heights (steeper than the talus almost everywhere) on a slope, a mask and a hardness field.
Fields fields(glm::ivec2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Fields f;
  f.domain = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 10.0 * (size.y - 1)}, size);
  auto in = std::make_shared<Heightfield>(f.domain), mask = std::make_shared<Heightfield>(f.domain),
       hard = std::make_shared<Heightfield>(f.domain);
  for (std::size_t k = 0; k < in->data.size(); ++k) {
    in->data[k] = 40.0f * u(rng) + 0.3f * static_cast<float>(k % static_cast<std::size_t>(size.x));
    mask->data[k] = 1.4f * u(rng) - 0.2f;  // clamped to 0..1 by the node
    hard->data[k] = u(rng);
  }
  f.in = in, f.mask = mask, f.hardness = hard;
  return f;
}

struct Maps {
  std::vector<float> out, erosion, deposition, flow;
};

std::unique_ptr<TileGraphAlgorithm> algorithm_of(const std::map<std::string, ParamValue>& set, const Domain& whole) {
  return test::algorithm_of("ThermalErosion", set, whole);
}

// The tiles' rounds as the driver runs them (messages through their bytes); `skip(tile, round)` drops that tile's
// answer of that round (a halo exchange left out: the mutation).
// `disagreements` counts the shared samples on which two tiles differ (none in a correct run).
Maps across_tiles(const TileGraphAlgorithm& algorithm, const Fields& f, glm::ivec2 counts, bool mask, bool hardness,
                  int* rounds_run, const std::function<bool(std::size_t, int)>& skip = {},
                  int* disagreements = nullptr) {
  const glm::ivec2 size = f.domain.resolution;
  auto tiles =
      test::start_tiles(algorithm, f.domain, counts, {f.in, mask ? f.mask : nullptr, hardness ? f.hardness : nullptr});
  const int rounds = test::run_rounds(algorithm, tiles, test::dropping(skip));
  if (rounds_run) *rounds_run = rounds;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Maps joined{std::vector<float>(f.in->data.size(), nan), std::vector<float>(f.in->data.size(), nan),
              std::vector<float>(f.in->data.size(), nan), std::vector<float>(f.in->data.size(), nan)};
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    std::vector<float>* into[] = {&joined.out, &joined.erosion, &joined.deposition, &joined.flow};
    for (std::size_t o = 0; o < 4; ++o) {
      const Heightfield& h = *std::get<HeightfieldPtr>(outputs[o]);
      test::join_tile_map((*into[o]), h, size.x, disagreements);
    }
  }
  return joined;
}

Maps whole_domain(const Fields& f, const ThermalParams& p, bool mask, bool hardness, int* iterations) {
  const ErosionMaps m = thermal_erosion(*f.in, p, mask ? f.mask.get() : nullptr, hardness ? f.hardness.get() : nullptr,
                                        nullptr, iterations);
  return {m.out->data, m.erosion->data, m.deposition->data, m.flow->data};
}

void expect_same(const Maps& tiled, const Maps& whole) {
  EXPECT_TRUE(same_bits(tiled.out, whole.out)) << "out";
  EXPECT_TRUE(same_bits(tiled.erosion, whole.erosion)) << "erosion";
  EXPECT_TRUE(same_bits(tiled.deposition, whole.deposition)) << "deposition";
  EXPECT_TRUE(same_bits(tiled.flow, whole.flow)) << "flow";
}

ThermalParams params(double travel_distance, double tolerance) {
  ThermalParams p;
  p.talus_angle = 30.0, p.strength = 0.5, p.travel_distance = travel_distance, p.tolerance = tolerance;
  return p;
}

// The registered algorithm (iterations per exchange from the tiles) and ones exchanging every 1, 3 and 8 iterations
// (halos of 2, 6 and 16 samples, wider than the smallest tiles below).
std::vector<std::pair<int, std::unique_ptr<TileGraphAlgorithm>>> algorithms(const ThermalParams& p,
                                                                            const Domain& whole) {
  std::vector<std::pair<int, std::unique_ptr<TileGraphAlgorithm>>> all;
  all.emplace_back(0, algorithm_of({{"talus_angle", p.talus_angle},
                                    {"strength", p.strength},
                                    {"travel_distance", p.travel_distance},
                                    {"tolerance", p.tolerance}},
                                   whole));
  for (const int k : {1, 3, 8}) all.emplace_back(k, thermal_across_tiles(p, whole, k));
  return all;
}

// The rounds of a run of `iterations` exchanging every k iterations (0: the default, 1 on these small tiles): the
// iterations per exchange, the first bands, then a round per block.
int expected_rounds(int k, int iterations) {
  const int block = k > 0 ? k : 1;
  return 2 + (iterations + block - 1) / block;
}

TEST(ThermalAcrossTiles, EveryTilingEqualsTheWholeDomainRunBitForBit) {
  const Fields f = fields({97, 81}, 3);
  // 30 degrees over 10 m: 12 iterations, every one moving material (tolerance 0).
  const ThermalParams p = params(60.0, 0.0);
  const auto all = algorithms(p, f.domain);
  for (const bool mask : {false, true})
    for (const bool hardness : {false, true}) {
      int iterations = 0;
      const Maps whole = whole_domain(f, p, mask, hardness, &iterations);
      ASSERT_EQ(iterations, 12);
      ASSERT_FALSE(same_bits(whole.out, f.in->data)) << "the run must move material";
      for (const auto& [k, algorithm] : all) {
        ASSERT_TRUE(algorithm);
        for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(4, 3),
                                        glm::ivec2(1, 4), glm::ivec2(7, 6)}) {
          SCOPED_TRACE("mask " + std::to_string(mask) + " hardness " + std::to_string(hardness) + " every " +
                       std::to_string(k) + " iterations, tiles " + test::tiles_text(counts));
          int rounds = 0;
          expect_same(across_tiles(*algorithm, f, counts, mask, hardness, &rounds), whole);
          EXPECT_EQ(rounds, expected_rounds(k, iterations));
        }
      }
    }
}

// Tiles of 2 and 3 samples: a halo sample then lies in a tile beyond the neighbor (up to 8 tiles away for a halo of
// 16 samples).
TEST(ThermalAcrossTiles, TilesNarrowerThanTheHaloTakeItFromTilesFurtherOn) {
  const Fields f = fields({41, 33}, 4);
  const ThermalParams p = params(40.0, 0.0);
  int iterations = 0;
  const Maps whole = whole_domain(f, p, true, true, &iterations);
  for (const auto& [k, algorithm] : algorithms(p, f.domain))
    for (const glm::ivec2 counts : {glm::ivec2(40, 1), glm::ivec2(20, 16), glm::ivec2(13, 32)}) {
      SCOPED_TRACE("every " + std::to_string(k) + " iterations, tiles " + test::tiles_text(counts));
      int rounds = 0;
      expect_same(across_tiles(*algorithm, f, counts, true, true, &rounds), whole);
    }
}

// A tolerance the run reaches before its iteration count: every tile stops after the same iteration as the
// whole-domain run, from the largest change over all tiles; a tile that ran past it within its block goes back.
TEST(ThermalAcrossTiles, AllTilesStopByToleranceWhereTheWholeDomainRunStops) {
  const Fields f = fields({97, 81}, 5);
  const ThermalParams p = params(500.0, 0.3);
  int iterations = 0;
  const Maps whole = whole_domain(f, p, true, false, &iterations);
  ASSERT_GT(iterations, 3);
  ASSERT_LT(iterations, 100) << "the run must stop early by tolerance";
  ASSERT_NE(iterations % 3, 0) << "the run must stop inside a block of 3";
  for (const auto& [k, algorithm] : algorithms(p, f.domain))
    for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(3, 2), glm::ivec2(7, 6)}) {
      SCOPED_TRACE("every " + std::to_string(k) + " iterations, tiles " + test::tiles_text(counts));
      int rounds = 0;
      expect_same(across_tiles(*algorithm, f, counts, true, false, &rounds), whole);
      EXPECT_EQ(rounds, expected_rounds(k, iterations));
    }
}

// The mutation check: one tile missing one halo exchange (its halo stays stale) changes the result, so the equality
// above depends on every exchange.
TEST(ThermalAcrossTiles, SkippingOneHaloExchangeBreaksTheEquality) {
  const Fields f = fields({97, 81}, 3);
  const ThermalParams p = params(60.0, 0.0);
  int iterations = 0;
  const Maps whole = whole_domain(f, p, false, false, &iterations);
  for (const int k : {1, 3}) {
    const auto algorithm = thermal_across_tiles(p, f.domain, k);
    int rounds = 0;
    expect_same(across_tiles(*algorithm, f, {3, 2}, false, false, &rounds), whole);
    for (const int round : {1, 3}) {
      SCOPED_TRACE("every " + std::to_string(k) + " iterations, skipped round " + std::to_string(round));
      int disagreements = 0;
      const Maps mutated = across_tiles(
          *algorithm, f, {3, 2}, false, false, &rounds,
          [&](std::size_t tile, int r) { return tile == 4 && r == round; }, &disagreements);
      EXPECT_FALSE(same_bits(mutated.out, whole.out));
      EXPECT_GT(disagreements, 0) << "the stale tile's border must differ from its neighbors'";
    }
  }
}

// What travels per exchange is the tiles' border bands, not the tiles; damaged bytes are refused.
TEST(ThermalAcrossTiles, BandsAreSmallAndTheirBytesAreChecked) {
  const Fields f = fields({97, 81}, 3);
  const auto algorithm = thermal_across_tiles(params(60.0, 0.0), f.domain, 3);
  auto tiles = test::start_tiles(*algorithm, f.domain, {2, 2}, {f.in, nullptr, nullptr});
  std::vector<std::string> messages;
  for (auto& tile : tiles) messages.push_back(tile->message(0));
  const auto blocks = algorithm->solve(0, messages);
  for (std::size_t t = 0; t < tiles.size(); ++t) tiles[t]->answer(0, blocks[t]);
  messages.clear();
  for (auto& tile : tiles) messages.push_back(tile->message(1));
  // Tile (0, 0) is 49 x 41 samples with neighbors right and below: 6 rows of 49 and 6 columns of 41 heights and rates.
  EXPECT_EQ(messages[0].size(), 28u + 2u * 4u * (6 * 49 + 6 * 41));
  test::expect_damaged_bytes_refused(*algorithm, tiles, 1, messages);
}

}  // namespace
}  // namespace orogen::erosion
