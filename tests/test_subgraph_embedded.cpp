// Embedded subgraph assets (a graph file's "subgraphs" section, instances naming "#name") and "make unique"
// (graph/subgraph_unique.h): they load, evaluate and cache like asset files, recursion and missing names are
// refused with their messages, and saving keeps them (docs/subgraphs.md, "Embedded assets").
#include <cstring>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/subgraph.h"
#include "graph/subgraph_unique.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The raw bytes of every heightfield and image `node` outputs.
std::vector<unsigned char> bytes_of(const EvalResult& r, const std::string& node) {
  std::vector<unsigned char> out;
  const auto it = r.outputs.find(node);
  EXPECT_NE(it, r.outputs.end()) << node << " did not evaluate";
  if (it == r.outputs.end()) return out;
  auto append = [&](const auto& data) {
    const auto* p = reinterpret_cast<const unsigned char*>(data.data());
    out.insert(out.end(), p, p + data.size() * sizeof(data[0]));
  };
  for (const auto& v : it->second) {
    if (const auto* h = std::get_if<HeightfieldPtr>(&v)) append((*h)->data);
    if (const auto* i = std::get_if<ImagePtr>(&v)) append((*i)->data);
  }
  EXPECT_FALSE(out.empty()) << node;
  return out;
}

EvalResult evaluate(Evaluator& evaluator, const Graph& graph, const std::vector<std::string>& nodes) {
  EvalRequest request;
  request.domain = graph.domain.to_domain();
  request.nodes = nodes;
  return evaluator.evaluate(graph, request);
}

// A 64^2 graph: FBM "base" colored by an instance "colors" of the library's terrain_colors.
json colors_doc() {
  return {{"format", "orogen-graph"},
          {"version", kGraphFormatVersion},
          {"domain", {{"size", {4096, 4096}}, {"resolution", {64, 64}}}},
          {"nodes",
           {{{"id", "base"}, {"type", "FBM"}, {"params", {{"seed", 4}, {"amplitude", 800}}}},
            {{"id", "colors"},
             {"type", "Subgraph"},
             {"asset", "terrain_colors"},
             {"asset_version", 1},
             {"inputs", {{"height", "base.out"}}}}}}};
}

// FBM noise (feature size exposed as `size`) added to an input, then inverted.
json noise_asset(int asset_version = 1) {
  return {{"format", "orogen-graph"},
          {"version", kGraphFormatVersion},
          {"domain", {{"size", {4096, 4096}}, {"resolution", {32, 32}}}},
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
               {"to", "noise.feature_size"}}}}}},
          {"nodes",
           {{{"id", "noise"}, {"type", "FBM"}, {"params", {{"octaves", 4}, {"seed", 3}}}},
            {{"id", "sum"}, {"type", "Add"}, {"inputs", {{"b", "noise.out"}}}},
            {{"id", "flip"}, {"type", "Invert"}, {"inputs", {{"in", "sum.out"}}}}}}};
}

// A graph: a base, an instance of `asset` fed by it (size set to 900), with `subgraphs` as its section.
json graph_doc(const std::string& asset, const json& subgraphs = nullptr, int resolution = 48) {
  json doc = {{"format", "orogen-graph"},
              {"version", kGraphFormatVersion},
              {"domain", {{"size", {4096, 4096}}, {"resolution", {resolution, resolution}}}},
              {"nodes",
               {{{"id", "base"}, {"type", "FBM"}, {"params", {{"seed", 9}}}},
                {{"id", "inst"},
                 {"type", "Subgraph"},
                 {"asset", asset},
                 {"asset_version", 1},
                 {"params", {{"size", 900}}},
                 {"inputs", {{"base", "base.out"}}}}}}};
  if (!subgraphs.is_null()) doc["subgraphs"] = subgraphs;
  return doc;
}

LoadResult load_doc(const fs::path& dir, const json& doc, const std::string& name = "graph.json") {
  write_text(dir / name, doc.dump(2));
  return load_graph_file(dir / name);
}

TEST(EmbeddedSubgraphs, AnEmbeddedAssetEvaluatesBitForBitLikeTheSameFile) {
  const fs::path dir = scratch_dir("embedded_like_file");
  write_text(dir / "noise.orogen-subgraph.json", noise_asset().dump(2));
  const LoadResult from_file = load_doc(dir, graph_doc("noise.orogen-subgraph.json"), "file.json");
  ASSERT_TRUE(from_file.ok()) << from_file.error_text();
  const LoadResult embedded = load_doc(dir, graph_doc("#noise", {{"noise", noise_asset()}}), "embedded.json");
  ASSERT_TRUE(embedded.ok()) << embedded.error_text();
  const SubgraphAsset* asset = embedded.graph->at("inst").type->subgraph;
  ASSERT_TRUE(asset);
  EXPECT_EQ(asset->embedded, "noise");
  EXPECT_TRUE(asset->file.empty());
  EXPECT_EQ(embedded.graph->at("inst").asset, "#noise");

  Evaluator evaluator;
  const auto want = bytes_of(evaluate(evaluator, *from_file.graph, {"inst"}), "inst");
  Evaluator fresh;
  EXPECT_EQ(bytes_of(evaluate(fresh, *embedded.graph, {"inst"}), "inst"), want);
  // Same content, same cache keys: the file's evaluator has every inner node already.
  const EvalResult again = evaluate(evaluator, *embedded.graph, {"inst"});
  EXPECT_EQ(bytes_of(again, "inst"), want);
  EXPECT_EQ(again.nodes.at("inst/flip").status, NodeStatus::Cached);
}

TEST(EmbeddedSubgraphs, EmbeddedAssetsNestEmbeddedLibraryAndFileAssets) {
  const fs::path dir = scratch_dir("embedded_nested");
  write_text(dir / "noise.orogen-subgraph.json", noise_asset().dump(2));
  // wrap: #noise (embedded) then noise.orogen-subgraph.json (a file), then terrain_colors (the library).
  json wrap = noise_asset();
  wrap["interface"] = {
      {"asset_version", 1},
      {"description", "Two noises and colors"},
      {"inputs", {{{"name", "base"}, {"type", "Heightfield"}, {"description", "Base"}, {"to", "first.base"}}}},
      {"outputs",
       {{{"name", "out"}, {"type", "Heightfield"}, {"description", "Heights"}, {"from", "second.out"}},
        {{"name", "color"}, {"type", "Image"}, {"description", "Colors"}, {"from", "colors.color"}}}},
      {"params", json::array()}};
  wrap["nodes"] = {{{"id", "first"}, {"type", "Subgraph"}, {"asset", "#noise"}, {"asset_version", 1}},
                   {{"id", "second"},
                    {"type", "Subgraph"},
                    {"asset", "noise.orogen-subgraph.json"},
                    {"asset_version", 1},
                    {"inputs", {{"base", "first.out"}}}},
                   {{"id", "colors"},
                    {"type", "Subgraph"},
                    {"asset", "terrain_colors"},
                    {"asset_version", 1},
                    {"inputs", {{"height", "second.out"}}}}};
  json doc = graph_doc("#wrap", {{"wrap", wrap}, {"noise", noise_asset()}});
  doc["nodes"][1].erase("params");
  const LoadResult loaded = load_doc(dir, doc);
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Evaluator evaluator;
  const EvalResult r = evaluate(evaluator, *loaded.graph, {"inst"});
  EXPECT_EQ(r.nodes.at("inst").status, NodeStatus::Computed) << r.nodes.at("inst").message;
  EXPECT_TRUE(r.nodes.count("inst/first/flip") && r.nodes.count("inst/second/flip") &&
              r.nodes.count("inst/colors/colors"));
  // Saved and loaded again: both embedded assets are kept (wrap by the instance, noise through wrap).
  const std::string text = serialize_graph(*loaded.graph);
  const json saved = json::parse(text);
  ASSERT_TRUE(saved.contains("subgraphs"));
  EXPECT_TRUE(saved["subgraphs"].contains("wrap") && saved["subgraphs"].contains("noise"));
  EXPECT_FALSE(saved["subgraphs"]["wrap"].contains("subgraphs"));
  write_text(dir / "again.json", text);
  const LoadResult reloaded = load_graph_file(dir / "again.json");
  ASSERT_TRUE(reloaded.ok()) << reloaded.error_text();
  EXPECT_EQ(serialize_graph(*reloaded.graph), text);
  EXPECT_EQ(bytes_of(evaluate(evaluator, *reloaded.graph, {"inst"}), "inst"), bytes_of(r, "inst"));
}

TEST(EmbeddedSubgraphs, RecursionAmongEmbeddedAssetsIsRefusedWithTheCycle) {
  const fs::path dir = scratch_dir("embedded_recursion");
  json a = noise_asset(), b = noise_asset();
  // a's sum is fed by an instance of b, b's by an instance of a.
  a["nodes"].push_back({{"id", "inner"}, {"type", "Subgraph"}, {"asset", "#b"}, {"asset_version", 1}});
  a["nodes"][1]["inputs"]["b"] = "inner.out";
  a["nodes"].erase(0);
  a["interface"]["params"] = json::array();
  b["nodes"].push_back({{"id", "inner"}, {"type", "Subgraph"}, {"asset", "#a"}, {"asset_version", 1}});
  b["nodes"][1]["inputs"]["b"] = "inner.out";
  b["nodes"].erase(0);
  b["interface"]["params"] = json::array();
  json doc = graph_doc("#a", {{"a", a}, {"b", b}});
  doc["nodes"][1].erase("params");
  const LoadResult loaded = load_doc(dir, doc);
  ASSERT_FALSE(loaded.ok());
  const std::string text = loaded.error_text();
  EXPECT_NE(text.find("/nodes/1/asset [node 'inst']"), std::string::npos) << text;
  EXPECT_NE(text.find("subgraph asset '#a' contains itself: #a -> #b -> #a"), std::string::npos) << text;
}

TEST(EmbeddedSubgraphs, AMissingNameNamesTheNodeAndListsTheEmbeddedAssets) {
  const fs::path dir = scratch_dir("embedded_missing");
  const LoadResult loaded = load_doc(dir, graph_doc("#nois", {{"noise", noise_asset()}, {"other", noise_asset()}}));
  ASSERT_FALSE(loaded.ok());
  ASSERT_FALSE(loaded.diagnostics.empty());
  EXPECT_EQ(loaded.diagnostics[0].node, "inst");
  EXPECT_EQ(loaded.diagnostics[0].path, "/nodes/1/asset");
  EXPECT_NE(loaded.diagnostics[0].message.find(
                "embedded subgraph asset '#nois' not found: the file's embedded assets are #noise, #other"),
            std::string::npos)
      << loaded.error_text();
  const LoadResult none = load_doc(dir, graph_doc("#noise"), "none.json");
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error_text().find("the file has no embedded assets"), std::string::npos) << none.error_text();
}

TEST(EmbeddedSubgraphs, VersionsInterfacesAndTheSectionAreCheckedLikeFiles) {
  const fs::path dir = scratch_dir("embedded_checks");
  // A changed interface: the instance records an input the asset no longer has.
  json doc = graph_doc("#noise", {{"noise", noise_asset(2)}});
  doc["nodes"][1]["interface"] = {{"inputs", {{"base", "Heightfield"}, {"warp", "Heightfield"}}},
                                  {"outputs", {{"out", "Heightfield"}}},
                                  {"params", {{"size", "float"}}}};
  LoadResult r = load_doc(dir, doc, "changed.json");
  EXPECT_NE(r.error_text().find("the interface of subgraph asset 'noise' changed (made with version 1, the asset "
                                "(embedded asset '#noise') is at version 2): input 'warp' removed"),
            std::string::npos)
      << r.error_text();
  // Older than the instance.
  doc = graph_doc("#noise", {{"noise", noise_asset()}});
  doc["nodes"][1]["asset_version"] = 3;
  r = load_doc(dir, doc, "older.json");
  EXPECT_NE(r.error_text().find("subgraph asset 'noise' is older than this instance"), std::string::npos)
      << r.error_text();
  // A newer format version than this build reads, an inner problem, a section in an embedded asset.
  json bad = noise_asset();
  bad["version"] = kGraphFormatVersion + 1;
  r = load_doc(dir, graph_doc("#noise", {{"noise", bad}}), "newer.json");
  EXPECT_NE(r.error_text().find("embedded subgraph asset '#noise' is invalid"), std::string::npos) << r.error_text();
  bad = noise_asset();
  bad["subgraphs"] = json::object();
  r = load_doc(dir, graph_doc("#noise", {{"noise", bad}}), "nested_section.json");
  EXPECT_NE(r.error_text().find("cannot have a \"subgraphs\" section of its own"), std::string::npos) << r.error_text();
  r = load_doc(dir, graph_doc("#noise", {{"no ise", noise_asset()}}), "bad_name.json");
  EXPECT_NE(r.error_text().find("invalid embedded asset name 'no ise'"), std::string::npos) << r.error_text();
  // An unused embedded asset is checked too, and a warning says saving drops it.
  bad = noise_asset();
  bad["nodes"][0]["type"] = "NoSuchNode";
  r = load_doc(dir, graph_doc("#noise", {{"noise", noise_asset()}, {"broken", bad}}), "unused_broken.json");
  EXPECT_NE(r.error_text().find("/subgraphs/broken"), std::string::npos) << r.error_text();
  r = load_doc(dir, graph_doc("#noise", {{"noise", noise_asset()}, {"spare", noise_asset()}}), "unused.json");
  ASSERT_TRUE(r.ok()) << r.error_text();
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].message.find("embedded asset '#spare' is used by no instance"), std::string::npos);
  EXPECT_FALSE(json::parse(serialize_graph(*r.graph))["subgraphs"].contains("spare"));
}

TEST(EmbeddedSubgraphs, MakeUniqueOfALibraryAssetEvaluatesByteIdenticallyAndRoundTrips) {
  const fs::path dir = scratch_dir("embedded_make_unique");
  json doc = colors_doc();
  doc["nodes"][1]["params"] = {{"sun_azimuth", 120}};
  LoadResult loaded = load_doc(dir, doc);
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Graph graph = *loaded.graph;
  Evaluator evaluator;
  const auto before = bytes_of(evaluate(evaluator, graph, {"colors"}), "colors");
  const SubgraphAsset* library = graph.at("colors").type->subgraph;

  const MadeUnique made = make_instance_unique(graph, "colors");
  EXPECT_EQ(made.name, "terrain_colors");
  EXPECT_EQ(graph.at("colors").asset, "#terrain_colors");
  EXPECT_NE(made.asset, library);
  EXPECT_EQ(made.asset->embedded, "terrain_colors");
  EXPECT_EQ(std::get<double>(graph.param("colors", "sun_azimuth")), 120.0);  // values, links kept
  EXPECT_EQ(graph.at("colors").inputs.at("height"), (PortRef{"base", "out"}));
  // Byte-identical, and the library instance's cache entries serve the copy.
  Evaluator fresh;
  EXPECT_EQ(bytes_of(evaluate(fresh, graph, {"colors"}), "colors"), before);
  const EvalResult cached = evaluate(evaluator, graph, {"colors"});
  EXPECT_EQ(bytes_of(cached, "colors"), before);
  EXPECT_EQ(cached.nodes.at("colors/colors").status, NodeStatus::Cached);

  // A second instance of the same library asset gets a second name; the first one is unique already.
  add_subgraph_instance(graph, *library, "terrain_colors", "colors2");
  EXPECT_EQ(make_instance_unique(graph, "colors2").name, "terrain_colors2");
  try {
    make_instance_unique(graph, "colors");
    FAIL() << "expected a refusal";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("instance 'colors' is unique already"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_instance_unique(graph, "base"), GraphError);
  EXPECT_THROW(make_instance_unique(graph, "nope"), GraphError);
  graph.remove_node("colors2");

  // Saved and loaded: the embedded copy is in the file and the instance names it; same asset, same bytes.
  save_graph_file(graph, dir / "unique.json");
  const LoadResult reloaded = load_graph_file(dir / "unique.json");
  ASSERT_TRUE(reloaded.ok()) << reloaded.error_text();
  EXPECT_TRUE(reloaded.warnings.empty());
  EXPECT_EQ(reloaded.graph->at("colors").type->subgraph, made.asset);
  EXPECT_EQ(serialize_graph(*reloaded.graph), serialize_graph(graph));
  EXPECT_EQ(bytes_of(evaluate(fresh, *reloaded.graph, {"colors"}), "colors"), before);
}

// An embedded asset two instances share: making one unique gives it a copy under a new name; each evaluates
// as before, and the copy can then be changed alone.
TEST(EmbeddedSubgraphs, MakeUniqueOfASharedEmbeddedAssetCopiesIt) {
  const fs::path dir = scratch_dir("embedded_shared");
  json doc = graph_doc("#noise", {{"noise", noise_asset()}});
  doc["nodes"].push_back({{"id", "other"},
                          {"type", "Subgraph"},
                          {"asset", "#noise"},
                          {"asset_version", 1},
                          {"inputs", {{"base", "inst.out"}}}});
  const LoadResult loaded = load_doc(dir, doc);
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Graph graph = *loaded.graph;
  Evaluator evaluator;
  const auto before = bytes_of(evaluate(evaluator, graph, {"other"}), "other");
  const MadeUnique made = make_instance_unique(graph, "other");
  EXPECT_EQ(made.name, "noise2");
  EXPECT_EQ(graph.at("other").asset, "#noise2");
  EXPECT_EQ(graph.at("inst").asset, "#noise");
  Evaluator fresh;
  EXPECT_EQ(bytes_of(evaluate(fresh, graph, {"other"}), "other"), before);
  const json saved = json::parse(serialize_graph(graph));
  EXPECT_TRUE(saved["subgraphs"].contains("noise") && saved["subgraphs"].contains("noise2"));
  EXPECT_THROW(make_instance_unique(graph, "other"), GraphError);  // unique now
}

// A file asset in another folder: the copy's relative paths (an input file, a nested asset) are rebased to the
// graph's folder and still name the same files.
TEST(EmbeddedSubgraphs, MakeUniqueRebasesRelativePaths) {
  const fs::path dir = scratch_dir("embedded_rebase");
  write_text(dir / "assets" / "noise.orogen-subgraph.json", noise_asset().dump(2));
  // An input file beside the assets: made by evaluating a writer there.
  write_text(dir / "assets" / "make.json",
             json{{"format", "orogen-graph"},
                  {"version", kGraphFormatVersion},
                  {"domain", {{"size", {4096, 4096}}, {"resolution", {48, 48}}}},
                  {"nodes",
                   {{{"id", "n"}, {"type", "FBM"}, {"params", {{"amplitude", 80}, {"seed", 11}}}},
                    {{"id", "w"},
                     {"type", "WriteHeightfield"},
                     {"inputs", {{"in", "n.out"}}},
                     {"params", {{"path", "dem.exr"}}}}}}}
                 .dump());
  ASSERT_EQ(run_process(cli_binary(),
                        {"eval", (dir / "assets" / "make.json").string(), "-o", (dir / "assets").string(), "--quiet"})
                .exit_code,
            0);
  ASSERT_TRUE(fs::exists(dir / "assets" / "dem.exr"));
  json outer = noise_asset();
  outer["interface"]["params"] = json::array();
  outer["nodes"] = {{{"id", "n"}, {"type", "Subgraph"}, {"asset", "noise.orogen-subgraph.json"}, {"asset_version", 1}},
                    {{"id", "read"}, {"type", "ReadHeightfield"}, {"params", {{"path", "dem.exr"}}}},
                    {{"id", "sum"}, {"type", "Add"}, {"inputs", {{"a", "n.out"}, {"b", "read.out"}}}},
                    {{"id", "flip"}, {"type", "Invert"}, {"inputs", {{"in", "sum.out"}}}}};
  outer["interface"]["inputs"][0]["to"] = "n.base";
  write_text(dir / "assets" / "outer.orogen-subgraph.json", outer.dump(2));
  json doc = graph_doc("assets/outer.orogen-subgraph.json");
  doc["nodes"][1].erase("params");
  const LoadResult loaded = load_doc(dir, doc);
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  Graph graph = *loaded.graph;
  Evaluator evaluator;
  const auto before = bytes_of(evaluate(evaluator, graph, {"inst"}), "inst");
  const MadeUnique made = make_instance_unique(graph, "inst");
  EXPECT_EQ(made.name, "outer");
  EXPECT_EQ(made.asset->graph.at("n").asset, "assets/noise.orogen-subgraph.json");
  EXPECT_EQ(std::get<std::string>(made.asset->graph.param("read", "path")), "assets/dem.exr");
  Evaluator fresh;
  EXPECT_EQ(bytes_of(evaluate(fresh, graph, {"inst"}), "inst"), before);
  save_graph_file(graph, dir / "unique.json");
  const LoadResult reloaded = load_graph_file(dir / "unique.json");
  ASSERT_TRUE(reloaded.ok()) << reloaded.error_text();
  EXPECT_EQ(bytes_of(evaluate(fresh, *reloaded.graph, {"inst"}), "inst"), before);
}

// `orogen subgraph make-unique`: in place or to -o, the written graph evaluates to the same files; refusals write
// nothing.
TEST(EmbeddedSubgraphs, TheCommandLineMakesAnInstanceUnique) {
  const fs::path dir = scratch_dir("embedded_cli");
  json doc = colors_doc();
  doc["nodes"].push_back({{"id", "save"},
                          {"type", "WriteImage"},
                          {"params", {{"path", "color.png"}}},
                          {"inputs", {{"in", "colors.color"}}}});
  const fs::path graph = dir / "g.json";
  write_text(graph, doc.dump(2));
  const std::string text = read_text(graph);
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {"subgraph", "make-unique"});
    return run_process(cli_binary(), args);
  };
  auto eval = [&](const fs::path& g, const fs::path& out) {
    const auto r = run_process(cli_binary(), {"eval", g.string(), "-o", out.string(), "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_text(out / "color.png");
  };
  const std::string before = eval(graph, dir / "before");
  ASSERT_FALSE(before.empty());

  // Refused, nothing written: not an instance, an unknown node, an output in another folder.
  auto refused = [&](const std::vector<std::string>& args, const std::string& message) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(read_text(graph), text);
  };
  refused({graph.string(), "--node", "base"}, "node 'base' is a FBM, not a subgraph instance");
  refused({graph.string(), "--node", "colours"}, "no node 'colours' in the graph (did you mean 'colors'?)");
  refused({graph.string(), "--node", "colors", "-o", (dir / "sub" / "u.json").string()}, "is not in the folder of");

  const auto r = run({graph.string(), "--node", "colors", "-o", (dir / "unique.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("instance 'colors' now uses the embedded asset \"#terrain_colors\" (a copy of "
                       "\"terrain_colors\""),
            std::string::npos)
      << r.out;
  EXPECT_EQ(read_text(graph), text);  // -o: the graph itself is unchanged
  const json unique = json::parse(read_text(dir / "unique.json"));
  EXPECT_EQ(unique["nodes"][1]["asset"], "#terrain_colors");
  EXPECT_TRUE(unique["subgraphs"].contains("terrain_colors"));
  EXPECT_EQ(eval(dir / "unique.json", dir / "after"), before);
  refused({graph.string(), "--node", "colors", "-o", (dir / "unique.json").string()}, "exists; choose another file");

  // In place; then the instance is unique already.
  ASSERT_EQ(run({graph.string(), "--node", "colors"}).exit_code, 0);
  EXPECT_EQ(read_text(graph), read_text(dir / "unique.json"));
  const auto again = run({graph.string(), "--node", "colors"});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("instance 'colors' is unique already"), std::string::npos) << again.err;
}

}  // namespace
}  // namespace orogen::test
