// End-to-end tests of distributed builds (docs/distributed.md): `mpirun -n R orogen eval G --tiles NxM` spreads
// the tiles over R ranks and must write, for any R, exactly the files of the single-process tiled build, whose
// rasters are in turn the windows of the untiled build. Skipped, with a message, when orogen was built without
// MPI (OROGEN_MPI off). The launcher is run with the environment that lets Open MPI run as root (CI) and place
// more ranks than cores.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <glm/vec2.hpp>

#include "nodes/io/heightfield_file.h"
#include "support/distributed_builds.h"
#include "support/run_process.h"
#include "support/test_paths.h"
#include "support/tile_windows.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

const std::string kMpiexec = OROGEN_MPIEXEC;  // empty: built without MPI

#define SKIP_WITHOUT_MPI() \
  if (kMpiexec.empty()) GTEST_SKIP() << "orogen was built without MPI (OROGEN_MPI off): distributed builds untested"

ProcessResult orogen(const std::vector<std::string>& args) { return run_process(cli_binary(), args); }

// Every file under `dir`, by relative path.
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.is_regular_file()) files[fs::relative(f.path(), dir).generic_string()] = file_bytes(f.path());
  return files;
}

struct Job {
  const char* graph;  // under graphs/
  int resolution;
  glm::ivec2 tiles;
  int ranks;
};

// The outputs of `graph` at `resolution`: untiled in one process, and per tiling in one process (cached).
struct SingleProcess {
  fs::path untiled;
  std::map<std::string, fs::path> tiled;  // by "NxM"
};

const fs::path& single_process_build(const Job& job) {
  static std::map<std::string, fs::path> built;
  const std::string key = std::string(job.graph) + "@" + std::to_string(job.resolution) + "/" + tiles_text(job.tiles);
  if (auto it = built.find(key); it != built.end()) return it->second;
  const fs::path dir = scratch_dir("distributed-single");
  std::vector<std::string> args = {"eval",         (source_dir() / "graphs" / job.graph).string(),
                                   "-o",           dir.string(),
                                   "--resolution", std::to_string(job.resolution),
                                   "--quiet"};
  if (job.tiles != glm::ivec2(0)) args.insert(args.end(), {"--tiles", tiles_text(job.tiles)});
  const auto r = orogen(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return built[key] = dir;
}

// On more than one rank, each stage's line gives the fewest and the most time any rank spent in its tiles, with
// rank 0's own in between; on one rank there is nothing to compare.
void expect_every_ranks_tile_time(const std::string& err, int ranks) {
  static const std::regex stage(R"(computed across the tiles in [0-9.]+ ms: inputs [0-9]+ ms, tiles ([0-9]+) ms)"
                                R"(( \(the ranks ([0-9]+) to ([0-9]+) ms\))?)");
  int lines = 0;
  for (auto m = std::sregex_iterator(err.begin(), err.end(), stage); m != std::sregex_iterator(); ++m, ++lines) {
    const auto& match = *m;
    ASSERT_EQ(match[2].matched, ranks > 1) << match.str();
    if (ranks == 1) continue;
    const long long own = std::stoll(match[1]), fewest = std::stoll(match[3]), most = std::stoll(match[4]);
    EXPECT_LE(fewest, own) << match.str();
    EXPECT_LE(own, most) << match.str();
  }
  int stages = 0;
  for (auto at = err.find("computed across the tiles in"); at != std::string::npos;
       at = err.find("computed across the tiles in", at + 1))
    ++stages;
  EXPECT_EQ(lines, stages) << "every stage line gives its times as above:\n" << err;
}

// Runs `job` on its ranks and checks its files equal the single-process tiled build's, byte for byte.
fs::path run_distributed(const Job& job) {
  const fs::path dir = scratch_dir("distributed-mpi");
  const auto r = mpirun(kMpiexec, job.ranks,
                        {"eval", (source_dir() / "graphs" / job.graph).string(), "-o", dir.string(), "--resolution",
                         std::to_string(job.resolution), "--tiles", tiles_text(job.tiles)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The nodes of each test graph that run across the ranks' tiles, not on the whole domain: FillDepressions with
  // epsilon flats and carving, FlowDirection with filling, D8 and MFD FlowAccumulation (hydrology.json's 'flow' is MFD)
  // and Watersheds (perimeter rounds, a ring of the filled surface, counts and outlets through perimeter links, MFD
  // shares in rounds); RiverExtract (every tile gets the whole joined network, compared below), Lakes and
  // DrainageMetrics; FloodFill; the erosion nodes.
  static const std::map<std::string, std::vector<std::string>> across = {
      {"distributed_hydrology.json",
       {"'filled' (FillDepressions)", "'direction' (FlowDirection)", "'flow_d8' (FlowAccumulation)",
        "'flow_mfd' (FlowAccumulation)", "'basins_id' (Watersheds)"}},
      {"../bench/distributed_carve.json", {"'carved' (FillDepressions)", "'carved_flat' (FillDepressions)"}},
      {"hydrology.json",
       {"'filled' (FillDepressions)", "'flow' (FlowAccumulation)", "'rivers' (RiverExtract)", "'lakes' (Lakes)",
        "'metrics' (DrainageMetrics)"}},
      {"../bench/distributed_flood.json", {"'lake' (FloodFill)", "'flood' (FloodFill)"}},
      {"../bench/distributed_thermal.json", {"'thermal' (ThermalErosion)"}},
      {"../bench/distributed_particles.json", {"'droplets' (HydraulicErosion)"}},
      {"../bench/distributed_pipe.json", {"'storm' (PipeErosion)"}},
      {"../bench/distributed_kmeans.json", {"'clusters' (KMeansClusters)"}},
      {"../bench/distributed_stream_power.json", {"'landscape' (StreamPower)"}},
      {"../bench/distributed_water_flow.json", {"'water' (WaterFlow)"}},
      {"../bench/distributed_sun.json", {"'sun' (SunIllumination)", "'sun_south' (SunIllumination)"}},
  };
  if (const auto it = across.find(job.graph); it != across.end() && job.tiles.x * job.tiles.y > 1) {
    for (const std::string& node : it->second) {
      EXPECT_NE(r.err.find("node " + node + " computed across the tiles"), std::string::npos) << r.err;
    }
  }
  expect_every_ranks_tile_time(r.err, job.ranks);
  const std::string graph = job.graph;
  if ((graph == "../bench/distributed_flood.json" || graph == "../bench/distributed_shade.json") &&
      job.tiles.x * job.tiles.y > 1) {
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << "nothing is computed on the whole domain:\n" << r.err;
  }
  const auto mine = files_under(dir), single = files_under(single_process_build(job));
  EXPECT_EQ(mine.size(), single.size());
  std::size_t differing = 0;
  for (const auto& [name, bytes] : single) {
    const auto it = mine.find(name);
    if (it == mine.end() || it->second != bytes) {
      ++differing;
      ADD_FAILURE() << name << (it == mine.end() ? " missing" : " differs");
    }
  }
  EXPECT_EQ(differing, 0u);
  return dir;
}

TEST(Distributed, RankGroupCollectivesOnTwoThreeAndFourRanks) {
  SKIP_WITHOUT_MPI();
  for (int ranks : {2, 3, 4}) {
    allow_launcher();
    const auto r = run_process(kMpiexec, {"-n", std::to_string(ranks), OROGEN_RANK_GROUP_CHECK});
    EXPECT_EQ(r.exit_code, 0) << ranks << " ranks: " << r.err;
  }
}

TEST(Distributed, AnyRankCountWritesTheSingleProcessTilesAndTheyJoinIntoTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  const std::vector<Job> jobs = {
      {"distributed_hydrology.json", 129, {1, 1}, 1},
      {"distributed_hydrology.json", 129, {2, 2}, 1},
      {"distributed_hydrology.json", 129, {2, 2}, 2},
      {"distributed_hydrology.json", 129, {2, 2}, 3},
      {"distributed_hydrology.json", 129, {2, 2}, 4},
      {"distributed_hydrology.json", 129, {3, 2}, 4},
      {"distributed_hydrology.json", 129, {4, 3}, 3},
      {"hydrology.json", 129, {3, 2}, 2},
      {"hydrology.json", 129, {2, 2}, 4},
      {"terrain.json", 129, {3, 2}, 3},
  };
  for (const Job& job : jobs) {
    SCOPED_TRACE(std::string(job.graph) + " " + tiles_text(job.tiles) + " on " + std::to_string(job.ranks) + " ranks");
    const fs::path dir = run_distributed(job);
    // Every float raster of the untiled build, put together from the tiles, bit for bit.
    const fs::path& untiled = single_process_build({job.graph, job.resolution, {0, 0}, 1});
    std::size_t compared = 0;
    for (const auto& f : fs::recursive_directory_iterator(untiled)) {
      if (f.path().extension() != ".exr" && f.path().extension() != ".tif") continue;
      if (read_height_raster(f.path()).channels != 1) continue;
      const auto rel = fs::relative(f.path(), untiled);
      const FloatRaster whole = read_float_raster(f.path());
      const FloatRaster joined = stitch(dir, rel, job.tiles, {whole.width, whole.height});
      EXPECT_TRUE(same_bits(whole, joined)) << rel.generic_string();
      ++compared;
    }
    EXPECT_GT(compared, 0u);
    // Curves: every tile's file is the untiled build's (RiverExtract's network joined across the tiles).
    std::size_t curve_files = 0;
    for (const auto& f : fs::recursive_directory_iterator(untiled)) {
      if (f.path().extension() != ".json" || f.path().filename().string().find("rivers") == std::string::npos) continue;
      const auto rel = fs::relative(f.path(), untiled);
      for (int tj = 0; tj < job.tiles.y; ++tj)
        for (int ti = 0; ti < job.tiles.x; ++ti) {
          const fs::path tile = tile_file(dir, rel, ti, tj);
          EXPECT_EQ(file_bytes(tile), file_bytes(f.path())) << tile;
        }
      ++curve_files;
    }
    if (std::string(job.graph) == "hydrology.json") {
      EXPECT_GT(curve_files, 0u) << "no rivers curve file compared";
    }
  }
}

TEST(Distributed, OneRankWithoutTilesIsThePlainBuild) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = scratch_dir("distributed-one");
  const auto r = mpirun(kMpiexec, 1,
                        {"eval", (source_dir() / "graphs" / "distributed_hydrology.json").string(), "-o", dir.string(),
                         "--resolution", "129"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(files_under(dir), files_under(single_process_build({"distributed_hydrology.json", 129, {0, 0}, 1})));
}

// The test graph's shapes, checked on the joined tiles of a 3x2 build on 4 ranks: one lake across three tiles,
// an exactly flat plateau on the corner of four tiles of 2x2; no undrained cell after filling (either mode); D8
// accumulation (computed across the tiles) at every outlet exactly the area whose D8 paths end there.
TEST(Distributed, HydrologyAcrossTilesDrainsEveryCellAndConservesArea) {
  SKIP_WITHOUT_MPI();
  const int n = 129;
  const glm::ivec2 tiles{3, 2};
  const fs::path dir = run_distributed({"distributed_hydrology.json", n, tiles, 4}) / "distributed_hydrology";
  const auto joined = [&](const std::string& name) { return stitch(dir, name + ".tif", tiles, {n, n}); };
  const FloatRaster height = joined("height"), depth = joined("depth"), direction = joined("direction");
  const FloatRaster flow = joined("flow_d8");

  // The lake: depth > 0 in each of the three lower tiles of 3x2, connected through lake cells.
  {
    std::vector<char> seen(depth.values.size(), 0);
    int start = -1;
    for (int i = 0; i < n && start < 0; ++i)
      if (depth.at(i, n / 4) > 0.0f) start = n / 4 * n + i;
    ASSERT_GE(start, 0) << "no lake along y = 1/4";
    std::deque<int> queue{start};
    seen[static_cast<std::size_t>(start)] = 1;
    std::array<bool, 3> tiles_reached{};
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      const int i = c % n, j = c / n;
      if (j < edge(1, n, 2)) tiles_reached[static_cast<std::size_t>(std::min(2, i * 3 / (n - 1)))] = true;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= n || y >= n || seen[static_cast<std::size_t>(y * n + x)] || !(depth.at(x, y) > 0))
            continue;
          seen[static_cast<std::size_t>(y * n + x)] = 1;
          queue.push_back(y * n + x);
        }
    }
    EXPECT_TRUE(tiles_reached[0] && tiles_reached[1] && tiles_reached[2]) << "the lake must span three tiles";
  }
  // The plateau: exactly 110 m on both sides of the 2x2 tile borders at the centre.
  const int c = edge(1, n, 2);
  for (const auto& [di, dj] : {std::pair{-2, -2}, {2, -2}, {-2, 2}, {2, 2}})
    EXPECT_EQ(height.at(c + di, c + dj), 110.0f);

  // Drained: from the border, climbing (never descending) reaches every cell of the filled terrain.
  for (const char* name : {"filled", "filled_flat"}) {
    const FloatRaster filled = joined(name);
    std::vector<char> reached(filled.values.size(), 0);
    std::deque<int> queue;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (i == 0 || j == 0 || i == n - 1 || j == n - 1)
          reached[static_cast<std::size_t>(j * n + i)] = 1, queue.push_back(j * n + i);
    while (!queue.empty()) {
      const int k = queue.front();
      queue.pop_front();
      const int i = k % n, j = k / n;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= n || y >= n || reached[static_cast<std::size_t>(y * n + x)] ||
              filled.at(x, y) < filled.at(i, j))
            continue;
          reached[static_cast<std::size_t>(y * n + x)] = 1;
          queue.push_back(y * n + x);
        }
    }
    EXPECT_EQ(std::count(reached.begin(), reached.end(), 0), 0) << name << ": undrained cells";
  }

  // Area: follow each cell's D8 direction to its outlet (-1: nothing drains on, the border); the accumulation
  // there is the number of cells that end there times one cell's area (the smallest accumulation), exactly.
  const float cell_area = *std::min_element(flow.values.begin(), flow.values.end());
  std::vector<long long> draining(flow.values.size(), 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int x = i, y = j;
      for (int steps = 0; direction.at(x, y) >= 0.0f; ++steps) {
        ASSERT_LT(steps, n * n) << "a D8 path loops";
        const double a = direction.at(x, y) * std::numbers::pi / 180.0;
        x += static_cast<int>(std::lround(std::cos(a))), y += static_cast<int>(std::lround(std::sin(a)));
        ASSERT_TRUE(x >= 0 && y >= 0 && x < n && y < n);
      }
      ++draining[static_cast<std::size_t>(y * n + x)];
    }
  long long outlets = 0, total = 0;
  for (std::size_t k = 0; k < draining.size(); ++k) {
    if (draining[k] == 0) continue;
    ++outlets;
    total += draining[k];
    EXPECT_EQ(flow.values[k], static_cast<float>(static_cast<double>(draining[k]) * cell_area))
        << "outlet " << k % n << "," << k / n;
  }
  EXPECT_EQ(total, static_cast<long long>(n) * n);
  EXPECT_GT(outlets, 4);
}

TEST(Distributed, TheMosaicOpensInGdalAsTheUntiledRaster) {
  SKIP_WITHOUT_MPI();
  const fs::path gdal_translate = "/usr/bin/gdal_translate";
  if (!fs::exists(gdal_translate)) GTEST_SKIP() << "gdal-bin is not installed";
  const fs::path dir = run_distributed({"distributed_hydrology.json", 129, {4, 3}, 3});
  const fs::path& untiled = single_process_build({"distributed_hydrology.json", 129, {0, 0}, 1});
  for (const char* name : {"height", "flow_mfd", "watersheds"}) {
    SCOPED_TRACE(name);
    const fs::path vrt = dir / "distributed_hydrology" / (std::string(name) + ".vrt");
    ASSERT_TRUE(fs::exists(vrt));
    const fs::path whole = dir / (std::string(name) + "_from_vrt.tif");
    const auto r = run_process(gdal_translate, {"-q", vrt.string(), whole.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(same_bits(read_float_raster(whole),
                          read_float_raster(untiled / "distributed_hydrology" / (std::string(name) + ".tif"))));
  }
}

TEST(Distributed, BadRankCountsAreRefusedBeforeAnythingRuns) {
  SKIP_WITHOUT_MPI();
  const std::string graph = (source_dir() / "graphs" / "distributed_hydrology.json").string();
  const fs::path dir = scratch_dir("distributed-bad");
  auto r = mpirun(kMpiexec, 4, {"eval", graph, "-o", dir.string(), "--resolution", "129", "--tiles", "1x2"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("has only 2 tiles, so 2 ranks would have none"), std::string::npos) << r.err;
  r = mpirun(kMpiexec, 2, {"eval", graph, "-o", dir.string(), "--resolution", "129"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("add --tiles NxM"), std::string::npos) << r.err;
  r = mpirun(kMpiexec, 2,
             {"eval", graph, "-o", dir.string(), "--resolution", "129", "--tiles", "2x2", "--tile", "0,0"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--tile builds one tile in one process"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "distributed_hydrology"));
}

// Across the tiles a rank holds the state of all its tiles at once: a --max-memory (per rank) that fits four tiles
// but not sixteen refuses the one-process build up front, naming the ranks that would do, and lets four ranks build.
TEST(Distributed, AMemoryLimitARankCannotMeetIsRefusedNamingTheRanksThatWould) {
  SKIP_WITHOUT_MPI();
  const std::string graph = (source_dir() / "graphs" / "distributed_hydrology.json").string();
  const fs::path dir = scratch_dir("distributed-memory");
  const std::vector<std::string> args = {"eval",         graph,  "-o",      (dir / "out").string(),
                                         "--resolution", "129",  "--tiles", "4x4",
                                         "--max-memory", "400K", "--quiet"};
  const auto one = orogen(args);
  EXPECT_EQ(one.exit_code, 2) << one.err;
  EXPECT_NE(one.err.find("node 'filled' runs across the tiles, and a rank holds its state for all of its tiles at "
                         "once: 16 tiles"),
            std::string::npos)
      << one.err;
  EXPECT_NE(one.err.find("run it on 4 ranks or more"), std::string::npos) << one.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "distributed_hydrology"));
  const auto four = mpirun(kMpiexec, 4, args);
  EXPECT_EQ(four.exit_code, 0) << four.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "distributed_hydrology"));
}

TEST(Distributed, AFailingRankStopsTheJobNamingRankTileAndNode) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = scratch_dir("distributed-fail");
  // A directory where tile 2,1's height file goes: its writer fails on rank 2 of 3 (tiles 4 and 5).
  fs::create_directories(dir / "distributed_hydrology" / "height_x2_y1.tif");
  const auto r = mpirun(kMpiexec, 3,
                        {"eval", (source_dir() / "graphs" / "distributed_hydrology.json").string(), "-o", dir.string(),
                         "--resolution", "129", "--tiles", "3x2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("rank 2: tile 2,1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("node 'save_height' failed"), std::string::npos) << r.err;
}

TEST(Distributed, ARerunWithTheSameCacheRecomputesOnlyTheUnfinishedTiles) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = scratch_dir("distributed-rerun");
  const fs::path blocker = dir / "out" / "distributed_hydrology" / "height_x2_y1.tif";
  fs::create_directories(blocker);
  const std::vector<std::string> args = {"eval",
                                         (source_dir() / "graphs" / "distributed_hydrology.json").string(),
                                         "-o",
                                         (dir / "out").string(),
                                         "--resolution",
                                         "129",
                                         "--tiles",
                                         "3x2",
                                         "--cache-dir",
                                         (dir / "cache").string(),
                                         "--stats",
                                         (dir / "stats.json").string(),
                                         "-q"};
  ASSERT_EQ(mpirun(kMpiexec, 3, args).exit_code, 1);
  // The tiles that finished before the job stopped wrote their stats (the failed one's and the stopped ones' too).
  const auto statuses = [&](const std::string& name) {
    std::map<std::string, std::string> s;
    const auto doc = nlohmann::json::parse(file_bytes(dir / name));
    for (const auto& [id, node] : doc["nodes"].items()) s[id] = node["status"].get<std::string>();
    return s;
  };
  std::vector<std::string> finished;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      const auto name = "stats_x" + std::to_string(i) + "_y" + std::to_string(j) + ".json";
      if (!fs::exists(dir / name)) continue;
      const auto s = statuses(name);
      const bool failed = std::any_of(s.begin(), s.end(), [](const auto& e) { return e.second == "failed"; });
      EXPECT_EQ(failed, name == "stats_x2_y1.json") << name;
      // Tiles stopped by the job's end show their unfinished nodes as cancelled.
      if (std::all_of(s.begin(), s.end(), [](const auto& e) { return e.second == "computed" || e.second == "cached"; }))
        finished.push_back(name);
    }
  EXPECT_FALSE(finished.empty());
  fs::remove(blocker);
  const auto r = mpirun(kMpiexec, 3, args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto computed = [&](const std::string& name) {
    std::string ids;
    for (const auto& [id, status] : statuses(name))
      if (status == "computed") ids += (ids.empty() ? "" : ", ") + id;
    return ids;
  };
  for (const auto& name : finished) EXPECT_EQ(computed(name), "") << name << " was finished, and cached";
  EXPECT_NE(computed("stats_x2_y1.json").find("save_height"), std::string::npos) << "the failed tile writes now";
}

// --merge across ranks: rank 0 streams the tiles every rank wrote into one file per raster, the untiled build's
// bytes; and the ranks name their tiles as --tile-naming says, as the single-process tiled build does.
TEST(Distributed, MergedFilesAndNamedTilesEqualTheSingleProcessBuilds) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = scratch_dir("distributed-merge");
  const std::string graph = (source_dir() / "graphs" / "distributed_hydrology.json").string();
  const std::vector<std::string> size = {"--resolution", "97"};
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin() + 1, size.begin(), size.end());
    return args;
  };
  ASSERT_EQ(orogen(run({"eval", graph, "-o", (dir / "whole").string(), "-q"})).exit_code, 0);
  auto r = mpirun(kMpiexec, 3,
                  run({"eval", graph, "-o", (dir / "merged").string(), "--tiles", "3x2", "--tile-naming", "unreal",
                       "--merge", "-q"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(files_under(dir / "merged"), files_under(dir / "whole"));
  const std::vector<std::string> tiled = {"--tiles", "3x2", "--tile-naming", "unreal", "-q"};
  auto one = run({"eval", graph, "-o", (dir / "one").string()});
  auto three = run({"eval", graph, "-o", (dir / "three").string()});
  one.insert(one.end(), tiled.begin(), tiled.end());
  three.insert(three.end(), tiled.begin(), tiled.end());
  ASSERT_EQ(orogen(one).exit_code, 0);
  ASSERT_EQ(mpirun(kMpiexec, 3, three).exit_code, 0);
  EXPECT_EQ(files_under(dir / "three"), files_under(dir / "one"));
  // hydrology.json: the rivers, joined across the ranks' tiles, merge into the untiled build's curve files (every
  // tile holds the whole network, so --merge writes it once), its mask and every other file too.
  // Its DrainageMetrics, across the ranks' tiles too, reports in every tile's statistics what the untiled build does.
  const std::string rivers = (source_dir() / "graphs" / "hydrology.json").string();
  fs::create_directories(dir / "stats");
  ASSERT_EQ(orogen(run({"eval", rivers, "-o", (dir / "rivers_whole").string(), "--stats",
                        (dir / "stats" / "whole.json").string(), "-q"}))
                .exit_code,
            0);
  r = mpirun(kMpiexec, 2,
             run({"eval", rivers, "-o", (dir / "rivers_merged").string(), "--tiles", "3x2", "--merge", "--stats",
                  (dir / "stats" / "tiled.json").string(), "-q"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(files_under(dir / "rivers_merged"), files_under(dir / "rivers_whole"));
  EXPECT_GT(file_bytes(dir / "rivers_whole" / "hydrology" / "rivers.json").size(), 1000u);
  const auto report = nlohmann::json::parse(file_bytes(dir / "stats" / "whole.json"))["reports"];
  ASSERT_TRUE(report.contains("metrics")) << report.dump();
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      const fs::path tile = dir / "stats" / ("tiled_x" + std::to_string(i) + "_y" + std::to_string(j) + ".json");
      EXPECT_EQ(nlohmann::json::parse(file_bytes(tile))["reports"], report) << tile;
    }
}

// `graph` (under bench/) on every tiling and rank count of `jobs`: the single-process tiled build's files
// (run_distributed), and every raster `names` of the untiled build (under its folder `stem`), put together from the
// ranks' tiles, bit for bit (each of `channels` of a multi-channel image).
void expect_ranks_equal_untiled(const std::string& graph, const std::string& stem,
                                const std::vector<std::string>& names,
                                const std::vector<std::pair<glm::ivec2, int>>& jobs,
                                const std::vector<int>& channels = {0}) {
  const std::string path = "../bench/" + graph;  // resolved under graphs/
  const fs::path& untiled = single_process_build({path.c_str(), 129, {0, 0}, 1});
  for (const auto& [tiles, ranks] : jobs) {
    const Job job{path.c_str(), 129, tiles, ranks};
    SCOPED_TRACE(tiles_text(job.tiles) + " on " + std::to_string(job.ranks) + " ranks");
    const fs::path dir = run_distributed(job);
    for (const std::string& name : names)
      for (const int channel : channels) {
        const FloatRaster whole = read_float_raster(untiled / stem / (name + ".tif"), channel);
        EXPECT_TRUE(
            same_bits(whole, stitch(dir, stem + "/" + name + ".tif", job.tiles, {whole.width, whole.height}, channel)))
            << name << " channel " << channel;
      }
  }
}

// ThermalErosion across the ranks' tiles, its halos exchanged every few iterations (bench/distributed_thermal.json: fBm
// with mask and hardness linked, every output written, and a blur downstream whose halo comes from the neighboring
// ranks' tiles).
TEST(Distributed, ThermalErosionAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_thermal.json", "distributed_thermal",
                             {"height", "erosion", "deposition", "flow", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{2, 2}, 3}});
}

// HydraulicErosion across the ranks' tiles, the whole-domain droplet schedule's phases with the changed samples
// exchanged between them (bench/distributed_particles.json: fBm with a mask linked, every output written, a blur
// downstream).
TEST(Distributed, HydraulicErosionAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_particles.json", "distributed_particles",
                             {"height", "erosion", "deposition", "flow", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{4, 3}, 3}});
}

// FloodFill across the ranks' tiles (bench/distributed_flood.json: a lake filled to its spill level from the middle of
// a bowl over the tiles' corner, a flood to a given level along a trench, and a blur of the lake whose halo comes from
// the neighboring ranks' tiles).
TEST(Distributed, FloodFillAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  const fs::path& untiled = single_process_build({"../bench/distributed_flood.json", 129, {0, 0}, 1});
  // The lake and the flood span the tiles of every tiling below.
  const FloatRaster lake = read_float_raster(untiled / "distributed_flood" / "lake_mask.tif");
  const FloatRaster flood = read_float_raster(untiled / "distributed_flood" / "flood_depth.tif");
  EXPECT_EQ(lake.at(64, 64), 1.0f);  // on the corner of the 2x2 tiles
  std::array<std::size_t, 4> quadrants{};
  for (int j = 0; j < lake.height; ++j)
    for (int i = 0; i < lake.width; ++i) quadrants[(j < 64 ? 0 : 2) + (i < 64 ? 0 : 1)] += lake.at(i, j) > 0.0f;
  for (const std::size_t q : quadrants) EXPECT_GT(q, 100u);
  std::size_t flooded = 0;
  for (const float d : flood.values) flooded += d > 0.0f;
  EXPECT_GT(flooded, 200u);
  expect_ranks_equal_untiled("distributed_flood.json", "distributed_flood",
                             {"terrain", "lake", "lake_depth", "lake_mask", "flood_depth", "lake_smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{4, 3}, 3}});
}

// FillDepressions carving across the ranks' tiles (bench/distributed_carve.json: the bowl over the tiles' corner,
// deeper than max_depth, breached through its rim; shallow depressions kept as lakes; flat channels too; a blur
// downstream).
TEST(Distributed, CarvingAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  const fs::path& untiled = single_process_build({"../bench/distributed_carve.json", 129, {0, 0}, 1});
  const FloatRaster terrain = read_float_raster(untiled / "distributed_carve" / "terrain.tif");
  const FloatRaster carved = read_float_raster(untiled / "distributed_carve" / "carved.tif");
  std::array<std::size_t, 4> quadrants{};  // cells lowered, per quadrant of the 2x2 tiling
  for (int j = 0; j < carved.height; ++j)
    for (int i = 0; i < carved.width; ++i)
      quadrants[(j < 64 ? 0 : 2) + (i < 64 ? 0 : 1)] += carved.at(i, j) < terrain.at(i, j);
  EXPECT_GE(std::count_if(quadrants.begin(), quadrants.end(), [](std::size_t q) { return q > 0; }), 2)
      << "a channel must cross a tile border";
  const FloatRaster lakes = read_float_raster(untiled / "distributed_carve" / "lakes.tif");
  EXPECT_GT(*std::max_element(lakes.values.begin(), lakes.values.end()), 0.0f) << "shallow depressions are kept";
  expect_ranks_equal_untiled("distributed_carve.json", "distributed_carve",
                             {"carved", "lakes", "carved_flat", "carved_smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{4, 3}, 3}});
}

// PipeErosion across the ranks' tiles, a 2-sample halo exchanged every step and the step from the deepest water over
// all tiles (bench/distributed_pipe.json: fBm with sea below -60 m, Drops rain driven by a moisture field, an
// evaporation field, every output written, and a blur downstream whose halo comes from the neighboring ranks' tiles).
TEST(Distributed, PipeErosionAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_pipe.json", "distributed_pipe",
                             {"height", "erosion", "deposition", "flow", "water", "velocity", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}});
}

// KMeansClusters across the ranks' tiles (bench/distributed_kmeans.json: slope and temperature of an fBm terrain, six
// clusters to convergence, the ids, their colors and a blur of the ids written): each rank tallies its tiles' cells,
// the exact sums add up to the whole domain's, so the ids equal the untiled build's bit for bit.
TEST(Distributed, KMeansAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_kmeans.json", "distributed_kmeans", {"cluster_id", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{4, 3}, 3}});
}

// StreamPower across the ranks' tiles, step by step (bench/distributed_stream_power.json: fBm with uplift and mask
// fields, 50 steps with the Priority-Flood fill, every output written, a blur downstream whose halo comes from the
// neighboring ranks' tiles).
TEST(Distributed, StreamPowerAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_stream_power.json", "distributed_stream_power",
                             {"height", "erosion", "deposition", "flow", "accumulation", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}, {{2, 2}, 3}});
}

// WaterFlow across the ranks' tiles, a 2-sample halo of water exchanged every iteration and the stop test from exact
// sums over all tiles (bench/distributed_water_flow.json: fBm with rainfall and sinks fields linked, depth and flux
// written, and a blur downstream whose halo comes from the neighboring ranks' tiles); every tile's statistics report
// the untiled build's water balance.
TEST(Distributed, WaterFlowAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_water_flow.json", "distributed_water_flow", {"depth", "flux", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 4}});
  const std::string graph = (source_dir() / "bench" / "distributed_water_flow.json").string();
  const fs::path dir = scratch_dir("distributed-water-flow");
  fs::create_directories(dir / "stats");
  ASSERT_EQ(orogen({"eval", graph, "-o", (dir / "whole").string(), "--resolution", "129", "--stats",
                    (dir / "stats" / "whole.json").string(), "-q"})
                .exit_code,
            0);
  const auto r = mpirun(kMpiexec, 4,
                        {"eval", graph, "-o", (dir / "tiled").string(), "--resolution", "129", "--tiles", "3x2",
                         "--stats", (dir / "stats" / "tiled.json").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(file_bytes(dir / "stats" / "whole.json"))["reports"];
  ASSERT_TRUE(report.contains("water")) << report.dump();
  EXPECT_GT(report["water"]["report"]["iterations"].get<int>(), 20);
  EXPECT_GT(report["water"]["report"]["sink_inflow_m3"].get<double>(), 0.0);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      const fs::path tile = dir / "stats" / ("tiled_x" + std::to_string(i) + "_y" + std::to_string(j) + ".json");
      EXPECT_EQ(nlohmann::json::parse(file_bytes(tile))["reports"], report) << tile;
    }
}

// SunIllumination across the ranks' tiles, each sun direction's sweep handing its lines' hulls from tile to tile
// (bench/distributed_sun.json: fBm hills under a low winter sun far north, all twelve months, and a southern winter
// morning every half hour for one month, every output written, and a blur of the lit mask downstream whose halo comes
// from the neighboring ranks' tiles). The monthly images channel by channel: January, June, September, December.
TEST(Distributed, SunIlluminationAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  const std::vector<std::pair<glm::ivec2, int>> jobs = {{{2, 2}, 2}, {{3, 2}, 4}};
  expect_ranks_equal_untiled(
      "distributed_sun.json", "distributed_sun",
      {"lit", "direct", "south_lit", "south_direct", "south_hours", "south_irradiance", "smooth"}, jobs);
  expect_ranks_equal_untiled("distributed_sun.json", "distributed_sun", {"hours", "irradiance"}, jobs, {0, 5, 8, 11});
}

// ShadePlacement with max_shadow_distance: per tile, each tile evaluated with the casters within that distance
// (bench/distributed_shade.json: trees and undergrowth by PoissonDisk on fBm ground under a low sun, the shadow map and
// a blur of it downstream written, and the shaded undergrowth). The maps bit for bit; the points as sets of lines (a
// point on a line of samples two tiles share is in both tiles' files).
TEST(Distributed, ShadePlacementWithABoundedShadowAcrossRanksEqualsTheUntiledBuild) {
  SKIP_WITHOUT_MPI();
  expect_ranks_equal_untiled("distributed_shade.json", "distributed_shade", {"shade", "smooth"},
                             {{{2, 2}, 2}, {{3, 2}, 3}});
  const auto lines = [](const std::vector<fs::path>& files) {
    std::set<std::string> out;
    for (const fs::path& f : files) {
      std::istringstream text(file_bytes(f));
      std::string line;
      std::getline(text, line);  // the header
      while (std::getline(text, line)) out.insert(line);
    }
    return out;
  };
  const fs::path untiled = single_process_build({"../bench/distributed_shade.json", 129, {0, 0}, 1});
  // The ranks' files are the single-process tiled build's, byte for byte (run_distributed).
  const fs::path tiled = single_process_build({"../bench/distributed_shade.json", 129, {3, 2}, 1});
  std::vector<fs::path> tiles;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) tiles.push_back(tile_file(tiled, "distributed_shade/undergrowth.csv", i, j));
  const auto whole = lines({untiled / "distributed_shade" / "undergrowth.csv"});
  EXPECT_GT(whole.size(), 500u);
  EXPECT_EQ(lines(tiles), whole);
}

}  // namespace
}  // namespace orogen::test
