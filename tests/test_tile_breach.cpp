// Carving depressions (FillDepressions mode 'carve', breach_depressions) on the whole domain and across tiles
// (nodes/hydrology/breach_rule.h, tile_breach.h, carve_across_tiles.cpp). The whole-domain carve must equal channels
// cut pit by pit down the tree, in any order of the pits, and leave every cell drained; across tiles, every tiling must
// give the whole-domain node's outputs bit for bit, lakes kept by max_depth included, down to tiles two samples wide.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/heightfield.h"
#include "nodes/hydrology/depressions.h"
#include "nodes/hydrology/flow_routing.h"
#include "support/depression_terrain.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::same_bits;
using test::Terrain;
using test::terrain;

float lower_by_an_ulp(float v) { return std::nextafter(v, -std::numeric_limits<float>::infinity()); }

// The carve as its definition says, one pit at a time in the given order: the epsilon surface's steepest-descent
// receivers (a plain per-cell search), and from each pit a channel lowered down them, cell by cell, until a cell no
// higher than the channel (one ulp lower per cell with epsilon).
std::vector<float> channels_pit_by_pit(const FlowGrid& g, const std::vector<float>& z, bool epsilon, bool reverse) {
  std::vector<float> e = z;
  fill_depressions(g, e, FlatMode::Epsilon);
  std::vector<std::int32_t> receiver(g.size());
  std::vector<std::int32_t> pits;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      receiver[static_cast<std::size_t>(c)] = c;
      if (g.on_border(i, j)) continue;
      double best = 0.0;
      bool lower = false;
      for (int k = 0; k < 8; ++k) {
        const std::int32_t n = g.index(i + kDi[k], j + kDj[k]);
        const double s = (static_cast<double>(e[c]) - e[n]) / std::hypot(kDi[k] * g.dx, kDj[k] * g.dy);
        if (s > best) best = s, receiver[static_cast<std::size_t>(c)] = n;
        lower = lower || z[n] < z[c];
      }
      if (!lower) pits.push_back(c);
    }
  if (reverse) std::reverse(pits.begin(), pits.end());
  std::vector<float> out = z;
  for (const std::int32_t pit : pits) {
    float target = epsilon ? lower_by_an_ulp(z[pit]) : z[pit];
    for (std::int32_t b = receiver[pit]; out[b] > target; b = receiver[b]) {
      out[b] = target;
      target = epsilon ? lower_by_an_ulp(target) : target;
      if (receiver[b] == b) break;  // an outlet
    }
  }
  return out;
}

TEST(Breach, EqualsChannelsCutPitByPitInEitherOrder) {
  int carved_cells = 0;
  for (const bool epsilon : {true, false})
    for (unsigned seed : {3u, 4u})
      for (int levels : {0, 3}) {
        const Terrain t = terrain({61, 47}, seed, levels);
        const FlowGrid g(t.size.x, t.size.y, 10.0, 10.0);
        std::vector<float> out = t.z;
        breach_depressions(g, out, epsilon ? FlatMode::Epsilon : FlatMode::Flat);
        SCOPED_TRACE(std::string(epsilon ? "epsilon" : "flat") + " seed " + std::to_string(seed) + " levels " +
                     std::to_string(levels));
        EXPECT_TRUE(same_bits(out, channels_pit_by_pit(g, t.z, epsilon, false)));
        EXPECT_TRUE(same_bits(out, channels_pit_by_pit(g, t.z, epsilon, true)));
        for (std::size_t c = 0; c < out.size(); ++c) carved_cells += out[c] != t.z[c];
      }
  EXPECT_GT(carved_cells, 200);
}

// Flat: no depression is left (filling changes nothing). Epsilon: every cell but the border has a strictly lower
// neighbour, so the result is its own epsilon fill (FillDepressions no longer fills after carving). Nothing rises.
TEST(Breach, LeavesEveryCellDrainedAndNothingRaised) {
  for (const bool epsilon : {true, false})
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      const FlowGrid g(73, 58, 4.0, 4.0);
      const std::vector<float> z = test::depression_terrain(g, seed);
      std::vector<float> out = z;
      breach_depressions(g, out, epsilon ? FlatMode::Epsilon : FlatMode::Flat);
      for (std::size_t c = 0; c < z.size(); ++c) ASSERT_LE(out[c], z[c]);
      std::vector<float> refilled = out;
      fill_depressions(g, refilled, epsilon ? FlatMode::Epsilon : FlatMode::Flat);
      EXPECT_TRUE(same_bits(refilled, out)) << (epsilon ? "epsilon" : "flat") << " seed " << seed;
      if (!epsilon) continue;
      for (int j = 1; j < g.ny - 1; ++j)
        for (int i = 1; i < g.nx - 1; ++i) {
          bool lower = false;
          for (int k = 0; k < 8; ++k) lower |= out[g.index(i + kDi[k], j + kDj[k])] < out[g.index(i, j)];
          ASSERT_TRUE(lower) << i << "," << j;
        }
    }
}

struct NodeOutputs {
  std::vector<float> out, depth, id;
};

NodeOutputs carve_whole(const Terrain& t, bool epsilon, double max_depth) {
  Heightfield ground(domain_of(t));
  ground.data = t.z;
  const FillResult r = fill_depressions(ground, FillParams{true, epsilon, max_depth, true});
  return {r.out->data, r.depth->data, r.lake_id->data};
}

NodeOutputs carve_tiled(const Terrain& t, bool epsilon, double max_depth, glm::ivec2 counts, int* rounds) {
  const auto algorithm = algorithm_of(
      "FillDepressions",
      {{"mode", std::string("carve")}, {"flats", std::string(epsilon ? "epsilon" : "flat")}, {"max_depth", max_depth}},
      domain_of(t));
  EXPECT_TRUE(algorithm);
  if (!algorithm) return {};
  auto joined = test::run_across_tiles(*algorithm, t, counts, 1, rounds);
  EXPECT_EQ(joined.size(), 3u);
  joined.resize(3);
  return {std::move(joined[0]), std::move(joined[1]), std::move(joined[2])};
}

void expect_same(const NodeOutputs& tiled, const NodeOutputs& whole) {
  EXPECT_TRUE(same_bits(tiled.out, whole.out)) << "out";
  EXPECT_TRUE(same_bits(tiled.depth, whole.depth)) << "water_depth";
  EXPECT_TRUE(same_bits(tiled.id, whole.id)) << "lake_id";
}

TEST(CarveAcrossTiles, EqualsTheWholeDomainNodeOnEveryTiling) {
  const std::vector<glm::ivec2> tilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}, {20, 16}};
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (const bool epsilon : {true, false})
        for (const double max_depth : {0.0, 3.0}) {
          const Terrain t = terrain(size, 7, levels);
          const NodeOutputs whole = carve_whole(t, epsilon, max_depth);
          int carved = 0;
          for (std::size_t c = 0; c < t.z.size(); ++c) carved += whole.out[c] < t.z[c];
          const std::set<float> ids(whole.id.begin(), whole.id.end());
          ASSERT_GT(carved, 10);
          if (max_depth > 0) {
            ASSERT_GT(ids.size(), 2u) << "some shallow lakes must be kept";
          }
          for (const glm::ivec2 counts : tilings) {
            SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " levels " + std::to_string(levels) +
                         (epsilon ? " epsilon" : " flat") + " max_depth " + std::to_string(max_depth) + " tiles " +
                         std::to_string(counts.x) + "x" + std::to_string(counts.y));
            int rounds = 0;
            expect_same(carve_tiled(t, epsilon, max_depth, counts, &rounds), whole);
          }
        }
}

// A pit near the east edge of a valley that rises eastwards: its channel runs down the valley to the west border,
// through all four tiles of a 4x1 tiling, so each tile learns its part of the channel from the tile before it.
TEST(CarveAcrossTiles, AChannelThroughFourTilesTakesARoundPerTile) {
  Terrain t{{65, 17}, {}};
  for (int j = 0; j < 17; ++j)
    for (int i = 0; i < 65; ++i)
      t.z.push_back(10.0f + 0.5f * static_cast<float>(i) + 0.2f * static_cast<float>(std::abs(j - 8)));
  t.z[8 * 65 + 60] = 0.0f;
  for (const bool epsilon : {true, false}) {
    const NodeOutputs whole = carve_whole(t, epsilon, 0.0);
    // The channel: the pit's row from the pit to the west border, at most the pit's height, falling westwards.
    for (int i = 0; i < 60; ++i) {
      const float here = whole.out[static_cast<std::size_t>(8 * 65 + i)],
                  east = whole.out[static_cast<std::size_t>(8 * 65 + i + 1)];
      ASSERT_LE(here, 0.0f) << i;
      if (epsilon) {
        ASSERT_LT(here, east) << i;
      }
    }
    int rounds_1 = 0, rounds_4 = 0;
    expect_same(carve_tiled(t, epsilon, 0.0, {1, 1}, &rounds_1), whole);
    expect_same(carve_tiled(t, epsilon, 0.0, {4, 1}, &rounds_4), whole);
    EXPECT_GE(rounds_4 - rounds_1, 3) << "the channel's values cross three borders, a round each";
  }
}

}  // namespace
}  // namespace orogen::hydrology
