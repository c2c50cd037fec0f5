// `orogen subgraph extract` (graph/subgraph_extract.h): a selection becomes an asset and the graph an instance of
// it, with every output file byte-identical; selections that cannot be extracted are refused with the reason.
#include <algorithm>
#include <map>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/subgraph.h"
#include "graph/subgraph_extract.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Every file under `dir`, by relative path, with its bytes.
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).generic_string()] = read_text(e.path());
  return out;
}

ProcessResult eval(const fs::path& graph, const fs::path& out, int resolution = 64) {
  const std::string res = std::to_string(resolution) + "x" + std::to_string(resolution);
  return run_process(cli_binary(), {"eval", graph.string(), "-o", out.string(), "--quiet", "--resolution", res});
}

ProcessResult extract(const std::vector<std::string>& args) {
  std::vector<std::string> all{"subgraph", "extract"};
  all.insert(all.end(), args.begin(), args.end());
  return run_process(cli_binary(), all);
}

const Node* instance_of(const Graph& g) {
  for (const auto& n : g.nodes())
    if (n.type->subgraph) return &n;
  return nullptr;
}

// A graph of graphs/ as it was before it used the subgraph library (tests/fixtures/before_library), else as it is.
fs::path plain_graph(const std::string& name) {
  const fs::path before = source_dir() / "tests/fixtures/before_library" / name;
  return fs::exists(before) ? before : source_dir() / "graphs" / name;
}

struct Case {
  std::string graph;  // in graphs/ (plain_graph)
  std::string nodes, expose;
  std::size_t inputs, outputs;
  bool as_is = false;  // the graph as it is in graphs/ (with library instances), not its plain form
};

// Seed graphs: the selection moves into an asset in a subfolder and the graph is written elsewhere, so both
// the asset's and the instance's relative paths are exercised; every output file stays byte for byte.
TEST(SubgraphExtract, OutputsStayByteIdentical) {
  const std::vector<Case> cases{
      // Inputs none (all sources selected); outputs landscape.out/erosion/flow, detail.out/deposition.
      {"eroded_mountains.json", "base,uplift_noise,uplift,landscape,talus,rework,detail",
       "base.seed,landscape.duration,talus.talus_angle", 0, 5},
      // One outside source feeding two selected inputs (continent.out -> mountain_mask.in, land.a) is one input.
      {"terrain.json", "warp_x,warp_y,ridges,mountain_mask,land,lifted", "ridges.amplitude", 1, 1},
      // A chain in the middle: inputs from map (several ports), outputs read by writers and later nodes.
      {"voronoi_island.json", "shaped,detail,coast_fade,dry,detail_mask,detail_masked,sum,terrain", "", 4, 1},
      // A library instance in the selection (named by the library, not rebased), its parameter promoted.
      {"river_network.json", "hills,terrain,network_height,valley", "valley.seed,hills.amplitude", 0, 3, true},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.graph);
    const fs::path dir = scratch_dir("extract_" + fs::path(c.graph).stem().string());
    const fs::path source = c.as_is ? source_dir() / "graphs" / c.graph : plain_graph(c.graph);
    fs::create_directories(dir / "graphs" / "lib");
    fs::create_directories(dir / "out_graphs");
    const fs::path original = dir / "graphs" / c.graph;
    fs::copy_file(source, original);
    const auto before = eval(original, dir / "before");
    ASSERT_EQ(before.exit_code, 0) << before.err;

    const fs::path asset = dir / "graphs" / "lib" / "part.orogen-subgraph.json";
    const fs::path rewritten = dir / "out_graphs" / c.graph;
    std::vector<std::string> args{original.string(), "--nodes",     c.nodes,           "-o",
                                  asset.string(),    "--graph-out", rewritten.string()};
    if (!c.expose.empty()) args.insert(args.end(), {"--expose", c.expose});
    const auto ex = extract(args);
    ASSERT_EQ(ex.exit_code, 0) << ex.err;
    EXPECT_EQ(read_text(original), read_text(source));  // --graph-out: untouched

    const auto loaded = load_graph_file(rewritten);
    ASSERT_TRUE(loaded.ok()) << loaded.error_text();
    const Node* inst = instance_of(*loaded.graph);
    ASSERT_NE(inst, nullptr);
    EXPECT_EQ(inst->id, "part");
    EXPECT_EQ(inst->asset, "../graphs/lib/part.orogen-subgraph.json");
    const SubgraphInterface& in = inst->type->subgraph->interface();
    EXPECT_EQ(in.inputs.size(), c.inputs);
    EXPECT_EQ(in.outputs.size(), c.outputs);
    const std::size_t selected = static_cast<std::size_t>(std::count(c.nodes.begin(), c.nodes.end(), ',') + 1);
    EXPECT_EQ(inst->type->subgraph->graph.nodes().size(), selected);
    EXPECT_EQ(loaded.graph->nodes().size() + selected - 1, load_graph_file(original).graph->nodes().size());

    const auto after = eval(rewritten, dir / "after");
    ASSERT_EQ(after.exit_code, 0) << after.err;
    const auto a = files_under(dir / "before"), b = files_under(dir / "after");
    ASSERT_FALSE(a.empty());
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [name, bytes] : a) {
      ASSERT_TRUE(b.count(name)) << name;
      EXPECT_TRUE(b.at(name) == bytes) << name << " differs after the extraction";
    }
  }
}

// The exposed parameters work on the instance: setting one equals setting the inner node in the original.
TEST(SubgraphExtract, ExposedParametersKeepValueAndMeaning) {
  const fs::path dir = scratch_dir("extract_expose");
  const fs::path original = dir / "terrain.json";
  fs::copy_file(plain_graph("terrain.json"), original);
  const auto ex = extract({original.string(), "--nodes", "warp_x,warp_y,ridges,land", "--expose",
                           "ridges.amplitude,warp_x.seed", "-o", (dir / "ridges.orogen-subgraph.json").string(),
                           "--graph-out", (dir / "new.json").string(), "--id", "rugged"});
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  const auto asset = json::parse(read_text(dir / "ridges.orogen-subgraph.json"));
  ASSERT_EQ(asset["interface"]["params"].size(), 2u);
  EXPECT_EQ(asset["interface"]["params"][0]["name"], "amplitude");
  EXPECT_EQ(asset["interface"]["params"][0]["to"], "ridges.amplitude");
  EXPECT_EQ(asset["interface"]["params"][1]["name"], "seed");
  // The instance sets nothing: the defaults are the selection's values.
  const auto rewritten = json::parse(read_text(dir / "new.json"));
  for (const auto& n : rewritten["nodes"])
    if (n["id"] == "rugged") EXPECT_FALSE(n.contains("params"));

  auto run = [&](const fs::path& graph, const std::string& out, const std::string& set) {
    const auto r = run_process(cli_binary(), {"eval", graph.string(), "-o", (dir / out).string(), "--quiet",
                                              "--resolution", "64x64", "--set", set});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_text(dir / out / "terrain" / "height.exr");
  };
  const std::string inner = run(original, "a", "ridges.amplitude=123");
  EXPECT_EQ(run(dir / "new.json", "b", "rugged.amplitude=123"), inner);
  EXPECT_EQ(run(dir / "new.json", "c", "rugged/ridges.amplitude=123"), inner);
  EXPECT_NE(run(dir / "new.json", "d", "rugged.amplitude=200"), inner);
}

// Relative input paths and nested assets named by path are rebased on the asset's folder; in place by default.
TEST(SubgraphExtract, RelativePathsInsideTheSelectionAreRebased) {
  const fs::path dir = scratch_dir("extract_paths");
  // An input file, and a nested asset beside the graph.
  write_text(dir / "make.json", json{{"format", "orogen-graph"},
                                     {"version", kGraphFormatVersion},
                                     {"domain", {{"size", {1024, 1024}}, {"resolution", {64, 64}}}},
                                     {"nodes",
                                      {{{"id", "n"}, {"type", "FBM"}, {"params", {{"amplitude", 80}}}},
                                       {{"id", "w"},
                                        {"type", "WriteHeightfield"},
                                        {"inputs", {{"in", "n.out"}}},
                                        {"params", {{"path", "dem.exr"}}}}}}}
                                    .dump());
  ASSERT_EQ(eval(dir / "make.json", dir).exit_code, 0);
  write_text(
      dir / "flip.orogen-subgraph.json",
      json{
          {"format", "orogen-graph"},
          {"version", kGraphFormatVersion},
          {"interface",
           {{"asset_version", 1},
            {"description", "Flipped"},
            {"inputs", json::array({{{"name", "in"}, {"type", "Heightfield"}, {"description", "In"}, {"to", "f.in"}}})},
            {"outputs",
             json::array({{{"name", "out"}, {"type", "Heightfield"}, {"description", "Out"}, {"from", "f.out"}}})}}},
          {"nodes", json::array({{{"id", "f"}, {"type", "Invert"}}})}}
          .dump());
  const fs::path graph = dir / "graph.json";
  write_text(graph, json{{"format", "orogen-graph"},
                         {"version", kGraphFormatVersion},
                         {"domain", {{"size", {1024, 1024}}, {"resolution", {64, 64}}}},
                         {"nodes",
                          {{{"id", "read"}, {"type", "ReadHeightfield"}, {"params", {{"path", "dem.exr"}}}},
                           {{"id", "flip"},
                            {"type", "Subgraph"},
                            {"asset", "flip.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"inputs", {{"in", "read.out"}}}},
                           {{"id", "blur"}, {"type", "Blur"}, {"inputs", {{"in", "flip.out"}}}},
                           {{"id", "save"},
                            {"type", "WriteHeightfield"},
                            {"inputs", {{"in", "blur.out"}}},
                            {"params", {{"path", "result.exr"}}}}}}}
                        .dump());
  ASSERT_EQ(eval(graph, dir / "before").exit_code, 0);
  fs::create_directories(dir / "assets" / "deep");
  const auto ex = extract({graph.string(), "--nodes", "read,flip,blur", "-o",
                           (dir / "assets" / "deep" / "source.orogen-subgraph.json").string()});
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  EXPECT_NE(ex.out.find("3 nodes replaced by instance 'source'"), std::string::npos) << ex.out;
  const auto asset = json::parse(read_text(dir / "assets" / "deep" / "source.orogen-subgraph.json"));
  EXPECT_EQ(asset["nodes"][0]["params"]["path"], "../../dem.exr");
  EXPECT_EQ(asset["nodes"][1]["asset"], "../../flip.orogen-subgraph.json");
  EXPECT_TRUE(asset["interface"]["inputs"].empty());
  const auto rewritten = json::parse(read_text(graph));  // rewritten in place
  ASSERT_EQ(rewritten["nodes"].size(), 2u);
  EXPECT_EQ(rewritten["nodes"][1]["inputs"]["in"], "source.out");
  ASSERT_EQ(eval(graph, dir / "after").exit_code, 0);
  EXPECT_EQ(read_text(dir / "after" / "result.exr"), read_text(dir / "before" / "result.exr"));
  EXPECT_FALSE(read_text(dir / "after" / "result.exr").empty());
}

// The interface as the library function builds it: inputs grouped by source, names made unique.
TEST(SubgraphExtract, InterfaceNamesAreUniqueAndInputsGroupedBySource) {
  Graph g;
  g.add_node("FBM", "a");
  g.add_node("FBM", "b");
  g.add_node("Add", "x");
  g.add_node("Multiply", "y");
  g.add_node("Invert", "z");
  g.add_node("Add", "after");
  g.connect({"a", "out"}, "x", "a");
  g.connect({"a", "out"}, "y", "a");  // a.out feeds two selected inputs: one interface input
  g.connect({"b", "out"}, "x", "b");
  g.connect({"x", "out"}, "y", "b");
  g.connect({"y", "out"}, "z", "in");
  g.connect({"x", "out"}, "after", "a");
  g.connect({"z", "out"}, "after", "b");
  ExtractRequest request;
  request.nodes = {"x", "y", "z"};
  request.asset_file = "part.orogen-subgraph.json";
  request.graph_file = "g.json";
  const Extraction ex = make_subgraph_asset(g, request);
  ASSERT_EQ(ex.inputs.size(), 2u);
  EXPECT_EQ(ex.inputs[0].name, "a");
  EXPECT_EQ(ex.inputs[0].targets.size(), 2u);
  EXPECT_EQ(ex.inputs[1].name, "b");
  ASSERT_EQ(ex.outputs.size(), 2u);
  EXPECT_EQ(ex.outputs[0].name, "out");
  EXPECT_EQ(ex.outputs[0].source, (PortRef{"x", "out"}));
  EXPECT_EQ(ex.outputs[1].name, "z_out");
  EXPECT_EQ(ex.reference, "part.orogen-subgraph.json");  // a path: it ends in .json
  const auto asset = json::parse(ex.asset_text);
  EXPECT_EQ(asset["interface"]["inputs"][0]["to"], json({"x.a", "y.a"}));
  EXPECT_EQ(asset["interface"]["outputs"][1]["from"], "z.out");
}

TEST(SubgraphExtract, RefusesWhatCannotBeExtracted) {
  const fs::path dir = scratch_dir("extract_refused");
  const fs::path graph = dir / "g.json";
  fs::copy_file(plain_graph("eroded_mountains.json"), graph);
  const std::string text = read_text(graph);
  const std::string asset = (dir / "a.orogen-subgraph.json").string();
  auto refused = [&](const std::vector<std::string>& extra, const std::string& message) {
    std::vector<std::string> args{graph.string(), "-o", asset};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = extract(args);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(asset));
    EXPECT_EQ(read_text(graph), text);
  };
  // landscape lies between base and talus: the instance would feed itself.
  refused({"--nodes", "base,talus"},
          "the selection is not convex: node 'landscape' (not selected) is fed by selected node 'base' and feeds "
          "selected node 'talus', so the instance would feed itself (a cycle)");
  refused({"--nodes", "base,landscpe"}, "no node 'landscpe' in the graph (did you mean 'landscape'?)");
  refused({"--nodes", "base,base"}, "node 'base' is selected twice");
  refused({"--nodes", "detail,save_deposition"},
          "the selection has writers: 'save_deposition' (WriteHeightfield); every instance of the asset would write "
          "the same file");
  refused({"--nodes", "base", "--expose", "base.octves"}, "node 'base' (FBM) has no parameter 'octves'");
  refused({"--nodes", "base", "--expose", "talus.talus_angle"}, "node 'talus' is not in the selection");
  refused({"--nodes", "base", "--id", "talus"}, "the instance id 'talus' is taken by a node that stays in the graph");
  refused({"--nodes", "base", "--id", "9x"}, "invalid instance id '9x'");
  // An existing asset is not overwritten without --force.
  write_text(asset, "{}");
  const auto r = extract({graph.string(), "-o", asset, "--nodes", "base"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("exists"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(asset), "{}");
  EXPECT_EQ(read_text(graph), text);
}

}  // namespace
}  // namespace orogen::test
