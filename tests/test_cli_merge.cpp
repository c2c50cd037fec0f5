// End-to-end tests of `orogen eval --tiles NxM --merge` (cli/merge_tiles.h): each height raster's tiles become
// one file that equals the untiled build's byte for byte, streamed through one process; the tiles go away, what
// cannot merge keeps its tiles and says so, and what can never merge is refused before anything runs.
#include <algorithm>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

ProcessResult orogen(const std::vector<std::string>& args) { return run_process(cli_binary(), args); }

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Every writer and format that merges: heights as EXR, TIFF (with its GDAL side file), PNG16 and RAW16 (fixed
// ranges, with their JSON side files), a linear data image (normals) as PNG and EXR, a color image (sRGB PNG)
// and splat weights that keep their tiles. 101 x 81 samples do not divide evenly into the tilings.
const char* kGraph = R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [1000, 800], "resolution": [101, 81] },
  "nodes": [
    { "id": "noise", "type": "FBM", "params": { "feature_size": 300, "octaves": 6, "seed": 3, "amplitude": 120 } },
    { "id": "smooth", "type": "Blur", "inputs": { "in": "noise.out" }, "params": { "sigma": 25 } },
    { "id": "normals", "type": "Normals", "inputs": { "in": "smooth.out" } },
    { "id": "tint", "type": "ColorRamp", "inputs": { "in": "smooth.out" } },
    { "id": "h_exr", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" }, "params": { "path": "height.exr" } },
    { "id": "h_tif", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "gis/height.tif", "crs": "EPSG:32633" } },
    { "id": "h_png", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "height.png", "range": "fixed", "height_min": -100, "height_max": 200 } },
    { "id": "h_raw", "type": "WriteHeightfield", "inputs": { "in": "smooth.out" },
      "params": { "path": "height.r16", "range": "fixed", "height_min": -100, "height_max": 200 } },
    { "id": "n_png", "type": "WriteImage", "inputs": { "in": "normals.out" }, "params": { "path": "normals.png" } },
    { "id": "n_exr", "type": "WriteImage", "inputs": { "in": "normals.out" }, "params": { "path": "normals.exr" } },
    { "id": "c_png", "type": "WriteImage", "inputs": { "in": "tint.out" }, "params": { "path": "color.png" } }
  ]
})";

const std::vector<std::string> kMerged = {"height.exr",      "gis/height.tif", "gis/height.tif.aux.xml", "height.png",
                                          "height.png.json", "height.r16",     "height.r16.json",        "normals.png",
                                          "normals.exr",     "color.png"};

fs::path write_graph(const fs::path& dir, const std::string& text) {
  fs::create_directories(dir);
  const fs::path g = dir / "graph.json";
  std::ofstream(g) << text;
  return g;
}

TEST(CliMerge, MergedFilesEqualTheUntiledBuildByteForByteAndReplaceTheTiles) {
  const fs::path dir = scratch_dir("cli_merge_equal");
  const fs::path graph = write_graph(dir, kGraph);
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", (dir / "whole").string(), "-q"}).exit_code, 0);
  for (const std::string tiles : {"3x2", "1x4", "4x3"})
    for (const std::string naming : {"orogen", "unreal"}) {
      SCOPED_TRACE(tiles + " " + naming);
      const fs::path out = dir / ("tiled_" + tiles + "_" + naming);
      const auto r =
          orogen({"eval", graph.string(), "-o", out.string(), "--tiles", tiles, "--tile-naming", naming, "--merge"});
      ASSERT_EQ(r.exit_code, 0) << r.err;
      for (const auto& f : kMerged) {
        ASSERT_TRUE(fs::exists(out / f)) << f;
        EXPECT_TRUE(file_bytes(out / f) == file_bytes(dir / "whole" / f)) << f << " differs from the untiled build";
      }
      // Nothing else is left: no tiles, no tile side files, no mosaic of merged files.
      std::size_t files = 0;
      for (const auto& e : fs::recursive_directory_iterator(out)) files += e.is_regular_file() ? 1 : 0;
      EXPECT_EQ(files, kMerged.size());
      EXPECT_NE(r.err.find("7 merged files"), std::string::npos) << r.err;
    }
}

// The lines of a CSV or PLY points file after its header, sorted: the points as a set in a canonical order.
std::vector<std::string> sorted_rows(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> rows;
  std::string line;
  bool body = file.extension() == ".csv";
  bool header = body;
  while (std::getline(in, line)) {
    if (header) {
      header = false;
      continue;
    }
    if (body) rows.push_back(line);
    if (line == "end_header") body = true;
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

TEST(CliMerge, PointsAndCurvesJoinIntoOneFile) {
  const fs::path dir = scratch_dir("cli_merge_vectors");
  const fs::path graph = write_graph(dir, R"({
    "format": "orogen-graph", "version": 7,
    "domain": { "size": [4096, 4096], "resolution": [97, 97] },
    "nodes": [
      { "id": "valley", "type": "Subgraph", "asset": "river_valley", "asset_version": 1,
        "inputs": { "terrain": "terrain.out" } },
      { "id": "hills", "type": "FBM", "params": { "feature_size": 1200, "amplitude": 60, "seed": 21 } },
      { "id": "raise", "type": "Constant", "params": { "value": 90 } },
      { "id": "terrain", "type": "Add", "inputs": { "a": "hills.out", "b": "raise.out" } },
      { "id": "spots", "type": "PoissonDisk", "params": { "radius_0": 80, "seed": 4 } },
      { "id": "csv", "type": "WritePoints", "inputs": { "in": "spots.out" }, "params": { "path": "spots.csv" } },
      { "id": "ply", "type": "WritePoints", "inputs": { "in": "spots.out" }, "params": { "path": "spots.ply" } },
      { "id": "json", "type": "WriteCurves", "inputs": { "in": "valley.rivers" }, "params": { "path": "rivers.json" } },
      { "id": "obj", "type": "WriteCurves", "inputs": { "in": "valley.rivers" }, "params": { "path": "rivers.obj" } }
    ]
  })");
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", (dir / "whole").string(), "-q"}).exit_code, 0);
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", (dir / "tiles").string(), "--tiles", "3x2", "-q"}).exit_code, 0);
  const auto r = orogen({"eval", graph.string(), "-o", (dir / "merged").string(), "--tiles", "3x2", "--merge", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The river network is replicated: every tile writes it whole, and the joined file is the untiled build's.
  for (const std::string f : {"rivers.json", "rivers.obj"}) {
    ASSERT_TRUE(fs::exists(dir / "merged" / f)) << f;
    EXPECT_TRUE(file_bytes(dir / "merged" / f) == file_bytes(dir / "whole" / f)) << f;
  }
  // The points are the union of the tiles' points, each once.
  for (const std::string f : {"spots.csv", "spots.ply"}) {
    const fs::path stem = fs::path(f).stem(), ext = fs::path(f).extension();
    std::vector<std::string> tiles;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        const auto rows = sorted_rows(
            dir / "tiles" / (stem.string() + "_x" + std::to_string(i) + "_y" + std::to_string(j) + ext.string()));
        tiles.insert(tiles.end(), rows.begin(), rows.end());
      }
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    const auto joined = sorted_rows(dir / "merged" / f);
    EXPECT_GT(joined.size(), 50u) << f;
    EXPECT_EQ(joined, tiles) << f;
  }
  const std::string ply = file_bytes(dir / "merged" / "spots.ply");
  EXPECT_NE(ply.find("element vertex " + std::to_string(sorted_rows(dir / "merged" / "spots.ply").size()) + "\n"),
            std::string::npos);
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "merged")) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 4u);
}

TEST(CliMerge, AMergeReplacesAnEarlierTiledBuildsTilesAndMosaic) {
  const fs::path dir = scratch_dir("cli_merge_again");
  const fs::path graph = write_graph(dir, kGraph);
  const fs::path out = dir / "out";
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", out.string(), "--tiles", "2x2", "-q"}).exit_code, 0);
  ASSERT_TRUE(fs::exists(out / "gis" / "height.vrt"));
  ASSERT_TRUE(fs::exists(out / "height_x1_y1.r16.json"));
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", out.string(), "--tiles", "2x2", "--merge", "-q"}).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "gis" / "height.vrt"));
  EXPECT_FALSE(fs::exists(out / "gis" / "height_x0_y0.tif"));
  EXPECT_FALSE(fs::exists(out / "height_x1_y1.r16.json"));
  EXPECT_TRUE(fs::exists(out / "height.r16"));
}

// A 41 x 41 graph of FBM noise ('noise') and the nodes `nodes` (JSON objects, comma-separated).
std::string small_graph(const std::string& nodes) {
  return R"({ "format": "orogen-graph", "version": 7, "domain": { "size": [400, 400], "resolution": [41, 41] },
    "nodes": [ { "id": "noise", "type": "FBM", "params": { "feature_size": 200, "seed": 2, "amplitude": 50 } },)" +
         nodes + "] }";
}

TEST(CliMerge, WritersThatCannotMergeKeepTheirTilesAndSaySo) {
  const fs::path dir = scratch_dir("cli_merge_weightmaps");
  const fs::path graph = write_graph(
      dir, small_graph(R"(      { "id": "weights", "type": "SplatWeights", "inputs": { "in": "noise.out" } },
      { "id": "maps", "type": "WriteWeightmaps", "inputs": { "in": "weights.out" }, "params": { "path": "layers.json" } },
      { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "noise.out" }, "params": { "path": "height.tif" } }
  )"));
  const fs::path out = dir / "out";
  const auto r = orogen({"eval", graph.string(), "-o", out.string(), "--tiles", "2x2", "--merge"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: --merge: 'maps' keeps its tiles: WriteWeightmaps files are not merged"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(out / "height.tif"));
  EXPECT_TRUE(fs::exists(out / "layers_x1_y1.json"));
}

TEST(CliMerge, WhatCannotMergeIsRefusedBeforeAnythingRuns) {
  const fs::path dir = scratch_dir("cli_merge_refused");
  const fs::path graph = write_graph(
      dir,
      small_graph(
          R"(      { "id": "save_png", "type": "WriteHeightfield", "inputs": { "in": "noise.out" }, "params": { "path": "h.png" } },
      { "id": "save_raw", "type": "WriteHeightfield", "inputs": { "in": "noise.out" },
        "params": { "path": "h.raw", "range": "fixed", "height_min": -60, "height_max": 60 } }
  )"));
  const fs::path out = dir / "out";
  auto r = orogen({"eval", graph.string(), "-o", out.string(), "--tiles", "2x2", "--merge"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--merge: 'save_png' writes 16-bit heights with range 'auto'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("set range 'fixed'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("'save_raw'"), std::string::npos) << r.err;  // a fixed range merges
  EXPECT_FALSE(fs::exists(out));
  r = orogen({"eval", graph.string(), "-o", out.string(), "--merge"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--merge joins the files of every tile: it needs --tiles NxM"), std::string::npos) << r.err;
  r = orogen({"eval", graph.string(), "-o", out.string(), "--tiles", "2x2", "--tile", "0,0", "--merge"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace orogen::test
