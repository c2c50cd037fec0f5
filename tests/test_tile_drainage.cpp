// DrainageMetrics across tiles through its registered tile-graph algorithm (nodes/hydrology/drainage_across_tiles.cpp):
// depressions joined and kept as lakes across tiles, pits through the ring of the input, D8 counts, Strahler orders
// and main-stream lengths through the perimeters, then the channel cells joined into one network whose figures are
// computed in the whole-domain order. Every tile must get the whole-domain node's report, character for character,
// and its window of the Strahler map, on every tiling (tiles two samples wide included).
#include <gtest/gtest.h>

#include "nodes/hydrology/drainage_metrics.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::same_bits;
using test::Terrain;
using test::terrain;

struct Tiled {
  std::vector<std::string> reports;  // per tile
  std::vector<float> order;          // joined
};

Tiled run_metrics(const TileGraphAlgorithm& algorithm, const Terrain& t, glm::ivec2 counts) {
  auto tiles = test::start_tiles(algorithm, t, counts);
  test::run_rounds(algorithm, tiles);
  Tiled out;
  out.order.assign(t.z.size(), std::numeric_limits<float>::quiet_NaN());
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    out.reports.push_back(std::get<ReportPtr>(outputs.at(1))->json);
    test::join_tile_map(out.order, *std::get<HeightfieldPtr>(outputs.at(0)), t.size.x, nullptr);
  }
  return out;
}

TEST(DrainageMetricsAcrossTiles, EveryTileGetsTheWholeDomainReportAndItsWindowOfTheOrders) {
  int highest_order = 0;
  std::size_t most_lakes = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (const double threshold : {800.0, 5000.0}) {
        SCOPED_TRACE(test::tiles_text(size) + " levels " + std::to_string(levels) + " threshold " +
                     std::to_string(threshold));
        const Terrain t = terrain(size, 51, levels);
        const Domain whole = domain_of(t);
        // Lakes from 0.5 m deep and 4 cells: some kept, some not, some across tiles.
        const LakeThreshold lake{0.5, 400.0};
        const DrainageReport r = drainage_metrics(test::heights_of(t), threshold, nullptr, lake);
        highest_order = std::max(highest_order, r.network.max_order);
        most_lakes = std::max(most_lakes, r.lakes);
        std::vector<float> order(r.network.order.begin(), r.network.order.end());
        const std::string report = r.json();
        const auto algorithm = algorithm_of(
            "DrainageMetrics", {{"threshold", threshold}, {"lake_depth", 0.5}, {"lake_area", 400.0}}, whole);
        ASSERT_TRUE(algorithm);
        for (const glm::ivec2 counts : test::kTilings) {
          if (counts.x >= 40 && size.x > 41) continue;  // tiles two samples wide: on the small terrain only
          SCOPED_TRACE("tiles " + test::tiles_text(counts));
          const Tiled tiled = run_metrics(*algorithm, t, counts);
          for (const std::string& text : tiled.reports) ASSERT_EQ(text, report);
          EXPECT_TRUE(same_bits(tiled.order, order)) << "Strahler map";
        }
      }
  EXPECT_GE(highest_order, 3) << "the networks must branch";
  EXPECT_GE(most_lakes, 2u) << "some depressions must be kept as lakes";
}

TEST(DrainageMetricsAcrossTiles, RefusesMalformedMessages) {
  const Terrain t = terrain({9, 9}, 3, 0);
  const auto algorithm = algorithm_of("DrainageMetrics", {}, domain_of(t));
  ASSERT_TRUE(algorithm);
  EXPECT_THROW(algorithm->start({}), std::invalid_argument);
  EXPECT_THROW(algorithm->solve(0, {std::string("\x0b")}), std::invalid_argument);  // no such phase
  EXPECT_THROW(algorithm->solve(0, {std::string("\x01")}), std::invalid_argument);  // truncated depressions
}

}  // namespace
}  // namespace orogen::hydrology
