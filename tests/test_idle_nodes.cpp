// A node added but not wired yet that no output needs is a warning, not an error (issue 28, defect 5): the
// file loads with a warning, validate and eval succeed and say so, the evaluator leaves the node out. A node
// an output needs with an unconnected input is still an error.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/idle_nodes.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

// noise -> save, plus `loose` (Slope, its input not wired) feeding `more` (Blur): work in progress.
const char* kGraphWithLooseNodes = R"({
  "format": "orogen-graph", "version": 5,
  "domain": {"origin": [0, 0], "size": [1000, 1000], "resolution": [33, 33]},
  "nodes": [
    {"id": "noise", "type": "FBM"},
    {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"}, "params": {"path": "h.exr"}},
    {"id": "loose", "type": "Slope"},
    {"id": "more", "type": "Blur", "inputs": {"in": "loose.out"}}
  ]
})";

TEST(IdleNodes, AnUnwiredNodeNoOutputNeedsIsAWarning) {
  const LoadResult r = parse_graph(kGraphWithLooseNodes);
  ASSERT_TRUE(r.ok()) << r.error_text();
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].node, "loose");
  EXPECT_NE(r.warnings[0].message.find("no output needs"), std::string::npos) << r.warnings[0].str();
  EXPECT_EQ(idle_unwired_nodes(*r.graph), (std::vector<std::string>{"loose", "more"}));
}

TEST(IdleNodes, AnUnwiredNodeAWriterNeedsIsStillAnError) {
  std::string text = kGraphWithLooseNodes;
  text.replace(text.find("\"in\": \"noise.out\""), 17, "\"in\": \"more.out\"");
  const LoadResult r = parse_graph(text);
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(r.diagnostics[0].node, "loose");
  EXPECT_TRUE(r.warnings.empty());
}

TEST(IdleNodes, AGraphWithoutOutputsKeepsEveryNodeWanted) {
  Graph g;
  g.add_node("FBM", "noise");
  g.add_node("Slope", "loose");
  EXPECT_TRUE(idle_unwired_nodes(g).empty());  // its leaves are what it is for: the error stays
  EXPECT_FALSE(parse_graph(serialize_graph(g)).ok());
}

TEST(IdleNodes, TheEvaluatorLeavesThemOut) {
  LoadResult r = parse_graph(kGraphWithLooseNodes);
  ASSERT_TRUE(r.ok());
  EvaluatorOptions options;
  options.output.output_dir = scratch_dir("idle-nodes-eval");
  Evaluator evaluator(options);
  EvalRequest request;
  request.domain = r.graph->domain.to_domain();
  const EvalResult result = evaluator.evaluate(*r.graph, request);
  EXPECT_TRUE(result.ok());
  EXPECT_TRUE(result.nodes.count("save"));
  EXPECT_FALSE(result.nodes.count("loose"));
  EXPECT_FALSE(result.nodes.count("more"));
}

TEST(IdleNodes, ValidateAndEvalWarnAndSucceed) {
  const auto dir = scratch_dir("idle-nodes-cli");
  write_text(dir / "g.json", kGraphWithLooseNodes);
  const auto v = run_process(cli_binary(), {"validate", (dir / "g.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(v.exit_code, 0) << v.err;
  EXPECT_NE(v.err.find("warning: /nodes/2/inputs/in [node 'loose']"), std::string::npos) << v.err;
  EXPECT_NE(v.out.find("1 warning(s)"), std::string::npos) << v.out;
  const auto e = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.err.find("no output needs this node"), std::string::npos) << e.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "h.exr"));
}

}  // namespace
}  // namespace orogen::test
