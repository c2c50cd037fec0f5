// The fill of the pit basins alone (nodes/hydrology/pit_basin_fill.h) against the whole-domain Priority-Flood+epsilon
// fill: on random terrains with wide flats and deep depressions, the cells outside every pit basin keep their height
// in the whole fill, and the basins filled from the samples around them are the whole fill there, bit for bit.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/pit_basin_fill.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

// Per cell: whether its D8 path ends in a pit (a cell other than the border with no lower neighbour).
std::vector<std::uint8_t> in_pit_basins(const FlowGrid& g, const std::vector<float>& z) {
  const D8Flow flow = d8_flow(g, z);
  const auto n = static_cast<std::int32_t>(z.size());
  std::vector<std::uint8_t> inside(z.size(), 0);
  for (std::int32_t c = 0; c < n; ++c) {
    std::int32_t x = c;
    while (flow.receiver[static_cast<std::size_t>(x)] != x) x = flow.receiver[static_cast<std::size_t>(x)];
    inside[static_cast<std::size_t>(c)] = !g.on_border(g.column(x), g.row(x));
  }
  return inside;
}

TEST(PitBasinFill, EqualsTheWholeFillOnThePitBasinsAndLeavesTheRest) {
  for (const int levels : {0, 3, 12})
    for (const unsigned seed : {1u, 2u, 3u}) {
      SCOPED_TRACE("levels " + std::to_string(levels) + " seed " + std::to_string(seed));
      const test::Terrain t = test::terrain({53, 41}, seed, levels);
      const FlowGrid g(t.size.x, t.size.y, 10.0, 10.0);
      std::vector<float> filled = t.z;
      fill_depressions(g, filled, FlatMode::Epsilon);
      const auto inside = in_pit_basins(g, t.z);
      std::vector<BasinSample> samples;
      std::size_t basin_cells = 0;
      for (int j = 0; j < t.size.y; ++j)
        for (int i = 0; i < t.size.x; ++i) {
          const auto c = static_cast<std::size_t>(g.index(i, j));
          if (!inside[c]) {
            EXPECT_EQ(filled[c], t.z[c]) << "outside the pit basins the fill keeps the height";
            continue;
          }
          ++basin_cells;
          samples.push_back({static_cast<std::int64_t>(c), t.z[c], true});
          for (int k = 0; k < 8; ++k) {
            const int x = i + kDi[k], y = j + kDj[k];
            if (g.inside(x, y)) {
              const auto n = static_cast<std::size_t>(g.index(x, y));
              samples.push_back({static_cast<std::int64_t>(n), t.z[n], inside[n] != 0});
            }
          }
        }
      ASSERT_GT(basin_cells, 100u) << "the terrain must have pit basins";
      const auto basin_fill = fill_pit_basins(samples, t.size);
      ASSERT_EQ(basin_fill.size(), basin_cells);
      std::size_t raised = 0;
      for (const auto& [sample, height] : basin_fill) {
        EXPECT_EQ(height, filled[static_cast<std::size_t>(sample)]) << "sample " << sample;
        raised += height > t.z[static_cast<std::size_t>(sample)];
      }
      EXPECT_GT(raised, 10u) << "the basins must hold depressions to fill";
    }
}

TEST(PitBasinFill, RefusesAMissingNeighborAndDisagreeingCopies) {
  const glm::ivec2 size{5, 5};
  std::vector<BasinSample> samples = {{12, 1.0f, true}};
  EXPECT_THROW(fill_pit_basins(samples, size), std::invalid_argument);
  for (const std::int64_t n : {6, 7, 8, 11, 13, 16, 17, 18}) samples.push_back({n, 5.0f, false});
  EXPECT_NO_THROW(fill_pit_basins(samples, size));
  EXPECT_EQ(fill_pit_basins(samples, size).front().second, std::nextafter(5.0f, 6.0f))
      << "a one-cell pit fills to one ulp above its rim";
  samples.push_back({6, 4.0f, false});
  EXPECT_THROW(fill_pit_basins(samples, size), std::invalid_argument);
  EXPECT_THROW(fill_pit_basins({{25, 1.0f, false}}, size), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
