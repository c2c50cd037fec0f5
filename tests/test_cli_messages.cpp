// What a new user meets first (issue 28, defect 7): the README's --set example runs, a wrong node or parameter
// in --set gets a suggestion, and a missing input file stops eval before anything is computed, saying where
// relative paths are looked for.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

TEST(CliMessages, TheReadmesSetExampleRuns) {
  const std::string readme = read_text(source_dir() / "README.md");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(readme, m, std::regex(R"(orogen eval (graphs/\S+\.json) --set (\S+))")))
      << "no example";
  const auto dir = scratch_dir("readme-set");
  const auto r = run_process(cli_binary(), {"eval", (source_dir() / m[1].str()).string(), "--set", m[2].str(),
                                            "--resolution", "33", "-q", "-o", dir.string()});
  EXPECT_EQ(r.exit_code, 0) << m[0] << ": " << r.err;
}

TEST(CliMessages, SetSuggestsTheNodeOrParameterMeant) {
  const auto graph = (source_dir() / "graphs" / "terrain.json").string();
  const auto dir = scratch_dir("set-suggest");
  const auto node = run_process(cli_binary(), {"eval", graph, "--set", "ridge.octaves=8", "-o", dir.string()});
  EXPECT_EQ(node.exit_code, 2);
  EXPECT_NE(node.err.find("no node 'ridge' in the graph (did you mean 'ridges'?)"), std::string::npos) << node.err;
  const auto param = run_process(cli_binary(), {"eval", graph, "--set", "ridges.octave=8", "-o", dir.string()});
  EXPECT_EQ(param.exit_code, 2);
  EXPECT_NE(param.err.find("has no parameter 'octave' (did you mean 'octaves'?)"), std::string::npos) << param.err;
}

TEST(CliMessages, AMissingInputFileStopsEvalBeforeAnythingIsComputed) {
  const auto dir = scratch_dir("missing-input");
  write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 5,
    "domain": {"size": [100, 100], "resolution": [17, 17]},
    "nodes": [{"id": "noise", "type": "FBM"},
              {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"}, "params": {"path": "a.exr"}},
              {"id": "read", "type": "ReadHeightfield", "params": {"path": "maps/nothere.exr"}},
              {"id": "copy", "type": "WriteHeightfield", "inputs": {"in": "read.out"},
               "params": {"path": "b.exr"}}]})");
  // Run from another directory: the file is looked for next to the graph, and the message says so.
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string()}, "/");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("input file '" + (dir / "maps" / "nothere.exr").string() + "' does not exist"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("resolve against the graph file's directory"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("current directory"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "a.exr")) << "computed before the check";
}

TEST(CliMessages, ResolutionAcceptsEngineSizesByName) {
  const auto dir = scratch_dir("resolution-presets");
  write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 5,
    "domain": {"size": [1000, 1000], "resolution": [17, 17]},
    "nodes": [{"id": "noise", "type": "FBM"},
              {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"},
               "params": {"path": "h.raw"}}]})");
  const auto r = run_process(
      cli_binary(), {"eval", (dir / "g.json").string(), "--resolution", "unity-513", "-q", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(fs::file_size(dir / "h.raw"), 513u * 513u * 2u);
  const auto bad =
      run_process(cli_binary(), {"eval", (dir / "g.json").string(), "--resolution", "unreal-1000", "-o", dir.string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("unreal-1009"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace orogen::test
