// The seed graphs built on 1 to 4 MPI ranks (issue 24): `mpirun -n R orogen eval G --tiles NxM` must give the
// terrain one process gives. Every float raster, 16-bit height with a fixed range and image, put together from the
// ranks' tiles, equals the untiled single-process file bit for bit; points equal as sets (a point on a line of samples
// two tiles share is in both tiles' files; PoissonDisk with fill_border, ForestLifeCycle and ShadePlacement are
// computed on the whole domain and each tile gets the points inside it); curves computed whole (a replicated
// RiverNetwork) are the untiled file in every tile. 16-bit heights with `range: auto` map each tile over its own range,
// so both builds write them as float EXR instead (`--set ID.path=...exr`); meshes and scenes are per tile by design
// (docs/distributed.md, "Outputs"). The nodes that run across the tiles must say so in the build's stage lines (a
// fallback to the whole domain would give the same files). Small domains (129^2) keep CI short.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "nodes/io/heightfield_file.h"
#include "support/distributed_builds.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

const std::string kMpiexec = OROGEN_MPIEXEC;  // empty: built without MPI

// The tiles of `rel` under `dir` against the untiled raster `whole`, every channel, bit for bit; the number of
// differing samples (a tile whose window is not the tiling's fails the test, its samples all differing).
std::size_t differing_samples(const fs::path& whole, const fs::path& dir, const fs::path& rel, glm::ivec2 tiles) {
  const int channels = probe_height_raster(whole).channels;
  std::size_t differing = 0;
  for (int c = 0; c < channels; ++c) {
    const FloatRaster full = read_float_raster(whole, c);
    const FloatRaster joined = stitch(dir, rel, tiles, {full.width, full.height}, c);
    for (std::size_t k = 0; k < full.values.size(); ++k)
      differing += std::memcmp(&full.values[k], &joined.values[k], sizeof(float)) != 0;
  }
  return differing;
}

// The lines of a CSV file after its header.
std::set<std::string> csv_rows(const fs::path& file, std::size_t* count = nullptr) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::set<std::string> rows;
  while (std::getline(in, line)) {
    rows.insert(line);
    if (count) ++*count;
  }
  return rows;
}

// `--set ID.path=STEM.exr` for every 16-bit height writer of the graph with an automatic range.
std::vector<std::string> float_heights(const fs::path& graph) {
  const auto doc = nlohmann::json::parse(file_bytes(graph));
  std::vector<std::string> args;
  for (const auto& node : doc.at("nodes")) {
    if (node.value("type", "") != "WriteHeightfield" || !node.contains("params")) continue;
    const auto& params = node.at("params");
    const fs::path path = params.value("path", "");
    const std::string ext = path.extension().string();
    if ((ext == ".png" || ext == ".raw" || ext == ".r16") && params.value("range", "auto") == "auto")
      args.insert(args.end(),
                  {"--set", node.at("id").get<std::string>() + ".path=" + path.parent_path().string() +
                                (path.has_parent_path() ? "/" : "") + path.stem().string() + "_heights.exr"});
  }
  return args;
}

struct SeedJob {
  const char* graph;
  glm::ivec2 tiles;
  int ranks;
};

// The nodes of each seed graph that run across the ranks' tiles (each build's stage line names them), so a fallback
// to the whole domain fails the test: erosion, clustering, drainage figures, flow accumulation, lakes, flood fill,
// water flow and sunlight.
// forest.json and seamscape.json have none.
const std::map<std::string, std::vector<std::string>> kAcross = {
    {"eroded_mountains.json",
     {"'metrics' (DrainageMetrics)", "'metrics_stream_power' (DrainageMetrics)", "'range/detail' (HydraulicErosion)"}},
    {"game_world.json", {"'hydraulic' (HydraulicErosion)", "'thermal' (ThermalErosion)"}},
    {"rural_resources.json",
     {"'clusters' (KMeansClusters)", "'flow' (FlowAccumulation)", "'lake' (FloodFill)", "'lakes' (Lakes)",
      "'water' (WaterFlow)", "'sun' (SunIllumination)"}},
    {"voronoi_island.json", {"'island/eroded' (PipeErosion)"}},
};

TEST(DistributedSeedGraphs, EverySeedGraphOnOneToFourRanksEqualsOneProcess) {
  if (kMpiexec.empty()) GTEST_SKIP() << "orogen was built without MPI (OROGEN_MPI off): distributed builds untested";
  const std::vector<SeedJob> jobs = {
      {"eroded_mountains.json", {2, 2}, 4}, {"eroded_mountains.json", {3, 2}, 1}, {"game_world.json", {2, 2}, 2},
      {"game_world.json", {3, 2}, 3},       {"rural_resources.json", {2, 2}, 3},  {"rural_resources.json", {3, 2}, 4},
      {"voronoi_island.json", {2, 2}, 1},   {"voronoi_island.json", {3, 2}, 2},   {"forest.json", {2, 2}, 4},
      {"forest.json", {3, 2}, 3},           {"seamscape.json", {2, 2}, 2},        {"seamscape.json", {3, 2}, 4},
  };
  std::map<std::string, fs::path> untiled;
  for (const SeedJob& job : jobs) {
    const std::string label = std::string(job.graph) + " " + tiles_text(job.tiles) + " on " +
                              std::to_string(job.ranks) + (job.ranks == 1 ? " rank" : " ranks");
    SCOPED_TRACE(label);
    const fs::path graph = source_dir() / "graphs" / job.graph;
    const std::vector<std::string> overrides = float_heights(graph);
    if (!untiled.count(job.graph)) {
      const fs::path dir = scratch_dir("seed-untiled");
      std::vector<std::string> args = {"eval", graph.string(), "-o", dir.string(), "--resolution", "129", "-q"};
      args.insert(args.end(), overrides.begin(), overrides.end());
      const auto r = run_process(cli_binary(), args);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      untiled[job.graph] = dir;
    }
    const fs::path whole = untiled[job.graph];
    const fs::path dir = scratch_dir("seed-distributed");
    std::vector<std::string> args = {"eval",         graph.string(), "-o",      dir.string(),
                                     "--resolution", "129",          "--tiles", tiles_text(job.tiles)};
    args.insert(args.end(), overrides.begin(), overrides.end());
    const auto r = mpirun(kMpiexec, job.ranks, args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (const auto it = kAcross.find(job.graph); it != kAcross.end()) {
      for (const std::string& node : it->second) {
        EXPECT_NE(r.err.find("node " + node + " computed across the tiles"), std::string::npos) << r.err;
      }
    }
    std::size_t rasters = 0, point_files = 0, curve_files = 0;
    for (const auto& f : fs::recursive_directory_iterator(whole)) {
      if (!f.is_regular_file()) continue;
      const fs::path rel = fs::relative(f.path(), whole);
      const std::string ext = rel.extension().string();
      SCOPED_TRACE(rel.generic_string());
      if (ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".png") {
        EXPECT_EQ(differing_samples(f.path(), dir, rel, job.tiles), 0u);
        ++rasters;
      } else if (ext == ".csv") {
        std::set<std::string> joined;
        for (int j = 0; j < job.tiles.y; ++j)
          for (int i = 0; i < job.tiles.x; ++i) {
            const auto rows = csv_rows(tile_file(dir, rel, i, j));
            joined.insert(rows.begin(), rows.end());
          }
        std::size_t count = 0;
        EXPECT_TRUE(joined == csv_rows(f.path(), &count)) << joined.size() << " distinct points in the tiles";
        EXPECT_EQ(count, joined.size()) << "the untiled file repeats a point";
        ++point_files;
      } else if (ext == ".json" && rel.stem().extension().empty()) {  // curves, not a PNG's side file
        const std::string bytes = file_bytes(f.path());
        for (int j = 0; j < job.tiles.y; ++j)
          for (int i = 0; i < job.tiles.x; ++i)
            EXPECT_TRUE(file_bytes(tile_file(dir, rel, i, j)) == bytes) << "tile " << i << "," << j;
        ++curve_files;
      }
    }
    std::cerr << label << ": " << rasters << " rasters, " << point_files << " point files, " << curve_files
              << " curve files compared\n";
    EXPECT_GT(rasters, 0u);
  }
}

}  // namespace
}  // namespace orogen::test
