// End-to-end tests of tiled builds: `orogen eval --tiles NxM [--tile I,J]`, `--origin` and `--size`.
// Tiles share their border samples (SeamScape, Appendix B); with point-wise and local nodes every tile equals
// its window of the untiled build bit for bit, and nodes that need the whole domain are named in a warning.
#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <glm/vec2.hpp>

#include "nodes/io/heightfield_file.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

ProcessResult orogen(const std::vector<std::string>& args) { return run_process(cli_binary(), args); }

// Noise and local filters only: FBM, a direct blur, a wide (decimated) blur, slope, curvature and normals,
// on a domain whose 101 x 81 samples do not divide evenly into 3 x 2 tiles.
const char* kLocalGraph = R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [1000, 800], "resolution": [101, 81] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 300, "octaves": 6, "seed": 3, "amplitude": 120 } },
    { "id": "cells", "type": "Worley", "params": { "feature_size": 150, "seed": 9 } },
    { "id": "smooth", "type": "Blur", "inputs": { "in": "noise.out" }, "params": { "sigma": 25 } },
    { "id": "wide", "type": "Blur", "inputs": { "in": "cells.out" }, "params": { "sigma": 180 } },
    { "id": "slope", "type": "Slope", "inputs": { "in": "smooth.out" } },
    { "id": "bumps", "type": "Add", "inputs": { "a": "smooth.out", "b": "wide.out" } },
    { "id": "mix", "type": "Add", "inputs": { "a": "bumps.out", "b": "slope.out" } },
    { "id": "curv", "type": "Curvature", "inputs": { "in": "mix.out" } },
    { "id": "save_height", "type": "WriteHeightfield", "inputs": { "in": "mix.out" },
      "params": { "path": "height.exr" } },
    { "id": "save_curv", "type": "WriteHeightfield", "inputs": { "in": "curv.out" },
      "params": { "path": "curvature.tif" } },
    { "id": "normals", "type": "Normals", "inputs": { "in": "bumps.out" } },
    { "id": "save_normals", "type": "WriteImage", "inputs": { "in": "normals.out" },
      "params": { "path": "maps/normals.exr" } }
  ]
})";

// A local chain plus nodes that need the whole domain (a normalization and a depression fill).
// 'warped' is a node that still needs the whole domain (a warp by fields reads anywhere).
const char* kGlobalGraph = R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [640, 640], "resolution": [65, 65] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 200, "seed": 5, "amplitude": 50 } },
    { "id": "stretch", "type": "Normalize", "inputs": { "in": "noise.out" } },
    { "id": "warped", "type": "Warp", "inputs": { "in": "noise.out", "dx": "noise.out", "dy": "noise.out" } },
    { "id": "smooth", "type": "Blur", "inputs": { "in": "noise.out" }, "params": { "sigma": 20 } },
    { "id": "save_stretch", "type": "WriteHeightfield", "inputs": { "in": "stretch.out" },
      "params": { "path": "stretch.exr" } },
    { "id": "save_warped", "type": "WriteHeightfield", "inputs": { "in": "warped.out" },
      "params": { "path": "warped.exr" } },
    { "id": "save_smooth", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "smooth.png" } },
    { "id": "save_smooth_exr", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "smooth.exr" } }
  ]
})";

struct Raster {
  int width = 0, height = 0;
  std::vector<std::vector<float>> channels;  // row 0 = the southern row (domain row 0)
  float at(int c, int i, int j) const {
    return channels[static_cast<std::size_t>(c)][static_cast<std::size_t>(j * width + i)];
  }
};

Raster read_raster(const fs::path& file, int channel_count = 1) {
  Raster r;
  for (int c = 0; c < channel_count; ++c) {
    const auto raw = read_height_raster(file, c);
    r.width = raw.width;
    r.height = raw.height;
    std::vector<float> v(raw.values.size());
    for (int j = 0; j < raw.height; ++j)  // files store the northern row first
      for (int i = 0; i < raw.width; ++i)
        v[static_cast<std::size_t>(j * raw.width + i)] =
            static_cast<float>(raw.values[static_cast<std::size_t>((raw.height - 1 - j) * raw.width + i)]);
    r.channels.push_back(std::move(v));
  }
  return r;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Tile boundaries of SeamScape Appendix B on a lattice: tile I of N over W samples starts at floor(I (W-1) / N).
int edge(int t, int samples, int tiles) { return t * (samples - 1) / tiles; }

struct LocalBuild {
  fs::path dir, full, tiled;
};

// The local graph built once whole and once as 3 x 2 tiles (shared by several tests).
const LocalBuild& local_build() {
  static const LocalBuild build = [] {
    LocalBuild b;
    b.dir = scratch_dir("tiles-local");
    b.full = b.dir / "full";
    b.tiled = b.dir / "tiled";
    write_text(b.dir / "g.json", kLocalGraph);
    auto full = orogen({"eval", (b.dir / "g.json").string(), "-o", b.full.string(), "--quiet"});
    EXPECT_EQ(full.exit_code, 0) << full.err;
    auto tiled = orogen({"eval", (b.dir / "g.json").string(), "-o", b.tiled.string(), "--tiles", "3x2", "--stats",
                         (b.dir / "stats.json").string()});
    EXPECT_EQ(tiled.exit_code, 0) << tiled.err;
    EXPECT_EQ(tiled.err.find("warning"), std::string::npos) << "a local graph must tile without warnings:\n"
                                                            << tiled.err;
    return b;
  }();
  return build;
}

std::string tile_name(const std::string& stem, int i, int j, const std::string& ext) {
  return stem + "_x" + std::to_string(i) + "_y" + std::to_string(j) + ext;
}

// ---- argument errors ------------------------------------------------------------------------------------

TEST(CliTiles, BadArgumentsAreRefusedWithClearErrorsAndWriteNothing) {
  const auto dir = scratch_dir("tiles-args");
  write_text(dir / "g.json", kLocalGraph);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--tiles", "0x3"}, "tile counts must be from 1 to 4096"},
      {{"--tiles", "3x-1"}, "tile counts must be from 1 to 4096"},
      {{"--tiles", "3"}, "expected NxM"},
      {{"--tiles", "axb"}, "expected NxM"},
      {{"--tiles", "2x2x2"}, "expected NxM"},
      {{"--tiles", "3x2", "--tile", "3,0"}, "outside the 3x2 tiles"},
      {{"--tiles", "3x2", "--tile", "0,2"}, "outside the 3x2 tiles"},
      {{"--tiles", "3x2", "--tile", "-1,0"}, "outside the 3x2 tiles"},
      {{"--tiles", "3x2", "--tile", "1"}, "expected I,J"},
      {{"--tile", "1,1"}, "needs --tiles"},
      {{"--tiles", "101x2"}, "fewer than 2 samples"},  // 101 samples allow at most 100 tiles along x
      {{"--tiles", "6x2", "--resolution", "6x5"}, "fewer than 2 samples"},
      {{"--tiles", "2x2", "--tiles", "3x3"}, "--tiles"},  // given twice
      {{"--tiles", "2x2", "--tile", "0,0", "--tile", "1,1"}, "--tile"},
      {{"--global-nodes", "tile"}, "--global-nodes tile needs --tiles"},
      {{"--tiles", "2x2", "--global-nodes", "some"}, "--global-nodes 'some': expected 'whole' or 'tile'"},
      {{"--origin", "1"}, "--origin '1': expected two numbers"},
      {{"--origin", "1,nan"}, "--origin '1,nan': expected two numbers"},
      {{"--size", "0,400"}, "greater than 0 m"},
      {{"--size", "-5,400"}, "greater than 0 m"},
      {{"--size", "1e13,400"}, "expected two numbers"},
  };
  for (const auto& [extra, message] : cases) {
    std::vector<std::string> args = {"eval", (dir / "g.json").string(), "-o", (dir / "out").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    std::string joined;
    for (const auto& a : extra) joined += a + " ";
    SCOPED_TRACE(joined);
    const auto r = orogen(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "height.exr"));
    EXPECT_FALSE(fs::exists(dir / "out" / "height_x0_y0.exr"));
  }
}

// ---- file names -----------------------------------------------------------------------------------------

TEST(CliTiles, EveryTileWritesItsOwnSuffixedFilesAndStats) {
  const auto& b = local_build();
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(fs::exists(b.tiled / tile_name("height", i, j, ".exr")));
      EXPECT_TRUE(fs::exists(b.tiled / tile_name("curvature", i, j, ".tif")));
      EXPECT_TRUE(fs::exists(b.tiled / "maps" / tile_name("normals", i, j, ".exr")));
      const auto stats_file = b.dir / tile_name("stats", i, j, ".json");
      ASSERT_TRUE(fs::exists(stats_file));
      const auto s = nlohmann::json::parse(read_text(stats_file));
      EXPECT_TRUE(s["ok"].get<bool>());
      EXPECT_EQ(s["tile"]["index"], nlohmann::json::array({i, j}));
      EXPECT_EQ(s["tile"]["tiles"], nlohmann::json::array({3, 2}));
      EXPECT_EQ(s["tile"]["first_sample"], nlohmann::json::array({edge(i, 101, 3), edge(j, 81, 2)}));
      EXPECT_EQ(s["tile"]["resolution"], nlohmann::json::array({edge(i + 1, 101, 3) - edge(i, 101, 3) + 1,
                                                                edge(j + 1, 81, 2) - edge(j, 81, 2) + 1}));
      EXPECT_EQ(s["nodes"]["save_height"]["status"], "computed");
    }
  // Nothing else: no unsuffixed file, no tile beyond the grid, no stats without a suffix.
  EXPECT_FALSE(fs::exists(b.tiled / "height.exr"));
  EXPECT_FALSE(fs::exists(b.tiled / tile_name("height", 3, 0, ".exr")));
  EXPECT_FALSE(fs::exists(b.dir / "stats.json"));
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(b.tiled)) files += e.is_regular_file();
  EXPECT_EQ(files, 19u);  // 3 x 2 tiles of 3 rasters, their 6 stats files, the mosaic of curvature.tif
}

TEST(CliTiles, OneTileBuildsOnlyThatTileAndEqualsItInTheFullTiling) {
  const auto& b = local_build();
  const auto out = scratch_dir("tiles-one");
  auto r = orogen({"eval", (b.dir / "g.json").string(), "-o", out.string(), "--tiles", "3x2", "--tile", "2,1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("tile 2,1 (1/1)"), std::string::npos) << r.err;  // progress names the tile
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(out))
    if (e.is_regular_file()) names.push_back(fs::relative(e.path(), out).generic_string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"curvature_x2_y1.tif", "height_x2_y1.exr", "maps/normals_x2_y1.exr"}));
  const auto one = read_raster(out / "height_x2_y1.exr"), all = read_raster(b.tiled / "height_x2_y1.exr");
  ASSERT_EQ(one.channels[0].size(), all.channels[0].size());
  EXPECT_EQ(std::memcmp(one.channels[0].data(), all.channels[0].data(), one.channels[0].size() * sizeof(float)), 0);
}

// ---- bit identity ---------------------------------------------------------------------------------------

struct Output {
  std::string stem, ext;
  int channels;
};
const std::vector<Output> kOutputs = {{"height", ".exr", 1}, {"curvature", ".tif", 1}, {"maps/normals", ".exr", 3}};

TEST(CliTiles, NeighbouringTilesShareBitIdenticalBorders) {
  const auto& b = local_build();
  for (const auto& o : kOutputs) {
    SCOPED_TRACE(o.stem);
    std::map<std::pair<int, int>, Raster> tiles;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) tiles[{i, j}] = read_raster(b.tiled / tile_name(o.stem, i, j, o.ext), o.channels);
    std::size_t compared = 0;
    for (int c = 0; c < o.channels; ++c)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
          const Raster& t = tiles[{i, j}];
          if (i + 1 < 3) {  // the east column of (i, j) is the west column of (i + 1, j)
            const Raster& east = tiles[{i + 1, j}];
            ASSERT_EQ(t.height, east.height);
            for (int row = 0; row < t.height; ++row, ++compared)
              ASSERT_TRUE(same_bits(t.at(c, t.width - 1, row), east.at(c, 0, row)))
                  << "tile " << i << "," << j << " row " << row << " channel " << c << ": " << t.at(c, t.width - 1, row)
                  << " vs " << east.at(c, 0, row);
          }
          if (j + 1 < 2) {  // the north row of (i, j) is the south row of (i, j + 1)
            const Raster& north = tiles[{i, j + 1}];
            ASSERT_EQ(t.width, north.width);
            for (int col = 0; col < t.width; ++col, ++compared)
              ASSERT_TRUE(same_bits(t.at(c, col, t.height - 1), north.at(c, col, 0)))
                  << "tile " << i << "," << j << " column " << col << " channel " << c;
          }
        }
    EXPECT_GT(compared, 100u * static_cast<std::size_t>(o.channels));
  }
}

TEST(CliTiles, EveryTileEqualsItsWindowOfTheFullBuild) {
  const auto& b = local_build();
  for (const auto& o : kOutputs) {
    SCOPED_TRACE(o.stem);
    const Raster full = read_raster(b.full / (o.stem + o.ext), o.channels);
    ASSERT_EQ(full.width, 101);
    ASSERT_EQ(full.height, 81);
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        const Raster t = read_raster(b.tiled / tile_name(o.stem, i, j, o.ext), o.channels);
        const int i0 = edge(i, 101, 3), j0 = edge(j, 81, 2);
        ASSERT_EQ(t.width, edge(i + 1, 101, 3) - i0 + 1);
        ASSERT_EQ(t.height, edge(j + 1, 81, 2) - j0 + 1);
        std::size_t differing = 0;
        for (int c = 0; c < o.channels; ++c)
          for (int y = 0; y < t.height; ++y)
            for (int x = 0; x < t.width; ++x) differing += !same_bits(t.at(c, x, y), full.at(c, i0 + x, j0 + y));
        EXPECT_EQ(differing, 0u) << "tile " << i << "," << j;
      }
  }
}

// ---- nodes that need the whole domain --------------------------------------------------------------------

TEST(CliTiles, GlobalNodesAreNamedInAWarning) {
  const auto dir = scratch_dir("tiles-global");
  write_text(dir / "g.json", kGlobalGraph);
  for (const std::string mode : {"", "whole", "tile"})
    for (const bool quiet : {false, true}) {
      SCOPED_TRACE(mode + (quiet ? " quiet" : ""));
      std::vector<std::string> args = {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--tiles",
                                       "2x2"};
      if (!mode.empty()) args.insert(args.end(), {"--global-nodes", mode});
      if (quiet) args.push_back("--quiet");
      const auto r = orogen(args);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      // Every global node is named with its type: evaluated whole, in one warning; per tile, one warning each
      // with the writers it reaches.
      if (mode == "tile") {
        for (const auto& [node, type, writer] :
             {std::tuple{"stretch", "Normalize", "save_stretch"}, std::tuple{"warped", "Warp", "save_warped"}}) {
          const auto at = r.err.find(std::string("warning: --tiles: node '") + node + "' (" + type + ", reach global)");
          ASSERT_NE(at, std::string::npos) << r.err;
          const auto line = r.err.substr(at, r.err.find('\n', at) - at);
          EXPECT_NE(line.find("depends on the whole domain"), std::string::npos) << line;
          EXPECT_NE(line.find(std::string("'") + writer + "'"), std::string::npos) << line;
          EXPECT_NE(line.find("will not join"), std::string::npos) << line;
        }
      } else {
        // The normalization runs across the tiles (a reduction of their ranges): not named.
        EXPECT_NE(r.err.find("warning: --tiles: node 'warped' (Warp) depends on the whole domain (reach "
                             "global): computed once on the whole domain"),
                  std::string::npos)
            << r.err;
        std::istringstream lines(r.err);
        for (std::string line; std::getline(lines, line);)
          if (line.rfind("warning:", 0) == 0) {
            EXPECT_EQ(line.find("stretch"), std::string::npos) << line;
          }
      }
      // Local and point-wise nodes and the writers themselves are not reported.
      EXPECT_EQ(r.err.find("node 'smooth'"), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("node 'noise'"), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("node 'save_"), std::string::npos) << r.err;
      // A 16-bit PNG over each tile's own height range does not join either.
      EXPECT_NE(r.err.find("warning: --tiles: writer 'save_smooth' maps 16-bit heights over each tile's own range"),
                std::string::npos)
          << r.err;
      EXPECT_TRUE(fs::exists(dir / "out" / "warped_x1_y1.exr"));
    }
  // The warnings are about tiling: the untiled build has none.
  const auto whole = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string()});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(whole.err.find("warning"), std::string::npos) << whole.err;
  // With a fixed range, the PNG writer is no longer reported.
  const auto fixed = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "fixed").string(), "--tiles", "2x2",
                             "--set", "save_smooth.range=fixed", "--quiet"});
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  EXPECT_EQ(fixed.err.find("save_smooth"), std::string::npos) << fixed.err;
}

// Differing samples between tile (i, j) of `file` and its window of the untiled build.
std::size_t window_differences(const fs::path& whole_dir, const fs::path& tiled_dir, const std::string& stem,
                               glm::ivec2 samples, glm::ivec2 tiles, int i, int j) {
  const Raster whole = read_raster(whole_dir / (stem + ".exr"));
  const Raster t = read_raster(tiled_dir / tile_name(stem, i, j, ".exr"));
  const int i0 = edge(i, samples.x, tiles.x), j0 = edge(j, samples.y, tiles.y);
  EXPECT_EQ(t.width, edge(i + 1, samples.x, tiles.x) - i0 + 1);
  EXPECT_EQ(t.height, edge(j + 1, samples.y, tiles.y) - j0 + 1);
  std::size_t differing = 0;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) differing += !same_bits(t.at(0, x, y), whole.at(0, i0 + x, j0 + y));
  return differing;
}

TEST(CliTiles, GlobalNodesJoinWhenEvaluatedWholeAndNotPerTile) {
  const auto dir = scratch_dir("tiles-global-modes");
  write_text(dir / "g.json", kGlobalGraph);
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string(), "--quiet"}).exit_code, 0);
  for (const std::string mode : {"whole", "tile"}) {
    const auto out = dir / mode;
    const auto r = orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "--tiles", "2x2", "--global-nodes",
                           mode, "--stats", (dir / (mode + ".json")).string(), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        SCOPED_TRACE(mode + " tile " + std::to_string(i) + "," + std::to_string(j));
        // The local blur equals the untiled build in both modes.
        EXPECT_EQ(window_differences(dir / "whole", out, "smooth", {65, 65}, {2, 2}, i, j), 0u);
        const auto stretch = window_differences(dir / "whole", out, "stretch", {65, 65}, {2, 2}, i, j);
        const auto warped = window_differences(dir / "whole", out, "warped", {65, 65}, {2, 2}, i, j);
        const auto stats = nlohmann::json::parse(read_text(dir / tile_name(mode, i, j, ".json")));
        if (mode == "whole") {
          // Cut from one whole-domain result, or run across the tiles: the same samples as the untiled build.
          EXPECT_EQ(stretch, 0u);
          EXPECT_EQ(warped, 0u);
          const std::string expected = i == 0 && j == 0 ? "computed" : "cached";
          EXPECT_EQ(stats["nodes"]["warped"]["status"], expected);
          // The normalization ran across the tiles before they were evaluated: given to each tile.
          EXPECT_EQ(stats["nodes"]["stretch"]["status"], "cached");
        } else {
          // Each tile normalizes its own range: the warning is needed.
          EXPECT_GT(stretch, 0u);
          EXPECT_EQ(stats["nodes"]["stretch"]["status"], "computed");
        }
      }
  }
}

// Points that depend on the domain asked for (PoissonDisk filling up to the edges, ForestLifeCycle's competition)
// are computed on the whole domain and each tile gets the points inside it; tile-invariant scatterings (PoissonDisk
// cropped to the domain, ScatterRules) run per tile. Either way the tiles' files hold exactly the untiled points,
// and only the first kind is named in the whole-domain warning.
TEST(CliTiles, PointsJoinIntoTheUntiledPointsWhetherComputedWholeOrPerTile) {
  const auto dir = scratch_dir("tiles-points");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [300, 200], "resolution": [61, 41] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 120, "seed": 3, "amplitude": 40 } },
    { "id": "bordered", "type": "PoissonDisk", "inputs": { "height": "noise.out" },
      "params": { "radius_0": 6, "seed": 2 } },
    { "id": "cropped", "type": "PoissonDisk", "params": { "radius_0": 6, "seed": 2, "fill_border": false } },
    { "id": "forest", "type": "ForestLifeCycle", "inputs": { "in": "cropped.out", "height": "noise.out" },
      "params": { "years": 20 } },
    { "id": "plants", "type": "ScatterRules", "inputs": { "in": "noise.out" } },
    { "id": "save_bordered", "type": "WritePoints", "inputs": { "in": "bordered.out" }, "params": { "path": "b.csv" } },
    { "id": "save_cropped", "type": "WritePoints", "inputs": { "in": "cropped.out" }, "params": { "path": "c.csv" } },
    { "id": "save_forest", "type": "WritePoints", "inputs": { "in": "forest.out" }, "params": { "path": "f.csv" } },
    { "id": "save_plants", "type": "WritePoints", "inputs": { "in": "plants.out" }, "params": { "path": "p.csv" } }
  ]
})");
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string(), "--quiet"}).exit_code, 0);
  auto rows = [](const fs::path& file, std::multiset<std::string>& into) {
    std::istringstream in(read_text(file));
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) into.insert(line);
  };
  for (const glm::ivec2 tiles : {glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(1, 4)}) {
    const std::string text = std::to_string(tiles.x) + "x" + std::to_string(tiles.y);
    SCOPED_TRACE(text);
    const fs::path out = dir / ("tiled" + text);
    const auto r = orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "--tiles", text, "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string whole_nodes = r.err.substr(0, r.err.find('\n'));
    EXPECT_NE(whole_nodes.find("'bordered' (PoissonDisk)"), std::string::npos) << r.err;
    EXPECT_NE(whole_nodes.find("'forest' (ForestLifeCycle)"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("'cropped'"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("'plants'"), std::string::npos) << r.err;
    for (const char* name : {"b", "c", "f", "p"}) {
      std::multiset<std::string> untiled, joined;
      rows(dir / "whole" / (std::string(name) + ".csv"), untiled);
      for (int j = 0; j < tiles.y; ++j)
        for (int i = 0; i < tiles.x; ++i) rows(out / tile_name(name, i, j, ".csv"), joined);
      EXPECT_GT(untiled.size(), 20u) << name;
      // No point lies on a tile border here, so the tiles partition the untiled points.
      EXPECT_TRUE(joined == untiled) << name << ": " << joined.size() << " points in the tiles, " << untiled.size()
                                     << " untiled";
    }
  }
}

TEST(CliTiles, WholeDomainNodesWithoutRastersAreBuiltPerTileAndSaySo) {
  // A mesh cannot be cut from a whole-domain result: each tile meshes its own samples (and is named), while
  // the rivers, computed across the tiles, give each tile the whole network and its window of the mask.
  const auto dir = scratch_dir("tiles-mesh");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [640, 640], "resolution": [65, 65] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 200, "seed": 5, "amplitude": 50 } },
    { "id": "rivers", "type": "RiverExtract", "inputs": { "in": "noise.out" } },
    { "id": "mesh", "type": "HeightfieldToMesh", "inputs": { "in": "noise.out" } },
    { "id": "save_mesh", "type": "WriteMesh", "inputs": { "in": "mesh.out" }, "params": { "path": "terrain.obj" } },
    { "id": "save_rivers", "type": "WriteCurves", "inputs": { "in": "rivers.out" },
      "params": { "path": "rivers.json" } },
    { "id": "save_mask", "type": "WriteHeightfield", "inputs": { "in": "rivers.river_mask" },
      "params": { "path": "mask.exr" } },
    { "id": "lod", "type": "Resample", "inputs": { "in": "noise.out" }, "params": { "spacing": 20 } },
    { "id": "lod_mesh", "type": "HeightfieldToMesh", "inputs": { "in": "lod.out" } },
    { "id": "save_lod", "type": "WriteMesh", "inputs": { "in": "lod_mesh.out" }, "params": { "path": "lod.obj" } }
  ]
})");
  const auto r =
      orogen({"eval", (dir / "g.json").string(), "-o", (dir / "tiled").string(), "--tiles", "2x2", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("node 'mesh' (HeightfieldToMesh, reach global) depends on the whole domain: its mesh 'out' "
                       "cannot be cut from a whole-domain result: each tile computes it from its own part only"),
            std::string::npos)
      << r.err;
  // RiverExtract runs across the tiles (not named with the whole-domain nodes): every tile gets the whole joined
  // network and its window of the mask.
  EXPECT_EQ(r.err.find("'rivers'"), std::string::npos) << r.err;
  // Resample puts its output on a lattice of its own: it cannot be cut either, and resamples each tile.
  EXPECT_NE(r.err.find("node 'lod' (Resample, reach global) depends on the whole domain: its 'out' on its own lattice "
                       "cannot be cut from a whole-domain result: each tile computes it"),
            std::string::npos)
      << r.err;
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string(), "--quiet"}).exit_code, 0);
  auto vertices = [](const fs::path& obj_file) {
    const std::string obj = read_text(obj_file);
    std::size_t n = 0;
    for (std::size_t at = obj.find("\nv "); at != std::string::npos; at = obj.find("\nv ", at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(vertices(dir / "whole" / "lod.obj"), 33u * 33u);  // 640 m at 20 m
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      EXPECT_EQ(vertices(dir / "tiled" / tile_name("terrain", i, j, ".obj")), 33u * 33u)
          << "tile " << i << "," << j << " meshes its own 33 x 33 samples";
      EXPECT_EQ(vertices(dir / "tiled" / tile_name("lod", i, j, ".obj")), 17u * 17u)
          << "tile " << i << "," << j << " resamples its own 320 m at 20 m";
      EXPECT_EQ(window_differences(dir / "whole", dir / "tiled", "mask", {65, 65}, {2, 2}, i, j), 0u);
      EXPECT_EQ(read_text(dir / "tiled" / tile_name("rivers", i, j, ".json")),
                read_text(dir / "whole" / "rivers.json"));
    }
}

TEST(CliTiles, EveryExampleGraphTilesIntoItsUntiledBuild) {
  // With whole-domain nodes evaluated whole (the default), every float raster a graph writes is, tile by
  // tile, its window of the untiled build, bit for bit. (16-bit PNGs map each tile's own range: not compared.)
  // At 65^2 the 2x3 tiles are narrower than most halos, the harder case for the stitching, and the suite stays
  // short.
  std::size_t total = 0;
  for (const auto& entry : fs::directory_iterator(source_dir() / "graphs")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const auto dir = scratch_dir("tiles-example");
    auto whole =
        orogen({"eval", entry.path().string(), "--resolution", "65", "-o", (dir / "whole").string(), "--quiet"});
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    auto tiled = orogen({"eval", entry.path().string(), "--resolution", "65", "-o", (dir / "tiled").string(), "--tiles",
                         "2x3", "--quiet"});
    ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
    std::size_t compared = 0;
    for (const auto& f : fs::recursive_directory_iterator(dir / "whole")) {
      const auto ext = f.path().extension().string();
      if (ext != ".exr" && ext != ".tif" && ext != ".tiff") continue;
      const auto rel = fs::relative(f.path(), dir / "whole");
      const std::string stem = (rel.parent_path() / rel.stem()).generic_string();
      SCOPED_TRACE(rel.generic_string());
      const auto info = read_height_raster(f.path());
      const Raster full = read_raster(f.path(), info.channels);
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 2; ++i) {
          const Raster t = read_raster(dir / "tiled" / tile_name(stem, i, j, ext), info.channels);
          const int i0 = edge(i, full.width, 2), j0 = edge(j, full.height, 3);
          ASSERT_EQ(t.width, edge(i + 1, full.width, 2) - i0 + 1);
          ASSERT_EQ(t.height, edge(j + 1, full.height, 3) - j0 + 1);
          std::size_t differing = 0;
          for (int c = 0; c < info.channels; ++c)
            for (int y = 0; y < t.height; ++y)
              for (int x = 0; x < t.width; ++x) differing += !same_bits(t.at(c, x, y), full.at(c, i0 + x, j0 + y));
          EXPECT_EQ(differing, 0u) << "tile " << i << "," << j;
        }
      ++compared;
    }
    total += compared;
    std::cerr << entry.path().filename().string() << ": " << compared
              << " float raster outputs compared in 2x3 tiles\n";
  }
  EXPECT_GT(total, 3u);
}

// AmbientOcclusion and Cavity march their horizon rays a bounded distance (their radius, declared as their reach plus
// 2 samples), so they are per-tile nodes: each tile, evaluated with that halo, equals its window of the untiled build
// bit for bit, tiles narrower than the halo included (7x6 tiles of 65^2 are 10 or 11 samples wide; the occlusion's
// halo is 400 m / 31.25 m + 2 = 15 samples), and no warning names them.
TEST(CliTiles, HorizonShadingWithABoundedReachTilesIntoTheUntiledBuild) {
  const auto dir = scratch_dir("tiles-horizons");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [2000, 2000], "resolution": [65, 65] },
  "nodes": [
    { "id": "fbm", "type": "FBM", "params": { "feature_size": 600, "amplitude": 300, "octaves": 5, "seed": 4 } },
    { "id": "ao", "type": "AmbientOcclusion", "inputs": { "in": "fbm.out" }, "params": { "radius": 400, "directions": 16 } },
    { "id": "cavity", "type": "Cavity", "inputs": { "in": "fbm.out" }, "params": { "radius": 90, "directions": 8 } },
    { "id": "save_ao", "type": "WriteHeightfield", "inputs": { "in": "ao.out" }, "params": { "path": "ao.exr" } },
    { "id": "save_cavity", "type": "WriteHeightfield", "inputs": { "in": "cavity.out" }, "params": { "path": "cavity.exr" } }
  ]
})");
  auto whole = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string(), "--quiet"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  for (const glm::ivec2 counts : {glm::ivec2(3, 2), glm::ivec2(7, 6)}) {
    const std::string tiling = std::to_string(counts.x) + "x" + std::to_string(counts.y);
    SCOPED_TRACE(tiling);
    const fs::path out = dir / ("tiled" + tiling);
    auto tiled = orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "--tiles", tiling, "--quiet"});
    ASSERT_EQ(tiled.exit_code, 0) << tiled.err;
    EXPECT_EQ(tiled.err.find("warning"), std::string::npos) << tiled.err;
    for (const char* stem : {"ao", "cavity"})
      for (int j = 0; j < counts.y; ++j)
        for (int i = 0; i < counts.x; ++i)
          EXPECT_EQ(window_differences(dir / "whole", out, stem, {65, 65}, counts, i, j), 0u) << stem << " " << i << j;
  }
}

// Nodes that run across the tiles (cli/tile_graph_stages.h): depressions filled flat and with epsilon flats (rounds
// until no tile's perimeter falls), lakes kept by depth and area
// and numbered across tiles, a blur of the filled terrain whose halo comes from the neighboring tiles, a
// normalization of the blur over the whole domain's range (a reduction after a tile-graph node), and flow directions
// and D8 accumulation with its flow map and wetness index (the epsilon fill's rounds, a ring of the filled surface
// from the neighboring tiles, cell counts through perimeter links, the largest count), watersheds numbered
// across the tiles, and a flood from a seed (to a given level, and to the seed's spill level) joined across them.
const char* kAcrossTilesGraph = R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [2560, 2560], "resolution": [257, 257] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 600, "seed": 11, "amplitude": 80, "octaves": 5 } },
    { "id": "filled", "type": "FillDepressions", "inputs": { "in": "noise.out" }, "params": { "flats": "flat" } },
    { "id": "filled_eps", "type": "FillDepressions", "inputs": { "in": "noise.out" } },
    { "id": "save_filled_eps", "type": "WriteHeightfield", "inputs": { "in": "filled_eps.out" },
      "params": { "path": "filled_eps.exr" } },
    { "id": "lakes", "type": "Lakes", "inputs": { "in": "noise.out" },
      "params": { "min_depth": 0.5, "min_area": 2000 } },
    { "id": "smooth", "type": "Blur", "inputs": { "in": "filled.out" }, "params": { "sigma": 30 } },
    { "id": "stretch", "type": "Normalize", "inputs": { "in": "smooth.out" }, "params": { "min": -1, "max": 1 } },
    { "id": "save_stretch", "type": "WriteHeightfield", "inputs": { "in": "stretch.out" },
      "params": { "path": "stretch.exr" } },
    { "id": "save_filled", "type": "WriteHeightfield", "inputs": { "in": "filled.out" },
      "params": { "path": "filled.exr" } },
    { "id": "save_smooth", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "smooth.exr" } },
    { "id": "save_ids", "type": "WriteHeightfield", "inputs": { "in": "lakes.lake_id" },
      "params": { "path": "lake_id.exr" } },
    { "id": "save_depth", "type": "WriteHeightfield", "inputs": { "in": "lakes.water_depth" },
      "params": { "path": "lake_depth.exr" } },
    { "id": "direction", "type": "FlowDirection", "inputs": { "in": "noise.out" }, "params": { "method": "dinf" } },
    { "id": "save_direction", "type": "WriteHeightfield", "inputs": { "in": "direction.out" },
      "params": { "path": "direction.exr" } },
    { "id": "save_gradient", "type": "WriteHeightfield", "inputs": { "in": "direction.gradient" },
      "params": { "path": "gradient.exr" } },
    { "id": "flow", "type": "FlowAccumulation", "inputs": { "in": "noise.out" }, "params": { "method": "d8" } },
    { "id": "save_flow", "type": "WriteHeightfield", "inputs": { "in": "flow.out" },
      "params": { "path": "flow.exr" } },
    { "id": "save_flow_map", "type": "WriteHeightfield", "inputs": { "in": "flow.flow" },
      "params": { "path": "flow_map.exr" } },
    { "id": "save_wetness", "type": "WriteHeightfield", "inputs": { "in": "flow.wetness" },
      "params": { "path": "wetness.exr" } },
    { "id": "basins", "type": "Watersheds", "inputs": { "in": "noise.out" }, "params": { "min_area": 50000 } },
    { "id": "save_basins", "type": "WriteHeightfield", "inputs": { "in": "basins.out" },
      "params": { "path": "basins.exr" } },
    { "id": "save_basin_area", "type": "WriteHeightfield", "inputs": { "in": "basins.area" },
      "params": { "path": "basin_area.exr" } },
    { "id": "flood", "type": "FloodFill", "inputs": { "in": "noise.out" },
      "params": { "position": [1280, 1280], "level_mode": "level", "level": 0 } },
    { "id": "save_flood", "type": "WriteHeightfield", "inputs": { "in": "flood.water_depth" },
      "params": { "path": "flood_depth.exr" } },
    { "id": "pond", "type": "FloodFill", "inputs": { "in": "noise.out" }, "params": { "position": [1280, 1280] } },
    { "id": "save_pond", "type": "WriteHeightfield", "inputs": { "in": "pond.out" }, "params": { "path": "pond.exr" } }
  ]
})";

TEST(CliTiles, TileGraphAndReductionNodesRunAcrossTheTilesExactly) {
  const auto dir = scratch_dir("tiles-across");
  write_text(dir / "g.json", kAcrossTilesGraph);
  const auto graph = (dir / "g.json").string();
  ASSERT_EQ(orogen({"eval", graph, "-o", (dir / "whole").string(), "--quiet"}).exit_code, 0);
  const std::vector<std::string> tiled_args = {"eval",        graph,
                                               "-o",          (dir / "tiled").string(),
                                               "--tiles",     "4x3",
                                               "--stats",     (dir / "s.json").string(),
                                               "--cache-dir", (dir / "cache").string()};
  const auto r = orogen(tiled_args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("node 'filled' (FillDepressions) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'filled_eps' (FillDepressions) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'lakes' (Lakes) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'direction' (FlowDirection) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'flow' (FlowAccumulation) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'basins' (Watersheds) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'flood' (FloodFill) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'pond' (FloodFill) computed across the tiles"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << "nothing is computed on the whole domain:\n" << r.err;
  // Every tile is its window of the untiled build, bit for bit: filled heights, the blur's halo, lake numbers.
  EXPECT_NE(r.err.find("node 'stretch' (Normalize) computed across the tiles"), std::string::npos) << r.err;
  for (const std::string stem :
       {"filled", "filled_eps", "smooth", "lake_id", "lake_depth", "stretch", "direction", "gradient", "flow",
        "flow_map", "wetness", "basins", "basin_area", "flood_depth", "pond"})
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        EXPECT_EQ(window_differences(dir / "whole", dir / "tiled", stem, {257, 257}, {4, 3}, i, j), 0u)
            << stem << " tile " << i << "," << j;
  // The test means something: several lakes are kept, and one of them spans tiles.
  const Raster ids = read_raster(dir / "whole" / "lake_id.exr");
  std::map<int, std::set<int>> tiles_of_lake;
  for (int y = 0; y < ids.height; ++y)
    for (int x = 0; x < ids.width; ++x)
      if (const int id = static_cast<int>(ids.at(0, x, y)); id > 0)
        tiles_of_lake[id].insert(y * 3 / 257 * 4 + x * 4 / 257);
  EXPECT_GT(tiles_of_lake.size(), 3u);
  EXPECT_TRUE(
      std::any_of(tiles_of_lake.begin(), tiles_of_lake.end(), [](const auto& l) { return l.second.size() > 1; }));
  // The flood from the middle spans several tiles.
  const Raster flood = read_raster(dir / "whole" / "flood_depth.exr");
  std::set<int> flooded_tiles;
  for (int y = 0; y < flood.height; ++y)
    for (int x = 0; x < flood.width; ++x)
      if (flood.at(0, x, y) > 0.0f) flooded_tiles.insert(y * 3 / 257 * 4 + x * 4 / 257);
  EXPECT_GE(flooded_tiles.size(), 3u);
  // A memory limit that refuses the untiled fill refuses the tiles of one process too: across the tiles a rank holds
  // every one of its tiles' state at once, so such a limit is met by spreading the tiles over ranks
  // (test_distributed.cpp), and the refusal says over how many.
  const auto refused = orogen({"eval", graph, "-o", (dir / "m").string(), "--max-memory", "500K", "--quiet"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("node 'filled': its type FillDepressions needs"), std::string::npos) << refused.err;
  const auto tiles_refused =
      orogen({"eval", graph, "-o", (dir / "m").string(), "--max-memory", "500K", "--tiles", "4x4", "--quiet"});
  EXPECT_EQ(tiles_refused.exit_code, 2);
  EXPECT_NE(tiles_refused.err.find("node 'filled' runs across the tiles, and a rank holds its state for all of its "
                                   "tiles at once: 16 tiles of 99x99 samples"),
            std::string::npos)
      << tiles_refused.err;
  EXPECT_NE(tiles_refused.err.find("run it on 8 ranks or more"), std::string::npos) << tiles_refused.err;
  const auto accepted =
      orogen({"eval", graph, "-o", (dir / "m").string(), "--max-memory", "8M", "--tiles", "4x4", "--quiet"});
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;
  // Run again with the same cache: the stages find their results, and no tile computes anything.
  const auto again = orogen(tiled_args);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("node 'filled' (FillDepressions) cached on every tile"), std::string::npos) << again.err;
  const auto stats = nlohmann::json::parse(read_text(dir / "s_x2_y1.json"));
  for (const auto& [id, node] : stats["nodes"].items()) EXPECT_EQ(node["status"], "cached") << id;
}

// `orogen nodes TYPE` says which of the tile-graph nodes run across the tiles and which are, for now, computed on the
// whole domain.
TEST(CliTiles, TheNodeReferenceSaysWhichHydrologyNodesRunAcrossTheTiles) {
  for (const char* type : {"FillDepressions", "Lakes", "FlowDirection", "FlowAccumulation", "Watersheds", "FloodFill",
                           "RiverExtract", "DrainageMetrics"}) {
    const auto r = orogen({"nodes", type});
    ASSERT_EQ(r.exit_code, 0) << type;
    EXPECT_NE(r.out.find("(runs across the tiles"), std::string::npos) << type << ":\n" << r.out;
  }
  // With the parameters or inputs an algorithm cannot take, the node is computed on the whole domain: said too.
  for (const char* type : {"RiverExtract"}) {
    const auto r = orogen({"nodes", type});
    ASSERT_EQ(r.exit_code, 0) << type;
    EXPECT_NE(r.out.find("no rainfall_weight linked"), std::string::npos) << type << ":\n" << r.out;
    EXPECT_NE(r.out.find("otherwise computed on the whole domain by every rank that needs it)"), std::string::npos)
        << type << ":\n"
        << r.out;
  }
}

// A rainfall weight makes the accumulation a sum of floating-point weights, and D-infinity and MFD sums of fractions:
// they run across the tiles too (shares pulled in neighbour order, nodes/hydrology/tile_shares.h), as the unweighted
// D8 counts do, and all equal the untiled build.
TEST(CliTiles, WeightedAndDispersiveFlowAccumulationRunAcrossTheTiles) {
  const auto dir = scratch_dir("tiles-rainfall");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [640, 640], "resolution": [65, 65] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 200, "seed": 3, "amplitude": 30 } },
    { "id": "rain", "type": "FBM", "params": { "feature_size": 300, "seed": 4, "amplitude": 0.5 } },
    { "id": "flow", "type": "FlowAccumulation", "inputs": { "in": "noise.out" }, "params": { "method": "d8" } },
    { "id": "wet", "type": "FlowAccumulation", "inputs": { "in": "noise.out", "rainfall_weight": "rain.out" },
      "params": { "method": "d8" } },
    { "id": "spread", "type": "FlowAccumulation", "inputs": { "in": "noise.out", "rainfall_weight": "rain.out" },
      "params": { "method": "mfd" } },
    { "id": "facets", "type": "FlowAccumulation", "inputs": { "in": "noise.out" }, "params": { "method": "dinf" } },
    { "id": "save_flow", "type": "WriteHeightfield", "inputs": { "in": "flow.out" }, "params": { "path": "flow.exr" } },
    { "id": "save_wet", "type": "WriteHeightfield", "inputs": { "in": "wet.out" }, "params": { "path": "wet.exr" } },
    { "id": "save_spread", "type": "WriteHeightfield", "inputs": { "in": "spread.flow" },
      "params": { "path": "spread.exr" } },
    { "id": "save_facets", "type": "WriteHeightfield", "inputs": { "in": "facets.wetness" },
      "params": { "path": "facets.exr" } }
  ]
})");
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "whole").string(), "--quiet"}).exit_code, 0);
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "tiled").string(), "--tiles", "3x2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string node : {"flow", "wet", "spread", "facets"})
    EXPECT_NE(r.err.find("node '" + node + "' (FlowAccumulation) computed across the tiles"), std::string::npos)
        << r.err;
  for (const std::string stem : {"flow", "wet", "spread", "facets"})
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(window_differences(dir / "whole", dir / "tiled", stem, {65, 65}, {3, 2}, i, j), 0u)
            << stem << " tile " << i << "," << j;
}

// ---- --origin and --size ---------------------------------------------------------------------------------

TEST(CliTiles, OriginAndSizeEqualAnEditedGraph) {
  const auto dir = scratch_dir("tiles-origin");
  write_text(dir / "g.json", kLocalGraph);
  auto edited = nlohmann::json::parse(kLocalGraph);
  edited["domain"]["origin"] = {250.0, -130.5};
  edited["domain"]["size"] = {1500.0, 1200.0};
  write_text(dir / "edited.json", edited.dump(2));
  auto by_options = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "options").string(), "--origin",
                            "250,-130.5", "--size", "1500,1200", "--quiet"});
  ASSERT_EQ(by_options.exit_code, 0) << by_options.err;
  ASSERT_EQ(orogen({"eval", (dir / "edited.json").string(), "-o", (dir / "edited").string(), "--quiet"}).exit_code, 0);
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "plain").string(), "--quiet"}).exit_code, 0);
  for (const auto& o : kOutputs) {
    SCOPED_TRACE(o.stem);
    const Raster a = read_raster(dir / "options" / (o.stem + o.ext), o.channels);
    const Raster e = read_raster(dir / "edited" / (o.stem + o.ext), o.channels);
    const Raster p = read_raster(dir / "plain" / (o.stem + o.ext), o.channels);
    ASSERT_EQ(a.width, 101);
    ASSERT_EQ(a.height, 81);
    for (int c = 0; c < o.channels; ++c) {
      EXPECT_EQ(std::memcmp(a.channels[c].data(), e.channels[c].data(), a.channels[c].size() * sizeof(float)), 0);
      EXPECT_NE(std::memcmp(a.channels[c].data(), p.channels[c].data(), a.channels[c].size() * sizeof(float)), 0)
          << "moving the domain did not change the terrain";
    }
  }
}

TEST(CliTiles, OriginMovesTheTerrainByWholeSamples) {
  // Moving the origin by 3 samples east and 2 north shows the same terrain shifted (noise in world
  // coordinates): the moved build's sample (i, j) is the original's (i + 3, j + 2) for a point-wise graph.
  const auto dir = scratch_dir("tiles-shift");
  const std::string graph = R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [640, 480], "resolution": [65, 49] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 200, "seed": 2 } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "noise.out" }, "params": { "path": "h.exr" } }
  ]
})";
  write_text(dir / "g.json", graph);
  ASSERT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "a").string(), "--quiet"}).exit_code, 0);
  ASSERT_EQ(
      orogen({"eval", (dir / "g.json").string(), "-o", (dir / "b").string(), "--origin", "30,20", "--quiet"}).exit_code,
      0);
  const Raster a = read_raster(dir / "a" / "h.exr"), b = read_raster(dir / "b" / "h.exr");
  for (int j = 0; j + 2 < a.height; ++j)
    for (int i = 0; i + 3 < a.width; ++i) ASSERT_EQ(b.at(0, i, j), a.at(0, i + 3, j + 2)) << i << "," << j;
}

TEST(CliTiles, TilesOfAMovedDomainEqualItsWindows) {
  const auto dir = scratch_dir("tiles-moved");
  write_text(dir / "g.json", kLocalGraph);
  const std::vector<std::string> move = {"--origin", "-5000,12000", "--size", "2000,1600", "--resolution", "121"};
  auto args = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> a = {"eval", (dir / "g.json").string(), "-o", (dir / out).string(), "--quiet"};
    a.insert(a.end(), move.begin(), move.end());
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  ASSERT_EQ(orogen(args("whole", {})).exit_code, 0);
  const auto r = orogen(args("tiled", {"--tiles", "2x4", "--tile", "1,2"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Raster whole = read_raster(dir / "whole" / "height.exr"), t = read_raster(dir / "tiled" / "height_x1_y2.exr");
  ASSERT_EQ(whole.width, 121);
  ASSERT_EQ(whole.height, 97);
  const int i0 = edge(1, 121, 2), j0 = edge(2, 97, 4);
  ASSERT_EQ(t.width, edge(2, 121, 2) - i0 + 1);
  ASSERT_EQ(t.height, edge(3, 97, 4) - j0 + 1);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x)
      ASSERT_TRUE(same_bits(t.at(0, x, y), whole.at(0, i0 + x, j0 + y))) << x << "," << y;
}

// ---- cache and statistics per tile ------------------------------------------------------------------------

TEST(CliTiles, CacheAndStatsArePerTile) {
  const auto dir = scratch_dir("tiles-cache");
  write_text(dir / "g.json", kLocalGraph);
  auto run = [&](const std::string& stats, std::vector<std::string> extra) {
    std::vector<std::string> a = {"eval",        (dir / "g.json").string(), "-o",      (dir / "out").string(),
                                  "--cache-dir", (dir / "cache").string(),  "--stats", (dir / stats).string(),
                                  "--quiet"};
    a.insert(a.end(), extra.begin(), extra.end());
    const auto r = orogen(a);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  run("first.json", {"--tiles", "2x2"});
  std::set<std::string> keys;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const auto s = nlohmann::json::parse(read_text(dir / tile_name("first", i, j, ".json")));
      EXPECT_TRUE(s["ok"].get<bool>());
      EXPECT_EQ(s["nodes"]["noise"]["status"], "computed") << i << "," << j;
      keys.insert(s["nodes"]["noise"]["key"].get<std::string>());
      if (i == 0 && j == 0) {
        EXPECT_EQ(s["totals"]["computed"].get<int>(), 12);  // every node
      } else {
        // The wide blur's halo (180 m sigma) spans the whole domain from every tile: one result serves all
        // tiles, and its upstream is not even looked at.
        EXPECT_EQ(s["nodes"]["wide"]["status"], "cached") << i << "," << j;
        EXPECT_FALSE(s["nodes"].contains("cells")) << i << "," << j;
        EXPECT_EQ(s["totals"]["computed"].get<int>(), 10) << i << "," << j;
      }
    }
  EXPECT_EQ(keys.size(), 4u) << "each tile's noise is a result of its own";
  // The second run finds every tile's results.
  run("second.json", {"--tiles", "2x2"});
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const auto s = nlohmann::json::parse(read_text(dir / tile_name("second", i, j, ".json")));
      EXPECT_EQ(s["totals"]["computed"].get<int>(), 0) << i << "," << j;
      for (const auto& [id, node] : s["nodes"].items()) EXPECT_EQ(node["status"], "cached") << id;
    }
  // One tile of the same tiling alone is cached too; another tiling is not.
  run("one.json", {"--tiles", "2x2", "--tile", "1,0"});
  EXPECT_EQ(nlohmann::json::parse(read_text(dir / "one_x1_y0.json"))["totals"]["computed"].get<int>(), 0);
  run("other.json", {"--tiles", "3x3", "--tile", "1,1"});
  EXPECT_EQ(nlohmann::json::parse(read_text(dir / "other_x1_y1.json"))["nodes"]["noise"]["status"], "computed");
  // A 1x1 tiling is the untiled build: its nodes share the untiled results (only the suffixed writers run).
  run("untiled.json", {});
  run("single.json", {"--tiles", "1x1"});
  const auto single = nlohmann::json::parse(read_text(dir / "single_x0_y0.json"));
  for (const auto& [id, node] : single["nodes"].items())
    EXPECT_EQ(node["status"], id.rfind("save_", 0) == 0 ? "computed" : "cached") << id;
}

TEST(CliTiles, ProgressAndSummaryPerTile) {
  const auto& b = local_build();
  const auto out = scratch_dir("tiles-progress");
  const auto r = orogen({"eval", (b.dir / "g.json").string(), "-o", out.string(), "--tiles", "3x2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int n = 1; n <= 6; ++n) {
    const int i = (n - 1) % 3, j = (n - 1) / 3;
    const std::string label = "tile " + std::to_string(i) + "," + std::to_string(j) + " (" + std::to_string(n) + "/6)";
    EXPECT_NE(r.err.find(label + ": "), std::string::npos) << label << "\n" << r.err;
    const auto summary = r.err.find(label + ": 1");  // "12 computed" or "10 computed, 1 cached"
    ASSERT_NE(summary, std::string::npos) << label << "\n" << r.err;
    EXPECT_NE(r.err.find("0 failed, 0 skipped in", summary), std::string::npos) << label << "\n" << r.err;
  }
  EXPECT_NE(r.err.find("6 tiles built, 0 with failures"), std::string::npos) << r.err;
  // --quiet prints nothing for a seamless graph.
  const auto q = orogen({"eval", (b.dir / "g.json").string(), "-o", out.string(), "--tiles", "3x2", "--quiet"});
  ASSERT_EQ(q.exit_code, 0);
  EXPECT_TRUE(q.err.empty()) << q.err;
}

}  // namespace
}  // namespace orogen::test
