// Node libraries (graph/node_library.h): loading, refusals, the library's name on its types and in graph files,
// and `orogen test-node` on the deliberately broken nodes of tests/node_libraries/broken_nodes.cpp.
// This program is a host like orogen (it exports its symbols), so it loads the libraries in process too.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include "evaluator/run_node.h"
#include "graph/graph.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/node_library.h"
#include "graph/registry.h"
#include "orogen/version.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using test::cli_binary;
using test::run_process;

std::string load_error(const std::filesystem::path& p) {
  try {
    load_node_library(p);
  } catch (const NodeLibraryError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(NodeLibrary, ItsTypesRegisterCarryingItsName) {
  const NodeLibrary lib = load_node_library(OROGEN_TEST_SAMPLE_NODES);
  EXPECT_EQ(lib.name, "sample_nodes");
  EXPECT_EQ(lib.types, (std::vector<std::string>{"SampleQuantize", "SampleThrows"}));
  const NodeType* t = NodeRegistry::instance().find("SampleQuantize");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->library, "sample_nodes");
  EXPECT_EQ(NodeRegistry::instance().find("Slope")->library, "");
  // The node runs, in this process, through the one registry.
  const Domain d = Domain::from_extent({0, 0}, {30, 20}, {4, 3});
  auto in = std::make_shared<Heightfield>(d, 27.5f);
  const auto out = run_node("SampleQuantize", d, {{"step", 10.0}}, {{"in", PortValue(HeightfieldPtr(in))}});
  EXPECT_EQ(out.get<Heightfield>()->at(1, 1), 20.0f);
  // Loading the same file again is not an error and registers nothing twice.
  EXPECT_EQ(load_node_library(OROGEN_TEST_SAMPLE_NODES).types.size(), 2u);
  EXPECT_EQ(loaded_node_libraries().size(), 1u);
}

TEST(NodeLibrary, AnotherVersionIsRefusedNamingBoth) {
  const auto why = load_error(OROGEN_TEST_OLD_VERSION_NODES);
  EXPECT_TRUE(contains(why, "built against Orogen 0.0.1")) << why;
  EXPECT_TRUE(contains(why, std::string("this is Orogen ") + OROGEN_SDK_VERSION)) << why;
}

TEST(NodeLibrary, ADuplicateTypeRefusesTheWholeLibrary) {
  const auto why = load_error(OROGEN_TEST_DUPLICATE_NODES);
  EXPECT_TRUE(contains(why, "node type 'Slope' already exists (built into Orogen)")) << why;
  EXPECT_EQ(NodeRegistry::instance().find("DuplicateFine"), nullptr);
  EXPECT_EQ(NodeRegistry::instance().find("Slope")->library, "");
}

TEST(NodeLibrary, AThrowingOrInvalidDeclarationRefusesTheLibrary) {
  const auto why = load_error(OROGEN_TEST_INVALID_NODES);
  EXPECT_TRUE(contains(why, "'InvalidThrowingDeclaration': cannot read my configuration")) << why;
  EXPECT_TRUE(contains(why, "'InvalidRange'")) << why;
  EXPECT_EQ(NodeRegistry::instance().find("InvalidRange"), nullptr);
}

TEST(NodeLibrary, FilesThatAreNotNodeLibraries) {
  const auto dir = test::scratch_dir("node-library-files");
  test::write_text(dir / "notes.so", "not a library");
  EXPECT_TRUE(contains(load_error(dir / "notes.so"), "not an Orogen node library")) << load_error(dir / "notes.so");
  EXPECT_TRUE(contains(load_error(dir / "missing.so"), "cannot be read")) << load_error(dir / "missing.so");
  // A file with a stamp that the system loader cannot open.
  test::write_text(dir / "fake.so", std::string("orogen-node-library-stamp;name=fake;version=") + OROGEN_SDK_VERSION +
                                        ";abi=" + std::to_string(OROGEN_NODE_ABI) + ";");
  EXPECT_TRUE(contains(load_error(dir / "fake.so"), "cannot be opened")) << load_error(dir / "fake.so");
}

TEST(NodeLibrary, AGraphRecordsTheLibrariesOfItsNodes) {
  load_node_library(OROGEN_TEST_SAMPLE_NODES);
  Graph g;
  g.add_node(*NodeRegistry::instance().find("Constant"), "base");
  const std::string plain = serialize_graph(g);
  EXPECT_FALSE(contains(plain, "node_libraries")) << "graphs of built-in nodes stay as they were";
  g.add_node(*NodeRegistry::instance().find("SampleQuantize"), "terraces");
  g.connect({"base", "out"}, "terraces", "in");
  const std::string text = serialize_graph(g);
  EXPECT_TRUE(contains(text, "\"node_libraries\": {\n    \"sample_nodes\": [\"SampleQuantize\"]\n  }")) << text;
  const auto back = parse_graph(text);
  ASSERT_TRUE(back.ok()) << back.error_text();
  EXPECT_EQ(serialize_graph(*back.graph), text);
}

TEST(NodeLibrary, AMissingTypeNamesItsLibrary) {
  const std::string text = R"({"format": "orogen-graph", "version": 5,
    "domain": {"size": [100, 100], "resolution": [5, 5]},
    "nodes": [{"id": "c", "type": "Gorge"}],
    "node_libraries": {"gorges": ["Gorge"]}})";
  const auto r = parse_graph(text);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error_text(),
                       "unknown node type 'Gorge': it comes from node library 'gorges', which is "
                       "not loaded"))
      << r.error_text();
  // The editor keeps the node as a placeholder, and saving keeps the record of its library.
  LoadOptions partial;
  partial.keep_partial = true;
  const auto kept = parse_graph(text, partial);
  ASSERT_TRUE(kept.graph);
  EXPECT_TRUE(contains(serialize_graph(*kept.graph), "\"gorges\": [\"Gorge\"]"));
  // A malformed record is reported where it is.
  const auto bad = parse_graph(R"({"format": "orogen-graph", "version": 5, "domain": {"size": [100, 100],
    "resolution": [5, 5]}, "nodes": [], "node_libraries": {"gorges": "Gorge"}})");
  EXPECT_TRUE(contains(bad.error_text(), "/node_libraries/gorges")) << bad.error_text();
}

TEST(NodeLibraryCli, PluginTypesAreListedWithTheirLibrary) {
  const auto r = run_process(cli_binary(), {"--plugin", OROGEN_TEST_SAMPLE_NODES, "nodes"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "SampleQuantize")) << r.out;
  EXPECT_TRUE(contains(r.out, "[sample_nodes] Heights rounded down")) << r.out;
  const auto one = run_process(cli_binary(), {"nodes", "SampleQuantize", "--plugin", OROGEN_TEST_SAMPLE_NODES});
  EXPECT_TRUE(contains(one.out, "from node library 'sample_nodes'")) << one.out << one.err;
}

TEST(NodeLibraryCli, ARefusedPluginIsAnError) {
  const auto r = run_process(cli_binary(), {"nodes", "--plugin", OROGEN_TEST_DUPLICATE_NODES});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "'Slope' already exists")) << r.err;
}

TEST(NodeLibraryCli, PluginPathFoldersAreLoaded) {
  const auto dir = test::scratch_dir("plugin-path");
  std::filesystem::copy_file(OROGEN_TEST_SAMPLE_NODES, dir / "libsample_nodes.so");
  ::setenv("OROGEN_PLUGIN_PATH", ("/nonexistent:" + dir.string()).c_str(), 1);
  const auto r = run_process(cli_binary(), {"nodes", "SampleQuantize"});
  ::unsetenv("OROGEN_PLUGIN_PATH");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "from node library 'sample_nodes'")) << r.out;
}

TEST(NodeLibraryCli, EvaluatesAGraphOfPluginNodesAndAThrowingNodeIsThatNodesError) {
  const auto dir = test::scratch_dir("plugin-eval");
  test::write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 5,
    "domain": {"size": [100, 100], "resolution": [9, 9]},
    "nodes": [{"id": "base", "type": "Constant", "params": {"value": 27.5}},
              {"id": "terraces", "type": "SampleQuantize", "inputs": {"in": "base.out"}},
              {"id": "bad", "type": "SampleThrows", "inputs": {"in": "base.out"}},
              {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "terraces.out"},
               "params": {"path": "t.exr"}}]})");
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--quiet",
                                            "--plugin", OROGEN_TEST_SAMPLE_NODES});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "bad")) << r.err;
  EXPECT_TRUE(contains(r.err, "not a std::exception (node type from node library 'sample_nodes')")) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "t.exr")) << "the independent branch finished";
  const auto without = run_process(cli_binary(), {"validate", (dir / "g.json").string()});
  EXPECT_EQ(without.exit_code, 2);
}

// The contracts catch each deliberately broken node with a message that names the cause, and only its own.
TEST(TestNodeCli, CatchesEachBrokenNodeByItsOwnContractOnly) {
  struct Broken {
    std::string type, contract, cause;
  };
  for (const Broken& b : {Broken{"BrokenDomainBlind", "cache key", "changed with the domain"},
                          Broken{"BrokenNarrowReach", "reach", "the declared reach is too small"},
                          Broken{"BrokenThreadSplit", "threads", "with 1 thread differs from"},
                          Broken{"BrokenExtremeDivide", "extremes",
                                 "divisor = min (0): output 'out' has an infinity at sample (0, 0) although every "
                                 "input was finite"}}) {
    const auto r = run_process(cli_binary(), {"test-node", b.type, "--plugin", OROGEN_TEST_BROKEN_NODES});
    EXPECT_EQ(r.exit_code, 1) << b.type << "\n" << r.out << r.err;
    EXPECT_TRUE(contains(r.out, "FAIL  " + b.contract)) << b.type << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, b.cause)) << b.type << "\n" << r.out;
    std::size_t fails = 0;
    for (std::size_t at = r.out.find("FAIL"); at != std::string::npos; at = r.out.find("FAIL", at + 1)) ++fails;
    EXPECT_EQ(fails, 1u) << b.type << " should fail only its own contract\n" << r.out;
  }
}

// A node that never polls the cancel, at an extreme that runs for minutes: left running, its table printed,
// and the program exits at once instead of waiting for it.
TEST(TestNodeCli, ANodeIgnoringTheCancelIsLeftBehindAndTheTableIsPrinted) {
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_process(cli_binary(), {"test-node", "BrokenIgnoresCancel", "--plugin", OROGEN_TEST_BROKEN_NODES});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "FAIL  extremes")) << r.out;
  EXPECT_TRUE(contains(r.out, "steps = max (1000000)")) << r.out;
  EXPECT_TRUE(contains(r.out, "still running 4 s after it was cancelled")) << r.out;
  EXPECT_TRUE(contains(r.out, "pass  threads")) << r.out;
  EXPECT_LT(seconds, 60.0) << "test-node waited for the abandoned run";
}

// A node that throws something other than a std::exception fails its runs; the table is still printed.
TEST(TestNodeCli, ANodeThrowingANonExceptionFailsAndTheTableIsPrinted) {
  const auto r = run_process(cli_binary(), {"test-node", "SampleThrows", "--plugin", OROGEN_TEST_SAMPLE_NODES});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "FAIL  reach")) << r.out;
  EXPECT_TRUE(contains(r.out, "not a std::exception")) << r.out;
  EXPECT_TRUE(contains(r.out, "pass  declaration")) << r.out;
}

TEST(TestNodeCli, PassesOnCorrectNodes) {
  const auto r = run_process(cli_binary(), {"test-node", "SampleQuantize", "Slope", "Blur", "FBM", "Add", "--plugin",
                                            OROGEN_TEST_SAMPLE_NODES});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_FALSE(contains(r.out, "FAIL")) << r.out;
  EXPECT_TRUE(contains(r.out, "pass  reach")) << r.out;
}

}  // namespace
}  // namespace orogen
