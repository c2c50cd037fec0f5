// Subgraph assets and instances (graph/subgraph.h, docs/subgraphs.md): loading and its errors, expansion,
// evaluation and caching through instances, the library, and the CLI.
#include <algorithm>
#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/points.h"
#include "graph/curves.h"
#include "graph/subgraph.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The raw bytes of a value (rasters, points, curves), to compare bit for bit.
std::vector<unsigned char> bytes_of(const PortValue& v) {
  std::vector<unsigned char> out;
  auto append = [&](const auto& data) {
    const std::size_t at = out.size(), n = data.size() * sizeof(data[0]);
    out.resize(at + n);
    if (n) std::memcpy(out.data() + at, data.data(), n);
  };
  if (const auto* h = std::get_if<HeightfieldPtr>(&v)) {
    append((*h)->data);
  } else if (const auto* i = std::get_if<ImagePtr>(&v)) {
    append((*i)->data);
  } else if (const auto* p = std::get_if<PointsPtr>(&v)) {
    append((*p)->position);
    append((*p)->rotation);
    append((*p)->scale);
    append((*p)->class_id);
    for (const auto& [name, values] : (*p)->attributes) append(values);
    if ((*p)->size() == 0) out.push_back(0);  // an empty set of points is a value too
  } else if (const auto* c = std::get_if<CurvesPtr>(&v)) {
    for (const auto& curve : (*c)->curves) {
      append(curve.points);
      append(curve.width);
      for (const auto& [name, values] : curve.attributes) append(values);
      append(std::vector<int>{curve.parent});
    }
    if ((*c)->size() == 0) out.push_back(0);
  }
  return out;
}

std::string graph_text(const json& nodes, int resolution = 48) {
  json doc = {{"format", "orogen-graph"},
              {"version", kGraphFormatVersion},
              {"domain", {{"size", {4096, 4096}}, {"resolution", {resolution, resolution}}}},
              {"nodes", nodes}};
  return doc.dump(2);
}

// A small asset: FBM noise (feature size exposed as `size`, amplitude as `height`) added to an input, then
// inverted: inner nodes noise -> sum -> flip.
json noise_asset(int asset_version = 1, int octaves = 4) {
  return {{"format", "orogen-graph"},
          {"version", kGraphFormatVersion},
          {"interface",
           {{"asset_version", asset_version},
            {"description", "Noise over a base, flipped"},
            {"inputs", {{{"name", "base"}, {"type", "Heightfield"}, {"description", "Base"}, {"to", "sum.a"}}}},
            {"outputs", {{{"name", "out"}, {"type", "Heightfield"}, {"description", "Result"}, {"from", "flip.out"}}}},
            {"params",
             {{{"name", "size"},
               {"type", "float"},
               {"default", 700},
               {"description", "Size"},
               {"to", "noise.feature_size"}},
              {{"name", "height"},
               {"type", "float"},
               {"default", 30},
               {"min", 0},
               {"max", 500},
               {"description", "Height"},
               {"to", {"noise.amplitude"}}}}}}},
          {"nodes",
           {{{"id", "noise"}, {"type", "FBM"}, {"params", {{"octaves", octaves}, {"seed", 3}}}},
            {{"id", "sum"}, {"type", "Add"}, {"inputs", {{"b", "noise.out"}}}},
            {{"id", "flip"}, {"type", "Invert"}, {"inputs", {{"in", "sum.out"}}}}}}};
}

void write_json(const fs::path& p, const json& j) { write_text(p, j.dump(2)); }

LoadResult load(const fs::path& dir, const json& nodes) {
  write_text(dir / "graph.json", graph_text(nodes));
  return load_graph_file(dir / "graph.json");
}

EvalResult evaluate(Evaluator& evaluator, const Graph& graph, std::vector<std::string> nodes) {
  EvalRequest request;
  request.domain = graph.domain.to_domain();
  request.nodes = std::move(nodes);
  return evaluator.evaluate(graph, request);
}

TEST(Subgraphs, LibraryAssetsLoadAndAreDocumented) {
  const auto library = list_subgraph_library();
  std::set<std::string> names;
  for (const auto& entry : library) names.insert(entry.name);
  EXPECT_TRUE(names.count("terrain_colors"));
  EXPECT_TRUE(names.count("eroded_mountain_range"));
  for (const auto& entry : library) {
    const AssetLoad load = load_subgraph_asset(entry.name, {});
    ASSERT_NE(load.asset, nullptr) << load.error;
    const SubgraphInterface& in = load.asset->interface();
    EXPECT_GT(in.description.size(), 40u) << entry.name;
    EXPECT_FALSE(in.outputs.empty()) << entry.name;
    for (const auto& i : in.inputs) EXPECT_FALSE(i.port.description.empty()) << entry.name << "." << i.port.name;
    for (const auto& o : in.outputs) EXPECT_FALSE(o.port.description.empty()) << entry.name << "." << o.port.name;
    for (const auto& p : in.params) EXPECT_FALSE(p.decl.description.empty()) << entry.name << "." << p.decl.name;
  }
}

TEST(Subgraphs, AssetFilesRoundTripWithTheirInterface) {
  for (const auto& entry : list_subgraph_library()) {
    SCOPED_TRACE(entry.name);
    const auto loaded = load_graph_file(entry.file);
    ASSERT_TRUE(loaded.ok()) << loaded.error_text();
    ASSERT_TRUE(loaded.graph->interface);
    const std::string text = serialize_graph(*loaded.graph);
    EXPECT_EQ(json::parse(text)["interface"], json::parse(read_text(entry.file))["interface"]);
    const auto again = parse_graph(text);
    ASSERT_TRUE(again.ok()) << again.error_text();
    EXPECT_EQ(serialize_graph(*again.graph), text);
  }
}

// For every library asset: an instance evaluates bit for bit like the asset's nodes pasted inline with the
// exposed values written into them, fed by the same source.
TEST(Subgraphs, InstancedEqualsInlineForEveryLibraryAsset) {
  for (const auto& entry : list_subgraph_library()) {
    SCOPED_TRACE(entry.name);
    const AssetLoad load = load_subgraph_asset(entry.name, {});
    ASSERT_NE(load.asset, nullptr) << load.error;
    const SubgraphInterface& in = load.asset->interface();

    // Instanced: a source feeding every heightfield input, one instance with a non-default exposed value.
    Graph instanced;
    instanced.domain.size = load.asset->graph.domain.size;  // the scale the asset was made for (forest: 1 km)
    instanced.domain.resolution = {48, 48};
    const std::map<std::string, ParamValue> src_params{{"amplitude", 400.0}, {"feature_size", 900.0}};
    instanced.add_node("FBM", "src").params = src_params;
    add_subgraph_instance(instanced, *load.asset, entry.name, "inst");
    for (const auto& i : in.inputs) {
      ASSERT_EQ(i.port.type, PortType::Heightfield);
      instanced.connect({"src", "out"}, "inst", i.port.name);
    }
    // A non-default value for the first float parameter, within its range.
    std::string changed;
    for (const auto& p : in.params)
      if (p.decl.type == ParamType::Float) {
        const double def = std::get<double>(p.decl.default_value);
        double v = def * 0.9;
        if (p.decl.min && v < *p.decl.min) v = *p.decl.min;
        instanced.set_param("inst", p.decl.name, v);
        changed = p.decl.name;
        break;
      }

    // Inline: the asset's nodes (their values as the instance sets them) with the source linked in by hand.
    Graph inline_graph = load.asset->graph;
    inline_graph.interface.reset();
    inline_graph.domain = instanced.domain;
    inline_graph.add_node("FBM", "src").params = src_params;
    for (const auto& p : in.params)
      for (const auto& t : p.targets) inline_graph.set_param(t.node, t.name, instanced.param("inst", p.decl.name));
    for (const auto& i : in.inputs)
      for (const auto& t : i.targets) inline_graph.connect({"src", "out"}, t.node, t.name);
    std::vector<std::string> sources;
    for (const auto& o : in.outputs) sources.push_back(o.source.node);

    Evaluator a, b;
    const EvalResult r1 = evaluate(a, instanced, {"inst"});
    const EvalResult r2 = evaluate(b, inline_graph, sources);
    ASSERT_TRUE(r1.ok());
    ASSERT_TRUE(r2.ok());
    for (const auto& o : in.outputs) {
      const auto x = bytes_of(r1.output("inst", o.port.name, instanced));
      const auto y = bytes_of(r2.output(o.source.node, o.source.port, inline_graph));
      ASSERT_FALSE(x.empty()) << o.port.name;
      EXPECT_EQ(x, y) << o.port.name << " (changed " << changed << ")";
    }
    // The instance's report stands for its inner nodes, which are reported too.
    EXPECT_EQ(r1.nodes.at("inst").status, NodeStatus::Computed);
    for (const auto& n : load.asset->graph.nodes()) EXPECT_TRUE(r1.nodes.count("inst/" + n.id)) << n.id;
  }
}

TEST(Subgraphs, TwoInstancesWithEqualInputsShareCacheEntries) {
  const fs::path dir = scratch_dir("subgraph_share");
  write_json(dir / "noise.orogen-subgraph.json", noise_asset());
  auto loaded = load(dir, {{{"id", "src"}, {"type", "Constant"}, {"params", {{"value", 5}}}},
                           {{"id", "a"},
                            {"type", "Subgraph"},
                            {"asset", "noise.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"inputs", {{"base", "src.out"}}}},
                           {{"id", "b"},
                            {"type", "Subgraph"},
                            {"asset", "noise.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"inputs", {{"base", "src.out"}}}}});
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Graph& graph = *loaded.graph;
  Evaluator evaluator;
  const EvalResult r = evaluate(evaluator, graph, {"a", "b"});
  ASSERT_TRUE(r.ok());
  const auto equal_keys = compute_cache_keys(graph, graph.domain.to_domain());
  for (const std::string inner : {"noise", "sum", "flip"})
    EXPECT_EQ(equal_keys.at("a/" + inner), equal_keys.at("b/" + inner)) << inner;
  EXPECT_EQ(equal_keys.at("a"), equal_keys.at("b"));
  // One instance's nodes ran; the other's output node is the same job, reported Cached (and the evaluator
  // need not even plan what feeds it).
  EXPECT_EQ(r.nodes.at("a/flip").key, r.nodes.at("b/flip").key);
  const NodeStatus sa = r.nodes.at("a/flip").status, sb = r.nodes.at("b/flip").status;
  EXPECT_TRUE((sa == NodeStatus::Computed && sb == NodeStatus::Cached) ||
              (sa == NodeStatus::Cached && sb == NodeStatus::Computed));
  EXPECT_NE(r.nodes.at(sa == NodeStatus::Cached ? "a/flip" : "b/flip").message.find("same result as node"),
            std::string::npos);
  EXPECT_EQ(bytes_of(r.output("a", "out", graph)), bytes_of(r.output("b", "out", graph)));

  // A second run finds everything in the cache.
  const std::size_t hits = evaluator.cache_stats().hits;
  const EvalResult again = evaluate(evaluator, graph, {"b"});
  EXPECT_EQ(again.nodes.at("b").status, NodeStatus::Cached);
  EXPECT_GT(evaluator.cache_stats().hits, hits);

  // Another exposed value on b: b's noise and what it feeds get new keys; a keeps its own.
  graph.set_param("b", "height", 60.0);
  const auto keys = compute_cache_keys(graph, graph.domain.to_domain());
  EXPECT_NE(keys.at("a/noise"), keys.at("b/noise"));
  EXPECT_NE(keys.at("a/flip"), keys.at("b/flip"));
  EXPECT_NE(keys.at("a"), keys.at("b"));
  EXPECT_EQ(keys.at("a/sum"), equal_keys.at("a/sum"));
  const EvalResult changed = evaluate(evaluator, graph, {"a", "b"});
  EXPECT_EQ(changed.nodes.at("a").status, NodeStatus::Cached);
  EXPECT_EQ(changed.nodes.at("b").status, NodeStatus::Computed);
}

TEST(Subgraphs, AnEditInsideTheAssetChangesExactlyTheInstancesAndTheirDownstream) {
  const fs::path dir = scratch_dir("subgraph_edit");
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(1, 4));
  const json nodes = {{{"id", "src"}, {"type", "Constant"}, {"params", {{"value", 5}}}},
                      {{"id", "other"}, {"type", "Constant"}, {"params", {{"value", 7}}}},
                      {{"id", "inst"},
                       {"type", "Subgraph"},
                       {"asset", "noise.orogen-subgraph.json"},
                       {"asset_version", 1},
                       {"inputs", {{"base", "src.out"}}}},
                      {{"id", "after"}, {"type", "Abs"}, {"inputs", {{"in", "inst.out"}}}},
                      {{"id", "beside"}, {"type", "Abs"}, {"inputs", {{"in", "other.out"}}}}};
  auto before = load(dir, nodes);
  ASSERT_TRUE(before.ok()) << before.error_text();
  const auto k0 = compute_cache_keys(*before.graph, before.graph->domain.to_domain());

  // The same inner edit (octaves 4 -> 5), not an exposed parameter: the file changes, the interface does not.
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(1, 5));
  auto after = load(dir, nodes);
  ASSERT_TRUE(after.ok()) << after.error_text();
  const auto k1 = compute_cache_keys(*after.graph, after.graph->domain.to_domain());
  ASSERT_EQ(k0.size(), k1.size());
  std::set<std::string> changed;
  for (const auto& [id, key] : k0)
    if (k1.at(id) != key) changed.insert(id);
  EXPECT_EQ(changed, (std::set<std::string>{"inst", "inst/noise", "inst/sum", "inst/flip", "after"}));

  // Undoing the edit gives the first keys back: a cache hit.
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(1, 4));
  auto undone = load(dir, nodes);
  ASSERT_TRUE(undone.ok());
  EXPECT_EQ(compute_cache_keys(*undone.graph, undone.graph->domain.to_domain()), k0);
}

// Three levels of assets, each promoting the exposed parameter of the one inside it.
TEST(Subgraphs, AFailureInsideAnInstanceIsReportedByTheInstance) {
  const fs::path dir = scratch_dir("subgraph_failure");
  write_json(dir / "reader.orogen-subgraph.json",
             {{"format", "orogen-graph"},
              {"version", kGraphFormatVersion},
              {"interface",
               {{"asset_version", 1},
                {"outputs", {{{"name", "out"}, {"type", "Heightfield"}, {"from", "read.out"}}}},
                {"params", {{{"name", "file"}, {"type", "path"}, {"to", "read.path"}}}}}},
              {"nodes", {{{"id", "read"}, {"type", "ReadHeightfield"}}}}});
  auto loaded = load(dir, {{{"id", "inst"},
                            {"type", "Subgraph"},
                            {"asset", "reader.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"params", {{"file", "no_such_file.exr"}}}},
                           {{"id", "after"}, {"type", "Abs"}, {"inputs", {{"in", "inst.out"}}}}});
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Evaluator evaluator;
  const EvalResult r = evaluate(evaluator, *loaded.graph, {"after"});
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.nodes.at("inst/read").status, NodeStatus::Failed);
  EXPECT_NE(r.nodes.at("inst/read").message.find("no_such_file.exr"), std::string::npos)
      << r.nodes.at("inst/read").message;
  EXPECT_EQ(r.nodes.at("inst").status, NodeStatus::Failed);
  EXPECT_EQ(r.nodes.at("inst").message.rfind("inst/read: ", 0), 0u) << r.nodes.at("inst").message;
  EXPECT_EQ(r.nodes.at("after").status, NodeStatus::Skipped);
  EXPECT_EQ(r.outputs.count("after"), 0u);
}

// Input files named inside an asset resolve against the asset's folder; those set on the instance against
// the folder of the graph that sets them.
TEST(Subgraphs, InputPathsResolveWhereTheyAreWritten) {
  const fs::path dir = scratch_dir("subgraph_paths");
  fs::create_directories(dir / "assets");
  write_json(dir / "assets" / "reader.orogen-subgraph.json",
             {{"format", "orogen-graph"},
              {"version", kGraphFormatVersion},
              {"interface",
               {{"asset_version", 1},
                {"outputs",
                 {{{"name", "a"}, {"type", "Heightfield"}, {"from", "fixed.out"}},
                  {{"name", "b"}, {"type", "Heightfield"}, {"from", "chosen.out"}}}},
                {"params", {{{"name", "file"}, {"type", "path"}, {"to", "chosen.path"}}}}}},
              {"nodes",
               {{{"id", "fixed"}, {"type", "ReadHeightfield"}, {"params", {{"path", "data/dem.exr"}}}},
                {{"id", "chosen"}, {"type", "ReadHeightfield"}, {"params", {{"path", "default.exr"}}}}}}});
  auto loaded = load(dir, {{{"id", "inst"},
                            {"type", "Subgraph"},
                            {"asset", "assets/reader.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"params", {{"file", "mine.exr"}}}}});
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  const fs::path base = fs::weakly_canonical(dir);
  auto path_of = [](const Graph& g, const std::string& node) {
    return fs::path(std::get<std::string>(g.param(node, "path")));
  };
  const Graph expanded = expand_subgraphs(*loaded.graph).graph;
  EXPECT_EQ(path_of(expanded, "inst/fixed"), base / "assets" / "data" / "dem.exr");
  EXPECT_EQ(path_of(expanded, "inst/chosen"), base / "mine.exr");
  Graph defaults = *loaded.graph;
  defaults.reset_param("inst", "file");
  EXPECT_EQ(path_of(expand_subgraphs(defaults).graph, "inst/chosen"), base / "assets" / "default.exr");
}

// An asset of one node presenting its output `out` and exposing `size`, set into `target` (a parameter of the node,
// or an exposed parameter of a nested instance): a level of the promotion tests.
json promotion_level(const json& node, const std::string& target) {
  return json{
      {"format", "orogen-graph"},
      {"version", kGraphFormatVersion},
      {"interface",
       {{"asset_version", 1},
        {"outputs", {{{"name", "out"}, {"type", "Heightfield"}, {"from", node["id"].get<std::string>() + ".out"}}}},
        {"params", {{{"name", "size"}, {"type", "float"}, {"to", target}}}}}},
      {"nodes", {node}}};
}

// l1 (an FBM exposing its feature size as `size`) and l2 (an instance of l1 promoting it) in `dir`.
void write_two_promotion_levels(const fs::path& dir) {
  write_json(
      dir / "l1.orogen-subgraph.json",
      promotion_level({{"id", "noise"}, {"type", "FBM"}, {"params", {{"feature_size", 300}}}}, "noise.feature_size"));
  write_json(
      dir / "l2.orogen-subgraph.json",
      promotion_level({{"id", "one"}, {"type", "Subgraph"}, {"asset", "l1.orogen-subgraph.json"}, {"asset_version", 1}},
                      "one.size"));
}

TEST(Subgraphs, PromotionThroughThreeLevels) {
  const fs::path dir = scratch_dir("subgraph_promotion");
  write_two_promotion_levels(dir);
  fs::create_directories(dir / "sub");  // a nested asset's path resolves against its own folder
  write_json(dir / "sub" / "l3.orogen-subgraph.json",
             promotion_level(
                 {{"id", "two"}, {"type", "Subgraph"}, {"asset", "../l2.orogen-subgraph.json"}, {"asset_version", 1}},
                 "two.size"));
  auto loaded = load(dir, {{{"id", "top"},
                            {"type", "Subgraph"},
                            {"asset", "sub/l3.orogen-subgraph.json"},
                            {"asset_version", 1},
                            {"params", {{"size", 777}}}}});
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  const ExpandedGraph expanded = expand_subgraphs(*loaded.graph);
  ASSERT_EQ(expanded.graph.nodes().size(), 1u);
  EXPECT_EQ(expanded.graph.nodes()[0].id, "top/two/one/noise");
  EXPECT_EQ(std::get<double>(expanded.graph.param("top/two/one/noise", "feature_size")), 777.0);
  EXPECT_EQ(expanded.outputs.at("top").at(0).str(), "top/two/one/noise.out");

  // The default promotes too: each level's default is the one inside it (300 from l1's node).
  Graph defaults = *loaded.graph;
  defaults.reset_param("top", "size");
  EXPECT_EQ(std::get<double>(expand_subgraphs(defaults).graph.param("top/two/one/noise", "feature_size")), 300.0);

  // Evaluates like a plain FBM of feature size 777.
  Graph plain;
  plain.domain = loaded.graph->domain;
  plain.add_node("FBM", "n").params["feature_size"] = 777.0;
  Evaluator e1, e2;
  const auto r1 = evaluate(e1, *loaded.graph, {"top"});
  const auto r2 = evaluate(e2, plain, {"n"});
  ASSERT_TRUE(r1.ok() && r2.ok());
  EXPECT_EQ(bytes_of(r1.output("top", "out", *loaded.graph)), bytes_of(r2.output("n", "out", plain)));
}

TEST(Subgraphs, RecursionIsRefusedWithTheCycleNamed) {
  const fs::path dir = scratch_dir("subgraph_recursion");
  auto asset_using = [](const std::string& other) {
    return json{{"format", "orogen-graph"},
                {"version", kGraphFormatVersion},
                {"interface",
                 {{"asset_version", 1}, {"outputs", {{{"name", "out"}, {"type", "Heightfield"}, {"from", "x.out"}}}}}},
                {"nodes", {{{"id", "x"}, {"type", "Subgraph"}, {"asset", other}, {"asset_version", 1}}}}};
  };
  write_json(dir / "a.orogen-subgraph.json", asset_using("b.orogen-subgraph.json"));
  write_json(dir / "b.orogen-subgraph.json", asset_using("a.orogen-subgraph.json"));
  write_json(dir / "c.orogen-subgraph.json", asset_using("c.orogen-subgraph.json"));
  auto loaded =
      load(dir, {{{"id", "inst"}, {"type", "Subgraph"}, {"asset", "a.orogen-subgraph.json"}, {"asset_version", 1}}});
  ASSERT_FALSE(loaded.ok());
  ASSERT_EQ(loaded.diagnostics.size(), 1u);
  EXPECT_EQ(loaded.diagnostics[0].node, "inst");
  EXPECT_NE(loaded.diagnostics[0].message.find("contains itself: a -> b -> a"), std::string::npos)
      << loaded.error_text();
  auto direct =
      load(dir, {{{"id", "self"}, {"type", "Subgraph"}, {"asset", "c.orogen-subgraph.json"}, {"asset_version", 1}}});
  ASSERT_FALSE(direct.ok());
  EXPECT_NE(direct.error_text().find("contains itself: c -> c"), std::string::npos) << direct.error_text();
}

TEST(Subgraphs, MissingAssetNamesTheNodeAndTheAsset) {
  const fs::path dir = scratch_dir("subgraph_missing");
  auto by_name = load(dir, {{{"id", "hills"}, {"type", "Subgraph"}, {"asset", "no_such_asset"}, {"asset_version", 1}}});
  ASSERT_FALSE(by_name.ok());
  ASSERT_EQ(by_name.diagnostics.size(), 1u);
  EXPECT_EQ(by_name.diagnostics[0].node, "hills");
  EXPECT_EQ(by_name.diagnostics[0].path, "/nodes/0/asset");
  EXPECT_NE(by_name.diagnostics[0].message.find("subgraph asset 'no_such_asset' not found"), std::string::npos)
      << by_name.error_text();
  EXPECT_NE(by_name.diagnostics[0].message.find("terrain_colors"), std::string::npos);  // what the library has

  auto by_path = load(
      dir, {{{"id", "hills"}, {"type", "Subgraph"}, {"asset", "gone/x.orogen-subgraph.json"}, {"asset_version", 1}}});
  ASSERT_FALSE(by_path.ok());
  EXPECT_NE(by_path.error_text().find("[node 'hills']: subgraph asset 'gone/x.orogen-subgraph.json' not found"),
            std::string::npos)
      << by_path.error_text();
}

TEST(Subgraphs, ChangedInterfaceIsRefusedSayingWhatChanged) {
  const fs::path dir = scratch_dir("subgraph_interface");
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(1));
  auto first = load(dir, {{{"id", "src"}, {"type", "Constant"}},
                          {{"id", "inst"},
                           {"type", "Subgraph"},
                           {"asset", "noise.orogen-subgraph.json"},
                           {"asset_version", 1},
                           {"inputs", {{"base", "src.out"}}}}});
  ASSERT_TRUE(first.ok()) << first.error_text();
  // Saving records the version and the interface the instance was made with.
  const std::string saved = serialize_graph(*first.graph);
  const json saved_json = json::parse(saved);
  const json& inst = saved_json["nodes"][1];
  EXPECT_EQ(inst["asset"], "noise.orogen-subgraph.json");
  EXPECT_EQ(inst["asset_version"], 1);
  EXPECT_EQ(inst["interface"]["params"]["height"], "float");
  EXPECT_EQ(saved.find("inst/"), std::string::npos);  // the instance, not its expanded nodes
  write_text(dir / "graph.json", saved);
  auto reloaded = load_graph_file(dir / "graph.json");
  ASSERT_TRUE(reloaded.ok()) << reloaded.error_text();
  EXPECT_TRUE(*reloaded.graph == *first.graph);

  // Version 2: `height` is gone, `size` became an int... (here: retyped by targeting octaves), an input added.
  json v2 = noise_asset(2);
  auto& in = v2["interface"];
  in["params"] = json::array({{{"name", "size"}, {"type", "int"}, {"to", "noise.octaves"}}});
  in["inputs"].push_back({{"name", "warp"}, {"type", "Heightfield"}, {"to", "noise.warp_x"}});
  write_json(dir / "noise.orogen-subgraph.json", v2);
  auto changed = load_graph_file(dir / "graph.json");
  ASSERT_FALSE(changed.ok());
  const std::string text = changed.error_text();
  EXPECT_NE(text.find("[node 'inst']: the interface of subgraph asset 'noise' changed (made with version 1"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("is at version 2"), std::string::npos) << text;
  EXPECT_NE(text.find("input 'warp' added (Heightfield)"), std::string::npos) << text;
  EXPECT_NE(text.find("param 'height' removed (was float)"), std::string::npos) << text;
  EXPECT_NE(text.find("param 'size' retyped float -> int"), std::string::npos) << text;

  // A newer asset with the same interface loads (and saving moves the instance to the new version).
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(3));
  auto compatible = load_graph_file(dir / "graph.json");
  ASSERT_TRUE(compatible.ok()) << compatible.error_text();
  EXPECT_EQ(json::parse(serialize_graph(*compatible.graph))["nodes"][1]["asset_version"], 3);

  // An asset older than the instance is refused.
  write_json(dir / "noise.orogen-subgraph.json", noise_asset(1));
  json newer = saved_json;
  newer["nodes"][1]["asset_version"] = 2;
  write_text(dir / "graph.json", newer.dump());
  auto older = load_graph_file(dir / "graph.json");
  ASSERT_FALSE(older.ok());
  EXPECT_NE(older.error_text().find("subgraph asset 'noise' is older than this instance"), std::string::npos)
      << older.error_text();
}

TEST(Subgraphs, ExposedParameterValuesAreChecked) {
  const fs::path dir = scratch_dir("subgraph_values");
  write_json(dir / "noise.orogen-subgraph.json", noise_asset());
  auto bad = load(dir, {{{"id", "src"}, {"type", "Constant"}},
                        {{"id", "inst"},
                         {"type", "Subgraph"},
                         {"asset", "noise.orogen-subgraph.json"},
                         {"asset_version", 1},
                         {"inputs", {{"base", "src.out"}}},
                         {"params", {{"heigth", 10}, {"height", 900}}}}});
  ASSERT_FALSE(bad.ok());
  const std::string text = bad.error_text();
  EXPECT_NE(text.find("/nodes/1/params/heigth [node 'inst']: unknown parameter 'heigth' for node type Subgraph "
                      "(did you mean 'height'?)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("/nodes/1/params/height [node 'inst']"), std::string::npos) << text;
  EXPECT_NE(text.find("above the maximum 500"), std::string::npos) << text;

  // A required interface input left unconnected is reported like a node's.
  auto unlinked = load(
      dir, {{{"id", "inst"}, {"type", "Subgraph"}, {"asset", "noise.orogen-subgraph.json"}, {"asset_version", 1}}});
  ASSERT_FALSE(unlinked.ok());
  EXPECT_NE(unlinked.error_text().find("missing required input 'base'"), std::string::npos) << unlinked.error_text();
}

TEST(Subgraphs, InterfaceErrorsPointIntoTheAsset) {
  const fs::path dir = scratch_dir("subgraph_bad_interface");
  json asset = noise_asset();
  asset["interface"]["outputs"][0]["from"] = "flip.nope";
  asset["interface"]["params"][1]["max"] = 1e9;  // wider than FBM's amplitude range
  write_json(dir / "bad.orogen-subgraph.json", asset);
  auto loaded =
      load(dir, {{{"id", "inst"}, {"type", "Subgraph"}, {"asset", "bad.orogen-subgraph.json"}, {"asset_version", 1}}});
  ASSERT_FALSE(loaded.ok());
  const std::string text = loaded.error_text();
  EXPECT_NE(text.find("/interface/outputs/0/from: node 'flip' (Invert) has no output 'nope'"), std::string::npos)
      << text;
  EXPECT_NE(text.find("/interface/params/1/max: \"max\" 1e+09 is outside the inner parameter's range"),
            std::string::npos)
      << text;
}

// A parameter exposed over several inner parameters takes the range they all accept.
TEST(Subgraphs, AnExposedParameterOverSeveralTargetsTakesTheirCommonRange) {
  const fs::path dir = scratch_dir("subgraph_common_range");
  json asset = noise_asset();
  asset["nodes"].push_back({{"id", "more"}, {"type", "FBM"}});
  asset["interface"]["params"] = json::array(
      {{{"name", "share"}, {"type", "float"}, {"default", 0.25}, {"to", {"noise.amplitude", "more.gain"}}}});
  write_json(dir / "shared.orogen-subgraph.json", asset);
  const AssetLoad load = load_subgraph_asset("shared.orogen-subgraph.json", dir);
  ASSERT_NE(load.asset, nullptr) << load.error;
  const ParamDecl& decl = load.asset->type.params.at(0);
  EXPECT_EQ(decl.min, 0.0);  // FBM.gain is 0..1, FBM.amplitude -1e6..1e6
  EXPECT_EQ(decl.max, 1.0);

  asset["interface"]["params"][0].erase("default");  // the default would be noise.amplitude's, 200
  write_json(dir / "shared2.orogen-subgraph.json", asset);
  const AssetLoad bad = load_subgraph_asset("shared2.orogen-subgraph.json", dir);
  ASSERT_EQ(bad.asset, nullptr);
  EXPECT_NE(bad.error.find("/interface/params/0: default of 'share': value 200 is above the maximum 1"),
            std::string::npos)
      << bad.error;
}

TEST(Subgraphs, CliSetReachesExposedAndInnerParameters) {
  const fs::path dir = scratch_dir("subgraph_cli");
  write_json(dir / "noise.orogen-subgraph.json", noise_asset());
  auto graph = [&](const json& params) {
    return graph_text({{{"id", "src"}, {"type", "Constant"}, {"params", {{"value", 5}}}},
                       {{"id", "inst"},
                        {"type", "Subgraph"},
                        {"asset", "noise.orogen-subgraph.json"},
                        {"asset_version", 1},
                        {"params", params},
                        {"inputs", {{"base", "src.out"}}}},
                       {{"id", "write"}, {"type", "WriteHeightfield"}, {"inputs", {{"in", "inst.out"}}}}});
  };
  write_text(dir / "plain.json", graph(json::object()));
  write_text(dir / "high.json", graph({{"height", 80}}));
  auto eval = [&](const std::string& file, const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args{"eval", (dir / file).string(), "-o", (dir / out).string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_process(cli_binary(), args);
  };
  const auto plain = eval("plain.json", "plain", {});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto exposed = eval("plain.json", "exposed", {"--set", "inst.height=80"});
  ASSERT_EQ(exposed.exit_code, 0) << exposed.err;
  const auto in_file = eval("high.json", "in_file", {});
  ASSERT_EQ(in_file.exit_code, 0) << in_file.err;
  const auto inner = eval("plain.json", "inner", {"--set", "inst/noise.amplitude=80"});
  ASSERT_EQ(inner.exit_code, 0) << inner.err;
  const std::string h_plain = read_text(dir / "plain" / "height.exr");
  ASSERT_FALSE(h_plain.empty());
  EXPECT_NE(read_text(dir / "exposed" / "height.exr"), h_plain);
  EXPECT_EQ(read_text(dir / "exposed" / "height.exr"), read_text(dir / "in_file" / "height.exr"));
  // The exposed `height` sets noise.amplitude: the inner override gives the same heights.
  EXPECT_EQ(read_text(dir / "inner" / "height.exr"), read_text(dir / "exposed" / "height.exr"));
  // The inner value is applied after the exposed one, so it wins.
  const auto both = eval("plain.json", "both", {"--set", "inst.height=80", "--set", "inst/noise.amplitude=30"});
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_EQ(read_text(dir / "both" / "height.exr"), h_plain);

  const auto wrong = eval("plain.json", "wrong", {"--set", "inst/noies.octaves=2", "--set", "inst.height=900"});
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.err.find("no node 'inst/noies' in the graph (did you mean 'inst/noise'?)"), std::string::npos)
      << wrong.err;
  EXPECT_NE(wrong.err.find("--set 'inst.height=900'"), std::string::npos) << wrong.err;

  const auto valid = run_process(cli_binary(), {"validate", (dir / "plain.json").string()});
  EXPECT_EQ(valid.exit_code, 0) << valid.err;
  EXPECT_NE(valid.out.find("valid (3 nodes, 5 with subgraphs expanded)"), std::string::npos) << valid.out;

  const auto nodes = run_process(cli_binary(), {"nodes"});
  EXPECT_NE(nodes.out.find("subgraph library"), std::string::npos);
  EXPECT_NE(nodes.out.find("  terrain_colors (asset version 1)  in: height: Heightfield"), std::string::npos)
      << nodes.out;
  const auto one = run_process(cli_binary(), {"nodes", "eroded_mountain_range"});
  EXPECT_EQ(one.exit_code, 0);
  EXPECT_NE(one.out.find("talus_angle : float = 40.0"), std::string::npos) << one.out;
}

// `orogen nodes --json` and `--markdown` document the library's assets after the node types.
TEST(Subgraphs, NodeReferenceListsTheLibrary) {
  const auto out = run_process(cli_binary(), {"nodes", "--json"});
  ASSERT_EQ(out.exit_code, 0) << out.err;
  const json all = json::parse(out.out);
  ASSERT_TRUE(all.is_array());
  std::map<std::string, json> assets;
  bool types_first = true, seen_asset = false;
  for (const auto& t : all) {
    const bool asset = t.value("type", "") == "Subgraph";
    if (!asset && seen_asset) types_first = false;
    seen_asset = seen_asset || asset;
    if (asset) assets[t["name"]] = t;
  }
  EXPECT_TRUE(types_first);
  std::set<std::string> names;
  for (const auto& entry : list_subgraph_library()) names.insert(entry.name);
  ASSERT_EQ(assets.size(), names.size());
  for (const auto& name : names) ASSERT_TRUE(assets.count(name)) << name;
  const json& range = assets.at("eroded_mountain_range");
  EXPECT_EQ(range["asset_version"], 2);
  EXPECT_EQ(range["category"], "subgraph library");
  EXPECT_NE(range["description"].get<std::string>().find("HydraulicErosion"), std::string::npos);
  ASSERT_EQ(range["inputs"].size(), 1u);
  EXPECT_EQ(range["inputs"][0]["name"], "uplift");
  std::vector<std::string> outputs;
  for (const auto& o : range["outputs"]) outputs.push_back(o["name"]);
  EXPECT_EQ(outputs, (std::vector<std::string>{"out", "flow", "erosion", "deposition", "stream_power"}));
  bool talus = false;
  for (const auto& p : range["params"])
    if (p["name"] == "talus_angle") {
      talus = true;
      EXPECT_EQ(p["default"], 40.0);
      EXPECT_EQ(p["unit"], "deg");  // the inner parameter's unit
      EXPECT_FALSE(p["description"].get<std::string>().empty());
    }
  EXPECT_TRUE(talus);
  // One asset alone, as for a node type.
  const auto one = run_process(cli_binary(), {"nodes", "river_valley", "--json"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(json::parse(one.out), assets.at("river_valley"));

  const auto md = run_process(cli_binary(), {"nodes", "--markdown"});
  ASSERT_EQ(md.exit_code, 0) << md.err;
  const auto library = md.out.find("\n## Subgraph library\n");
  ASSERT_NE(library, std::string::npos);
  EXPECT_GT(library, md.out.find("### Slope"));  // after the node types
  for (const auto& name : names) EXPECT_NE(md.out.find("### " + name + "\n", library), std::string::npos) << name;
  EXPECT_NE(md.out.find("- `uplift` Uplift (Heightfield, optional)", library), std::string::npos);
  EXPECT_NE(md.out.find("| `talus_angle` | Talus angle | float | `40.0` |", library), std::string::npos);
}

// --set reaches every level: the outer exposed parameter, a nested instance's exposed parameter, and the
// innermost node's parameter all set the same FBM feature size.
TEST(Subgraphs, CliSetReachesNestedInstances) {
  const fs::path dir = scratch_dir("subgraph_cli_nested");
  write_two_promotion_levels(dir);
  write_text(
      dir / "graph.json",
      graph_text({{{"id", "top"}, {"type", "Subgraph"}, {"asset", "l2.orogen-subgraph.json"}, {"asset_version", 1}},
                  {{"id", "write"}, {"type", "WriteHeightfield"}, {"inputs", {{"in", "top.out"}}}}}));
  auto eval = [&](const std::string& out, const std::string& set) {
    const auto r = run_process(
        cli_binary(), {"eval", (dir / "graph.json").string(), "-o", (dir / out).string(), "--quiet", "--set", set});
    EXPECT_EQ(r.exit_code, 0) << set << "\n" << r.err;
    return read_text(dir / out / "height.exr");
  };
  const std::string outer = eval("outer", "top.size=777");
  EXPECT_EQ(eval("nested", "top/one.size=777"), outer);
  EXPECT_EQ(eval("innermost", "top/one/noise.feature_size=777"), outer);
  EXPECT_NE(eval("other", "top/one.size=500"), outer);
  const auto wrong = run_process(
      cli_binary(), {"eval", (dir / "graph.json").string(), "-o", (dir / "x").string(), "--set", "top/one.sise=1"});
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.err.find("subgraph instance 'top/one' has no parameter 'sise' (did you mean 'size'?)"),
            std::string::npos)
      << wrong.err;
}

}  // namespace
}  // namespace orogen::test
