// End-to-end tests of the `orogen` command: every example graph, exit codes, the output-path rule,
// overrides, statistics and the persistent cache across processes.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

ProcessResult orogen(const std::vector<std::string>& args) { return run_process(cli_binary(), args); }

// A small valid graph: a constant written to `path` as EXR.
std::string constant_graph(const std::string& path, double value = 5.0) {
  return R"({
  "format": "orogen-graph", "version": 1,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "flat", "type": "Constant", "params": { "value": )" +
         std::to_string(value) + R"( } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "flat.out" }, "params": { "path": ")" +
         path +
         R"(" } }
  ]
})";
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(read_text(p)); }

std::vector<fs::path> example_graphs() {
  std::vector<fs::path> graphs;
  for (const auto& entry : fs::directory_iterator(source_dir() / "graphs"))
    if (entry.path().extension() == ".json") graphs.push_back(entry.path());
  std::sort(graphs.begin(), graphs.end());
  return graphs;
}

TEST(Cli, EveryExampleGraphEvaluatesAndSecondRunIsEntirelyCached) {
  const auto graphs = example_graphs();
  ASSERT_FALSE(graphs.empty()) << "graphs/ has no example graphs";
  for (const auto& graph : graphs) {
    SCOPED_TRACE(graph.filename().string());
    const auto dir = scratch_dir("cli-example");
    const auto out = dir / "out", cache = dir / "cache";
    // Small (65^2): what is under test is that every node's result is cached, not the terrain.
    const std::vector<std::string> common = {"eval",       graph.string(), "--resolution", "65",      "-o",
                                             out.string(), "--cache-dir",  cache.string(), "--quiet", "--stats"};
    auto with_stats = [&](const char* file) {
      auto args = common;
      args.push_back((dir / file).string());
      return args;
    };
    auto first = orogen(with_stats("first.json"));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    EXPECT_TRUE(first.err.empty()) << "--quiet printed: " << first.err;
    const auto stats1 = read_json(dir / "first.json");
    EXPECT_TRUE(stats1["ok"].get<bool>());
    EXPECT_GT(stats1["totals"]["computed"].get<int>(), 0);
    // Every writer produced a non-empty file inside the output directory.
    std::size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(out))
      if (e.is_regular_file()) {
        ++files;
        EXPECT_GT(fs::file_size(e.path()), 0u) << e.path();
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << "temporary left: " << e.path();
      }
    EXPECT_GT(files, 0u);

    auto second = orogen(with_stats("second.json"));
    ASSERT_EQ(second.exit_code, 0) << second.err;
    const auto stats2 = read_json(dir / "second.json");
    for (const auto& [id, node] : stats2["nodes"].items())
      EXPECT_EQ(node["status"], "cached") << "node " << id << " was not cached on the second run";
    EXPECT_EQ(stats2["totals"]["computed"].get<int>(), 0);
  }
}

TEST(Cli, StatsReportStatusTimesBytesAndPeakMemory) {
  const auto dir = scratch_dir("cli-stats");
  write_text(dir / "g.json", constant_graph("flat.exr"));
  auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--stats",
                   (dir / "stats.json").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = read_json(dir / "stats.json");
  EXPECT_EQ(s["nodes"]["flat"]["status"], "computed");
  EXPECT_EQ(s["nodes"]["save"]["status"], "computed");
  EXPECT_GE(s["nodes"]["flat"]["output_bytes"].get<std::size_t>(), 16u * 16u * sizeof(float));
  EXPECT_GE(s["nodes"]["flat"]["milliseconds"].get<double>(), 0.0);
  EXPECT_GT(s["peak_memory_bytes"].get<std::size_t>(), 0u);
  EXPECT_EQ(s["totals"]["computed"].get<int>(), 2);
  EXPECT_TRUE(fs::exists(dir / "out" / "flat.exr"));
}

TEST(Cli, WithoutCacheDirASecondProcessRecomputes) {
  const auto dir = scratch_dir("cli-nocache");
  write_text(dir / "g.json", constant_graph("flat.exr"));
  for (int run = 0; run < 2; ++run) {
    auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--stats",
                     (dir / "stats.json").string(), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_json(dir / "stats.json")["nodes"]["flat"]["status"], "computed");
  }
}

TEST(Cli, DeletedOutputIsRewrittenFromTheCache) {
  const auto dir = scratch_dir("cli-deleted");
  write_text(dir / "g.json", constant_graph("flat.exr"));
  const std::vector<std::string> args = {
      "eval",        (dir / "g.json").string(), "-o",      (dir / "out").string(),
      "--cache-dir", (dir / "cache").string(),  "--stats", (dir / "stats.json").string(),
      "--quiet"};
  ASSERT_EQ(orogen(args).exit_code, 0);
  fs::remove(dir / "out" / "flat.exr");
  ASSERT_EQ(orogen(args).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "out" / "flat.exr"));
  const auto s = read_json(dir / "stats.json");
  EXPECT_EQ(s["nodes"]["flat"]["status"], "cached");
  EXPECT_EQ(s["nodes"]["save"]["status"], "computed");
}

TEST(Cli, InvalidGraphExitsTwoWithEveryProblem) {
  const auto dir = scratch_dir("cli-invalid");
  write_text(dir / "bad.json", R"({
  "format": "orogen-graph", "version": 6,
  "nodes": [
    { "id": "a", "type": "Constnt" },
    { "id": "b", "type": "Constant", "params": { "valu": 1 } }
  ]
})");
  auto r = orogen({"eval", (dir / "bad.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("Constnt"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Constant"), std::string::npos) << r.err;  // the suggestion
  EXPECT_NE(r.err.find("valu"), std::string::npos) << r.err;      // the second problem too
  EXPECT_FALSE(fs::exists(dir / "out"));

  auto v = orogen({"validate", (dir / "bad.json").string()});
  EXPECT_EQ(v.exit_code, 2);
  EXPECT_NE(v.err.find("/nodes/0"), std::string::npos) << v.err;

  auto missing = orogen({"validate", (dir / "nope.json").string()});
  EXPECT_EQ(missing.exit_code, 2);
}

TEST(Cli, ValidateAcceptsEveryExample) {
  for (const auto& graph : example_graphs()) {
    auto r = orogen({"validate", graph.string()});
    EXPECT_EQ(r.exit_code, 0) << graph << ": " << r.err;
    EXPECT_NE(r.out.find("valid"), std::string::npos);
  }
}

TEST(Cli, FailingNodeExitsOneAndReportsIt) {
  const auto dir = scratch_dir("cli-fail");
  // A file that exists but is no image fails when read (a missing one is refused before evaluating).
  write_text(dir / "height.exr", "not an image");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 1,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "missing", "type": "ReadHeightfield", "params": { "path": "height.exr" } },
    { "id": "save_missing", "type": "WriteHeightfield", "inputs": { "in": "missing.height" },
      "params": { "path": "a.exr" } },
    { "id": "flat", "type": "Constant" },
    { "id": "save_flat", "type": "WriteHeightfield", "inputs": { "in": "flat.out" }, "params": { "path": "b.exr" } }
  ]
})");
  auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--stats",
                   (dir / "stats.json").string(), "--quiet"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
  const auto s = read_json(dir / "stats.json");
  EXPECT_EQ(s["nodes"]["missing"]["status"], "failed");
  EXPECT_EQ(s["nodes"]["save_missing"]["status"], "skipped");
  EXPECT_EQ(s["nodes"]["save_flat"]["status"], "computed");  // the independent branch still finished
  EXPECT_TRUE(fs::exists(dir / "out" / "b.exr"));
  EXPECT_FALSE(fs::exists(dir / "out" / "a.exr"));
}

TEST(Cli, OutputPathRule) {
  const auto dir = scratch_dir("cli-paths");
  const auto outside = (dir / "outside.exr").string();
  write_text(dir / "abs.json", constant_graph(outside));
  write_text(dir / "climb.json", constant_graph("../escaped.exr"));

  auto abs = orogen({"eval", (dir / "abs.json").string(), "-o", (dir / "out").string(), "--quiet"});
  EXPECT_EQ(abs.exit_code, 2);
  EXPECT_NE(abs.err.find("absolute"), std::string::npos) << abs.err;
  EXPECT_FALSE(fs::exists(outside));

  auto climb = orogen({"eval", (dir / "climb.json").string(), "-o", (dir / "out").string(), "--quiet"});
  EXPECT_EQ(climb.exit_code, 2);
  EXPECT_NE(climb.err.find(".."), std::string::npos) << climb.err;
  EXPECT_FALSE(fs::exists(dir / "escaped.exr"));

  auto allowed =
      orogen({"eval", (dir / "abs.json").string(), "-o", (dir / "out").string(), "--quiet", "--allow-any-path"});
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
  EXPECT_TRUE(fs::exists(outside));
}

TEST(Cli, SetAndResolutionOverrides) {
  const auto dir = scratch_dir("cli-set");
  write_text(dir / "g.json", constant_graph("flat.exr"));
  auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--set", "flat.value=42",
                   "--resolution", "8x8", "--stats", (dir / "stats.json").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(dir / "stats.json")["nodes"]["flat"]["output_bytes"].get<std::size_t>() < 16u * 16u * 4u, true);

  auto bad_node = orogen({"eval", (dir / "g.json").string(), "--set", "nobody.value=1", "-o", (dir / "o2").string()});
  EXPECT_EQ(bad_node.exit_code, 2);
  EXPECT_NE(bad_node.err.find("nobody"), std::string::npos);
  auto bad_value =
      orogen({"eval", (dir / "g.json").string(), "--set", "flat.value=\"text\"", "-o", (dir / "o3").string()});
  EXPECT_EQ(bad_value.exit_code, 2);
  auto bad_syntax = orogen({"eval", (dir / "g.json").string(), "--set", "flatvalue", "-o", (dir / "o4").string()});
  EXPECT_EQ(bad_syntax.exit_code, 2);
  auto bad_res = orogen({"eval", (dir / "g.json").string(), "--resolution", "10x", "-o", (dir / "o5").string()});
  EXPECT_EQ(bad_res.exit_code, 2);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(orogen({}).exit_code, 2);
  EXPECT_EQ(orogen({"frobnicate"}).exit_code, 2);
  EXPECT_EQ(orogen({"eval"}).exit_code, 2);
  EXPECT_EQ(orogen({"eval", "x.json", "--threads", "-3"}).exit_code, 2);
}

TEST(Cli, HelpAndVersion) {
  auto v = orogen({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find(OROGEN_VERSION), std::string::npos);
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--help"}, {"eval", "--help"}, {"validate", "--help"}, {"nodes", "--help"}}) {
    auto h = orogen(args);
    EXPECT_EQ(h.exit_code, 0) << args[0];
    EXPECT_NE(h.out.find("Usage"), std::string::npos) << h.out;
  }
}

TEST(Cli, NodeReferenceComesFromTheRegistry) {
  auto list = orogen({"nodes"});
  ASSERT_EQ(list.exit_code, 0);
  EXPECT_NE(list.out.find("Constant"), std::string::npos);
  EXPECT_NE(list.out.find("WriteHeightfield"), std::string::npos);

  EXPECT_NE(list.out.find("Slope                 local"), std::string::npos) << list.out;
  EXPECT_NE(list.out.find("Normalize             global"), std::string::npos) << list.out;

  auto one = orogen({"nodes", "Constant"});
  ASSERT_EQ(one.exit_code, 0);
  EXPECT_NE(one.out.find("value"), std::string::npos);
  EXPECT_NE(one.out.find("Parameters"), std::string::npos);
  EXPECT_NE(one.out.find("Reach: point-wise"), std::string::npos) << one.out;
  EXPECT_NE(orogen({"nodes", "Blur"}).out.find("Reach: local: 5 sigma + 2 samples"), std::string::npos);
  // Every method of FlowAccumulation, weighted or not, runs across the tiles: no condition, no whole-domain case.
  const auto accumulation = orogen({"nodes", "FlowAccumulation"}).out;
  EXPECT_NE(accumulation.find("(runs across the tiles)"), std::string::npos) << accumulation;
  EXPECT_EQ(accumulation.find("otherwise computed on the whole domain"), std::string::npos) << accumulation;
  auto markdown = orogen({"nodes", "--markdown"});
  EXPECT_NE(markdown.out.find("### Slope"), std::string::npos);
  EXPECT_NE(markdown.out.find("Reach: local: 1 sample."), std::string::npos);

  auto json = orogen({"nodes", "--json"});
  ASSERT_EQ(json.exit_code, 0);
  const auto all = nlohmann::json::parse(json.out);
  ASSERT_TRUE(all.is_array());
  for (const auto& t : all) {
    EXPECT_FALSE(t["description"].get<std::string>().empty()) << t["name"];
    // Subgraph library assets come after the types, without a reach (their instances are expanded).
    if (t.value("type", "") != "Subgraph") {
      EXPECT_NE(t["reach"]["kind"], "undeclared") << t["name"];
    }
    if (t["name"] == "Slope") {
      EXPECT_EQ(t["reach"]["kind"], "local");
      EXPECT_EQ(t["reach"]["samples"], 1);
    }
    for (const auto& p : t["params"])
      EXPECT_FALSE(p["description"].get<std::string>().empty()) << t["name"] << "." << p["name"];
  }

  // Units and labels (docs/conventions.md): every number has a unit from graph/units.h, every port and
  // parameter a label.
  for (const auto& t : all) {
    for (const auto& p : t["params"]) {
      EXPECT_FALSE(p["label"].get<std::string>().empty()) << t["name"] << "." << p["name"];
      const auto type = p["type"].get<std::string>();
      if (type == "float" || type == "int" || type == "vec2" || type == "vec3") {
        EXPECT_TRUE(p.contains("unit") && p.contains("unit_name")) << t["name"] << "." << p["name"];
      }
    }
    for (const char* side : {"inputs", "outputs"})
      for (const auto& p : t[side])
        EXPECT_FALSE(p["label"].get<std::string>().empty()) << t["name"] << "." << p["name"];
    if (t["name"] == "Hillshade") {
      const auto& azimuth = t["params"][0];
      EXPECT_EQ(azimuth["name"], "sun_azimuth");
      EXPECT_EQ(azimuth["label"], "Sun azimuth");
      EXPECT_EQ(azimuth["unit"], "deg");
      EXPECT_EQ(azimuth["unit_symbol"], "°");
      EXPECT_EQ(azimuth["unit_name"], "degrees");
    }
  }
  const auto hillshade = orogen({"nodes", "Hillshade"}).out;
  EXPECT_NE(hillshade.find("sun_azimuth : float = 315.0 °  range [0, 360]"), std::string::npos) << hillshade;
  EXPECT_NE(hillshade.find("Sun azimuth: "), std::string::npos) << hillshade;

  auto unknown = orogen({"nodes", "Constnt"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("Constant"), std::string::npos);
}

// Input paths resolve against the graph file's directory, wherever orogen runs from; output paths inside -o.
TEST(Cli, InputPathsResolveAgainstTheGraphFile) {
  const auto dir = scratch_dir("cli-input-paths");
  const auto project = dir / "project";
  fs::create_directories(project / "data");
  // First write the input file with a graph of its own.
  auto made = orogen(
      {"eval", (write_text(project / "make.json", constant_graph("made.exr", 42.0)), project / "make.json").string(),
       "-o", (project / "data").string(), "--quiet"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  write_text(project / "read.json", R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "read", "type": "ReadHeightfield", "params": { "path": "data/made.exr" } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "read.out" }, "params": { "path": "copy.exr" } }
  ]
})");
  // Run from another directory: the relative input path still finds data/made.exr beside the graph.
  fs::create_directories(dir / "elsewhere");
  auto r =
      run_process(cli_binary(), {"eval", (project / "read.json").string(), "-o", "out", "--quiet"}, dir / "elsewhere");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "elsewhere" / "out" / "copy.exr"));
  auto v = run_process(cli_binary(), {"validate", (project / "read.json").string()}, dir / "elsewhere");
  EXPECT_EQ(v.exit_code, 0) << v.err;
}

TEST(Cli, ValidateChecksOutputPathsDuplicateWritersAndInputFiles) {
  const auto dir = scratch_dir("cli-validate-files");
  const auto check = [&](const std::string& name, const std::string& nodes) {
    write_text(dir / name, R"({"format": "orogen-graph", "version": 3,
      "domain": { "size": [100, 100], "resolution": [16, 16] }, "nodes": [
      { "id": "flat", "type": "Constant" }, )" +
                               nodes + "]}");
    return orogen({"validate", (dir / name).string(), "-o", (dir / "out").string()});
  };
  auto climbing = check("climbing.json", R"({ "id": "w", "type": "WriteHeightfield", "inputs": { "in": "flat.out" },
      "params": { "path": "../x.exr" } })");
  EXPECT_EQ(climbing.exit_code, 2);
  EXPECT_NE(climbing.err.find("w.path"), std::string::npos) << climbing.err;
  EXPECT_NE(climbing.err.find("climbs out"), std::string::npos) << climbing.err;

  auto twice = check("twice.json", R"({ "id": "w1", "type": "WriteHeightfield", "inputs": { "in": "flat.out" },
      "params": { "path": "h.exr" } }, { "id": "w2", "type": "WriteHeightfield", "inputs": { "in": "flat.out" },
      "params": { "path": "./h.exr" } })");
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("also written by w1.path"), std::string::npos) << twice.err;
  // eval refuses it too, before writing anything.
  auto eval_twice = orogen({"eval", (dir / "twice.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(eval_twice.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "out" / "h.exr"));

  auto missing =
      check("missing.json", R"({ "id": "r", "type": "ReadHeightfield", "params": { "path": "nothere.exr" } })");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("r.path: input file"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("does not exist"), std::string::npos) << missing.err;

  // A file the graph itself writes may appear later: a warning, not an error.
  auto later = orogen({"validate",
                       (write_text(dir / "later.json", R"({"format": "orogen-graph", "version": 6, "nodes": [
      { "id": "flat", "type": "Constant" },
      { "id": "w", "type": "WriteHeightfield", "inputs": { "in": "flat.out" }, "params": { "path": "h.exr" } },
      { "id": "r", "type": "ReadHeightfield", "params": { "path": "out/h.exr" } }]})"),
                        dir / "later.json")
                           .string(),
                       "-o", (dir / "out").string()});
  EXPECT_EQ(later.exit_code, 0) << later.err;
  EXPECT_NE(later.err.find("warning: r.path"), std::string::npos) << later.err;
  EXPECT_NE(later.err.find("w.path writes it"), std::string::npos) << later.err;
}

TEST(Cli, ResolutionKeepsCellsSquare) {
  const auto dir = scratch_dir("cli-resolution");
  write_text(dir / "g.json", constant_graph("h.exr"));  // a 100 x 100 m world
  auto refused = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--resolution", "100x50"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("cells must be square"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("use 100x100"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(dir / "out"));

  // A wide world: a single number gives the matching height.
  write_text(dir / "wide.json", R"({"format": "orogen-graph", "version": 6,
    "domain": { "size": [200, 100], "resolution": [21, 11] },
    "nodes": [{ "id": "flat", "type": "Constant" },
              { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "flat.out" },
                "params": { "path": "h.tif" } }]})");
  auto single = orogen({"eval", (dir / "wide.json").string(), "-o", (dir / "out").string(), "--resolution", "41",
                        "--stats", (dir / "s.json").string(), "--quiet"});
  ASSERT_EQ(single.exit_code, 0) << single.err;
  auto explicit_ok =
      orogen({"eval", (dir / "wide.json").string(), "-o", (dir / "out2").string(), "--resolution", "41x21", "--quiet"});
  EXPECT_EQ(explicit_ok.exit_code, 0) << explicit_ok.err;
  EXPECT_EQ(read_text(dir / "out" / "h.tif"), read_text(dir / "out2" / "h.tif"));  // 41 means 41x21 here
  auto wide_refused =
      orogen({"eval", (dir / "wide.json").string(), "-o", (dir / "out3").string(), "--resolution", "41x41"});
  EXPECT_EQ(wide_refused.exit_code, 2);
  EXPECT_NE(wide_refused.err.find("use 41x21"), std::string::npos) << wide_refused.err;
}

TEST(Cli, OutputsAreByteReproducible) {
  const auto dir = scratch_dir("cli-reproducible");
  write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 6,
    "domain": { "size": [100, 100], "resolution": [16, 16] },
    "nodes": [{ "id": "n", "type": "Perlin", "params": { "feature_size": 30 } },
              { "id": "c", "type": "ColorRamp", "inputs": { "in": "n.out" } },
              { "id": "he", "type": "WriteHeightfield", "inputs": { "in": "n.out" }, "params": { "path": "h.exr" } },
              { "id": "ht", "type": "WriteHeightfield", "inputs": { "in": "n.out" }, "params": { "path": "h.tif" } },
              { "id": "ie", "type": "WriteImage", "inputs": { "in": "c.out" }, "params": { "path": "c.exr" } },
              { "id": "it", "type": "WriteImage", "inputs": { "in": "c.out" }, "params": { "path": "c.tif" } }]})");
  auto a = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "a").string(), "--quiet"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // a header time of writing would now differ
  auto b = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "b").string(), "--quiet"});
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* f : {"h.exr", "h.tif", "c.exr", "c.tif"}) {
    const auto x = read_text(dir / "a" / f);
    EXPECT_FALSE(x.empty()) << f;
    EXPECT_TRUE(x == read_text(dir / "b" / f)) << f << " differs between two runs";
  }
}

}  // namespace
}  // namespace orogen::test
