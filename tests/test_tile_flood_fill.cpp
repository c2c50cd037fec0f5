// FloodFill across tiles through its registered tile-graph algorithm (nodes/hydrology/flood_fill_across_tiles.cpp):
// the spill level at the seed from the tiles' spill graphs (Barnes 2016), then the components of ground below the
// level joined through the samples tiles share. Put together, the tiles' outputs must equal the whole-domain node's
// bit for bit on every tiling (tiles two samples wide included), for seeds in lakes that span several tiles and
// their corners, in both level modes.
#include <set>

#include <gtest/gtest.h>

#include "nodes/hydrology/depressions.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::same_bits;
using test::Terrain;
using test::terrain;

// The tiles of `counts` holding sample (i, j) (several on a shared sample).
std::set<int> tiles_holding(int i, int j, glm::ivec2 size, glm::ivec2 counts) {
  std::set<int> out;
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti)
      if (test::edge(ti, size.x, counts.x) <= i && i <= test::edge(ti + 1, size.x, counts.x) &&
          test::edge(tj, size.y, counts.y) <= j && j <= test::edge(tj + 1, size.y, counts.y))
        out.insert(tj * counts.x + ti);
  return out;
}

TEST(FloodFillAcrossTiles, EqualsTheWholeDomainNodeOnEveryTiling) {
  int most_tiles_flooded = 0;
  bool corner_flooded = false;
  int cases_flooded = 0, cases = 0, bowls_filled = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2}) {
      const Terrain t = terrain(size, 21, levels);
      const Domain whole = domain_of(t);
      const Heightfield ground = test::heights_of(t);
      // Seeds: the bowl in the middle, the trench along the lower quarter, a corner of the domain, and off the
      // domain (clamped to its nearest sample).
      const std::vector<glm::dvec2> seeds = {whole.position(size.x / 2, size.y / 2),
                                             whole.position(size.x / 3, size.y / 4),
                                             whole.position(size.x - 1, 0),
                                             {-1e4, 5e5}};
      for (const glm::dvec2 seed : seeds)
        for (const bool spill : {true, false})
          for (const double level : spill ? std::vector<double>{0.0} : std::vector<double>{-6.0, 3.0}) {
            SCOPED_TRACE(test::tiles_text(size) + " levels " + std::to_string(levels) + " seed " +
                         std::to_string(seed.x) + "," + std::to_string(seed.y) +
                         (spill ? " spill" : " level " + std::to_string(level)));
            const FloodFillResult r = flood_fill(ground, {seed, spill, level});
            const auto algorithm = algorithm_of(
                "FloodFill",
                {{"position", seed}, {"level_mode", std::string(spill ? "spill" : "level")}, {"level", level}}, whole);
            ASSERT_TRUE(algorithm);
            ++cases;
            int flooded = 0;
            for (const float m : r.mask->data) flooded += m > 0.0f;
            cases_flooded += flooded > 1;
            bowls_filled += spill && seed == seeds[0] && flooded > 1;
            for (const glm::ivec2 counts : test::kTilings) {
              SCOPED_TRACE("tiles " + test::tiles_text(counts));
              int rounds = 0;
              const auto tiled = test::run_across_tiles(*algorithm, t, counts, 1, &rounds);
              EXPECT_EQ(rounds, spill ? 2 : 1);
              ASSERT_EQ(tiled.size(), 3u);
              EXPECT_TRUE(same_bits(tiled[0], r.out->data)) << "out";
              EXPECT_TRUE(same_bits(tiled[1], r.depth->data)) << "water_depth";
              EXPECT_TRUE(same_bits(tiled[2], r.mask->data)) << "lake_mask";
              if (counts.x * counts.y < 4) continue;
              std::set<int> tiles;
              for (int j = 0; j < size.y; ++j)
                for (int i = 0; i < size.x; ++i) {
                  if (!(r.mask->data[static_cast<std::size_t>(j * size.x + i)] > 0.0f)) continue;
                  const auto holding = tiles_holding(i, j, size, counts);
                  tiles.insert(holding.begin(), holding.end());
                  corner_flooded = corner_flooded || holding.size() == 4;
                }
              most_tiles_flooded = std::max(most_tiles_flooded, static_cast<int>(tiles.size()));
            }
          }
    }
  EXPECT_EQ(bowls_filled, 4) << "the bowl fills to its spill level on every terrain";
  EXPECT_GE(cases_flooded, cases / 3) << "seeds on the domain's border flood nothing with the spill level";
  EXPECT_GE(most_tiles_flooded, 6) << "some lake must span several tiles";
  EXPECT_TRUE(corner_flooded) << "some lake must cover a sample four tiles share";
}

// A lake that leaves a tile and comes back into it (a U through the neighbor): its two arms are separate components
// of the tile, joined only through the other tile.
TEST(FloodFillAcrossTiles, JoinsALakeThroughAnotherTile) {
  Terrain t{{21, 11}, std::vector<float>(21 * 11, 10.0f)};
  auto at = [&](int i, int j) -> float& { return t.z[static_cast<std::size_t>(j * 21 + i)]; };
  // Two arms along j = 3 and j = 7 from i = 2 to 14, joined at i = 14: in 2 x 1 tiles (the border at i = 10) the
  // left tile holds the arms apart.
  for (int i = 2; i <= 14; ++i) at(i, 3) = at(i, 7) = 0.0f;
  for (int j = 3; j <= 7; ++j) at(14, j) = 0.0f;
  const Domain whole = domain_of(t);
  const glm::dvec2 seed = whole.position(2, 3);
  const FloodFillResult r = flood_fill(test::heights_of(t), {seed, false, 5.0});
  const auto algorithm =
      algorithm_of("FloodFill", {{"position", seed}, {"level_mode", std::string("level")}, {"level", 5.0}}, whole);
  ASSERT_TRUE(algorithm);
  EXPECT_GT(r.mask->data[static_cast<std::size_t>(7 * 21 + 2)], 0.0f) << "the other arm is flooded";
  for (const glm::ivec2 counts : {glm::ivec2(2, 1), glm::ivec2(2, 2), glm::ivec2(20, 10)}) {
    const auto tiled = test::run_across_tiles(*algorithm, t, counts);
    EXPECT_TRUE(same_bits(tiled[2], r.mask->data)) << counts.x << "x" << counts.y;
  }
}

TEST(FloodFillAcrossTiles, RefusesMalformedMessages) {
  const Terrain t = terrain({9, 9}, 3, 0);
  const Domain whole = domain_of(t);
  const auto algorithm = algorithm_of("FloodFill", {{"level_mode", std::string("level")}, {"level", 1.0}}, whole);
  ASSERT_TRUE(algorithm);
  EXPECT_THROW(algorithm->solve(0, {std::string("\x01")}), std::invalid_argument);
  EXPECT_THROW(algorithm->solve(0, {}), std::invalid_argument);  // no tile holds the seed
  EXPECT_THROW(algorithm->start({}), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
