// graphs/seamscape.json, the SeamScape system (Ekman et al. 2016) as one graph, checked against what that
// report promised, on the graph's real outputs at a reduced resolution:
//  - tiles in global coordinates share their border samples bit for bit (its Appendix B), also with the
//    river network, a node that needs the whole domain, in the graph (--global-nodes whole, the default);
//  - the river tree descends to its outlets (heights never increase downstream, 0 at the outlets on the
//    border) and the carved terrain under each river follows the river's height.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/evaluator.h"
#include "graph/curves.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/points.h"
#include "nodes/io/heightfield_file.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

const fs::path kGraph = test::source_dir() / "graphs" / "seamscape.json";

test::ProcessResult orogen_cli(const std::vector<std::string>& args) {
  return test::run_process(test::cli_binary(), args);
}

// One channel of an EXR as rows south first (files store the northern row first).
struct Grid {
  int width = 0, height = 0;
  std::vector<double> v;
  double at(int i, int j) const {
    return v[static_cast<std::size_t>(j) * static_cast<std::size_t>(width) + static_cast<std::size_t>(i)];
  }
};

Grid read_grid(const fs::path& file) {
  const auto raw = read_height_raster(file);
  Grid g;
  g.width = raw.width;
  g.height = raw.height;
  g.v.resize(raw.values.size());
  for (int j = 0; j < raw.height; ++j)
    for (int i = 0; i < raw.width; ++i)
      g.v[static_cast<std::size_t>(j * raw.width + i)] =
          raw.values[static_cast<std::size_t>((raw.height - 1 - j) * raw.width + i)];
  return g;
}

std::string tile_file(int i, int j) {
  return "seamscape/height_x" + std::to_string(i) + "_y" + std::to_string(j) + ".exr";
}

// Builds the graph as 2 x 2 tiles at 129 x 129 samples (tiles of 65 x 65) and returns the four tiles'
// heights, [j][i]. `extra` is appended to the command of tile (1, 0) only (then built alone with --tile).
std::vector<std::vector<Grid>> tiled_heights(const fs::path& out, std::string* err,
                                             const std::vector<std::string>& extra = {}) {
  const std::vector<std::string> base = {"eval", kGraph.string(), "-o",  out.string(), "--resolution",
                                         "129",  "--tiles",       "2x2", "--quiet"};
  auto r = orogen_cli(base);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (err) *err = r.err;
  if (!extra.empty()) {
    auto args = base;
    args.insert(args.end(), {"--tile", "1,0"});
    args.insert(args.end(), extra.begin(), extra.end());
    auto one = orogen_cli(args);
    EXPECT_EQ(one.exit_code, 0) << one.err;
  }
  std::vector<std::vector<Grid>> tiles(2, std::vector<Grid>(2));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      tiles[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] = read_grid(out / tile_file(i, j));
  return tiles;
}

// Counts the shared border samples of neighbouring tiles that differ (bitwise: the values are compared as
// stored floats, so any difference counts).
int differing_border_samples(const std::vector<std::vector<Grid>>& t) {
  int differ = 0;
  const Grid &a = t[0][0], &b = t[0][1], &c = t[1][0], &d = t[1][1];
  for (int j = 0; j < a.height; ++j) {  // vertical seams: east column of the west tile = west column of the east
    differ += a.at(a.width - 1, j) != b.at(0, j);
    differ += c.at(c.width - 1, j) != d.at(0, j);
  }
  for (int i = 0; i < a.width; ++i) {  // horizontal seams: north row of the south tile = south row of the north
    differ += a.at(i, a.height - 1) != c.at(i, 0);
    differ += b.at(i, b.height - 1) != d.at(i, 0);
  }
  return differ;
}

TEST(SeedSeamscape, TiledBuildSharesItsBordersBitForBitAndEqualsTheWholeBuild) {
  const auto dir = test::scratch_dir("seed-seamscape-tiles");
  std::string warning;
  const auto tiles = tiled_heights(dir / "tiles", &warning);
  ASSERT_EQ(tiles[0][0].width, 65);
  ASSERT_EQ(tiles[0][0].height, 65);
  EXPECT_EQ(differing_border_samples(tiles), 0);
  // The nodes that need the whole domain and cannot be cut into the tiles are named: the terrain mesh (each tile
  // writes its own mesh and scene). The placement is not: ScatterRules draws every candidate from a hash of its
  // world cell, so each tile places exactly the untiled plants inside it. RiverNetwork grows over its own fixed
  // rectangle (min_corner, size), whatever the tile, so its curves are the same for every tile.
  EXPECT_NE(warning.find("'terrain_mesh'"), std::string::npos) << warning;
  EXPECT_EQ(warning.find("'plants'"), std::string::npos) << warning;
  // Each tile's terrain OBJ drapes its own tile of the color map.
  const std::string mtl = test::read_text(dir / "tiles" / "seamscape" / "terrain_x1_y0.mtl");
  EXPECT_NE(mtl.find("map_Kd color_x1_y0.png"), std::string::npos) << mtl;
  EXPECT_TRUE(fs::exists(dir / "tiles" / "seamscape" / "color_x1_y0.png"));

  // Every tile is its window of the untiled build, bit for bit (the tiles are in global coordinates).
  auto whole = orogen_cli({"eval", kGraph.string(), "-o", (dir / "whole").string(), "--resolution", "129", "--quiet"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const Grid full = read_grid(dir / "whole" / "seamscape" / "height.exr");
  ASSERT_EQ(full.width, 129);
  int differ = 0;
  for (int tj = 0; tj < 2; ++tj)
    for (int ti = 0; ti < 2; ++ti) {
      const Grid& t = tiles[static_cast<std::size_t>(tj)][static_cast<std::size_t>(ti)];
      for (int j = 0; j < t.height; ++j)
        for (int i = 0; i < t.width; ++i) differ += t.at(i, j) != full.at(64 * ti + i, 64 * tj + j);
    }
  EXPECT_EQ(differ, 0);
  // The terrain has relief and carved rivers: not a constant that would pass trivially.
  const auto [lo, hi] = std::minmax_element(full.v.begin(), full.v.end());
  EXPECT_GT(*hi - *lo, 100.0);
}

TEST(SeedSeamscape, TheBorderCheckSeesASeam) {
  // Control: tile (1, 0) rebuilt from another seed of the Perlin layer no longer joins its neighbours, and
  // the comparison above must find it.
  const auto dir = test::scratch_dir("seed-seamscape-tiles-seam");
  const auto tiles = tiled_heights(dir / "tiles", nullptr, {"--set", "hills.seed=12"});
  EXPECT_GT(differing_border_samples(tiles), 30);
}

struct Evaluated {
  Graph graph;
  EvalResult result;
};

Evaluated evaluate(int samples, std::vector<std::string> nodes) {
  const auto loaded = load_graph_file(kGraph);
  EXPECT_TRUE(loaded.ok()) << loaded.error_text();
  Evaluated e{*loaded.graph, {}};
  Evaluator evaluator;
  EvalRequest request;
  request.domain = Domain::from_extent({0, 0}, {4096, 4096}, {samples, samples});  // the file's extent
  request.nodes = std::move(nodes);
  e.result = evaluator.evaluate(e.graph, request);
  EXPECT_TRUE(e.result.ok());
  return e;
}

TEST(SeedSeamscape, RiversDescendToTheirOutletsAndTheCarvedTerrainFollowsThem) {
  const auto e = evaluate(257, {"rivers", "carved"});
  const auto rivers = std::get<CurvesPtr>(e.result.output("rivers", "out", e.graph));
  const auto carved = std::get<HeightfieldPtr>(e.result.output("carved", "out", e.graph));
  ASSERT_TRUE(rivers && carved);
  ASSERT_GT(rivers->size(), 20u);
  rivers->check_consistent();

  int roots = 0;
  double z_max = 0;
  double sum_dev = 0, max_dev = 0;
  std::size_t samples = 0;
  for (std::size_t c = 0; c < rivers->size(); ++c) {
    const Curve& curve = rivers->curves[c];
    ASSERT_GE(curve.points.size(), 2u);
    // Upstream to downstream: the height never increases.
    for (std::size_t k = 1; k < curve.points.size(); ++k)
      EXPECT_LE(curve.points[k].z, curve.points[k - 1].z) << "curve " << c << " climbs at vertex " << k;
    const glm::vec3 mouth = curve.points.back();
    if (curve.parent < 0) {
      // An outlet: height 0 on the border of the 4096 m square.
      ++roots;
      EXPECT_EQ(mouth.z, 0.0f) << "curve " << c;
      const float border = std::min({mouth.x, mouth.y, 4096.0f - mouth.x, 4096.0f - mouth.y});
      EXPECT_LT(border, 1.0f) << "outlet of curve " << c << " at " << mouth.x << ", " << mouth.y;
    } else {
      // A tributary joins its parent where the parent starts, at the same height: no step up downstream.
      const Curve& parent = rivers->curves[static_cast<std::size_t>(curve.parent)];
      const glm::vec3 join = parent.points.front();
      EXPECT_LT(std::hypot(mouth.x - join.x, mouth.y - join.y), 1e-2f) << "curve " << c;
      EXPECT_GE(mouth.z, join.z - 1e-4f) << "curve " << c;
    }
    for (const auto& p : curve.points) {
      z_max = std::max(z_max, static_cast<double>(p.z));
      // The carved terrain under the river: the river's height minus at most the channel depth, within the
      // blend of the neighbouring samples (16 m apart) toward the terrain around.
      const double depth = 0.15 * curve.width[static_cast<std::size_t>(&p - curve.points.data())];
      const double t = carved->sample_world(p.x, p.y);
      const double dev = t - (p.z - 0.5 * depth);
      sum_dev += std::abs(dev);
      max_dev = std::max(max_dev, std::abs(dev));
      ++samples;
    }
  }
  EXPECT_GE(roots, 1);
  EXPECT_GT(z_max, 50.0);  // the network climbs well above the outlets inland
  const double mean_dev = sum_dev / static_cast<double>(samples);
  EXPECT_LT(mean_dev, 1.0) << "max " << max_dev;
  EXPECT_LT(max_dev, 8.0);
}

TEST(SeedSeamscape, PlantsAndRocksStandOnTheCarvedTerrainByTheEcosystemRules) {
  const auto e = evaluate(129, {"placed", "carved"});
  const auto placed = std::get<PointsPtr>(e.result.output("placed", "out", e.graph));
  const auto carved = std::get<HeightfieldPtr>(e.result.output("carved", "out", e.graph));
  ASSERT_TRUE(placed && carved);
  ASSERT_GT(placed->size(), 1000u);
  std::vector<int> per_class(8, 0);
  for (std::size_t k = 0; k < placed->size(); ++k) {
    const glm::vec3 p = placed->position[k];
    // On the ground: the offset of the graph (-0.1 m, trunks slightly sunk), neither floating nor buried.
    EXPECT_NEAR(p.z, carved->sample_world(p.x, p.y) - 0.1f, 1e-3f) << "point " << k;
    const int c = placed->class_id[k];
    ASSERT_GE(c, 0);
    ASSERT_LT(c, 8);
    ++per_class[static_cast<std::size_t>(c)];
  }
  // Table 1's highland, marshland and plains each placed their plants (cherry, gold and green trees,
  // shrubs, grass, stones).
  for (int c : {0, 1, 2, 4, 5, 6}) EXPECT_GT(per_class[static_cast<std::size_t>(c)], 0) << "class " << c;
}

}  // namespace
}  // namespace orogen
