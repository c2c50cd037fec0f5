// End-to-end tests of the `orogen` command: every example graph, exit codes, the output-path rule,
// overrides, statistics and the persistent cache across processes.
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
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "flat.out" }, "params": { "path": ")" + path +
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
    auto first = orogen({"eval", graph.string(), "-o", out.string(), "--cache-dir", cache.string(), "--stats",
                         (dir / "first.json").string(), "--quiet"});
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

    auto second = orogen({"eval", graph.string(), "-o", out.string(), "--cache-dir", cache.string(), "--stats",
                          (dir / "second.json").string(), "--quiet"});
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
  const std::vector<std::string> args = {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(),
                                         "--cache-dir", (dir / "cache").string(), "--stats",
                                         (dir / "stats.json").string(), "--quiet"};
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
  "format": "orogen-graph", "version": 1,
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
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 1,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "missing", "type": "ReadHeightfield", "params": { "path": "/nonexistent/height.exr" } },
    { "id": "save_missing", "type": "WriteHeightfield", "inputs": { "in": "missing.height" }, "params": { "path": "a.exr" } },
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

  auto allowed = orogen({"eval", (dir / "abs.json").string(), "-o", (dir / "out").string(), "--quiet", "--allow-any-path"});
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
  EXPECT_TRUE(fs::exists(outside));
}

TEST(Cli, SetAndResolutionOverrides) {
  const auto dir = scratch_dir("cli-set");
  write_text(dir / "g.json", constant_graph("flat.exr"));
  auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--set", "flat.value=42",
                   "--resolution", "8x4", "--stats", (dir / "stats.json").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(dir / "stats.json")["nodes"]["flat"]["output_bytes"].get<std::size_t>() < 16u * 16u * 4u, true);

  auto bad_node = orogen({"eval", (dir / "g.json").string(), "--set", "nobody.value=1", "-o", (dir / "o2").string()});
  EXPECT_EQ(bad_node.exit_code, 2);
  EXPECT_NE(bad_node.err.find("nobody"), std::string::npos);
  auto bad_value = orogen({"eval", (dir / "g.json").string(), "--set", "flat.value=\"text\"", "-o", (dir / "o3").string()});
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

  auto one = orogen({"nodes", "Constant"});
  ASSERT_EQ(one.exit_code, 0);
  EXPECT_NE(one.out.find("value"), std::string::npos);
  EXPECT_NE(one.out.find("Parameters"), std::string::npos);

  auto json = orogen({"nodes", "--json"});
  ASSERT_EQ(json.exit_code, 0);
  const auto all = nlohmann::json::parse(json.out);
  ASSERT_TRUE(all.is_array());
  for (const auto& t : all) {
    EXPECT_FALSE(t["description"].get<std::string>().empty()) << t["name"];
    for (const auto& p : t["params"]) EXPECT_FALSE(p["description"].get<std::string>().empty()) << t["name"] << "." << p["name"];
  }

  auto unknown = orogen({"nodes", "Constnt"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("Constant"), std::string::npos);
}

}  // namespace
}  // namespace orogen::test
