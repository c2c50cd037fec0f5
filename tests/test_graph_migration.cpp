// Graph file format version 2 (docs/conventions.md): primary ports `in`/`out`, American spelling. Files of
// version 1 with the old names still load, and evaluate to exactly the same results as their version-2
// rewrite; the rename table matches the registered node types; the example graphs are at the current version.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <variant>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/graph_migrations.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "graph/scene.h"
#include "support/rename_checks.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using ::testing::HasSubstr;

// Every node type whose names changed, wired as a version-1 file would have it.
const char* kVersion1 = R"({
  "format": "orogen-graph",
  "version": 1,
  "domain": {"size": [1000, 1000], "resolution": [65, 65]},
  "nodes": [
    {"id": "hill", "type": "Cone", "params": {"centre": [400, 600], "radius": 450, "height": 300}},
    {"id": "island", "type": "RadialFalloff", "params": {"centre": [500, 500], "radius": 480}},
    {"id": "shaped", "type": "Multiply", "inputs": {"a": "hill.height", "b": "island.mask"}},
    {"id": "slope", "type": "Slope", "inputs": {"height": "shaped.out"}},
    {"id": "aspect", "type": "Aspect", "inputs": {"height": "shaped.out"}, "params": {"output": "northness"}},
    {"id": "curvature", "type": "Curvature", "inputs": {"height": "shaped.out"}, "params": {"type": "plan"}},
    {"id": "normals", "type": "Normals", "inputs": {"height": "shaped.out"}},
    {"id": "steep", "type": "BandMask", "inputs": {"in": "slope.slope"}, "params": {"min": 20, "max": 90}},
    {"id": "color", "type": "ColorRamp", "inputs": {"in": "shaped.out"}},
    {"id": "mesh", "type": "HeightfieldToMesh", "inputs": {"height": "shaped.out", "colors": "color.image"},
     "params": {"max_error": 2}},
    {"id": "save_height", "type": "WriteHeightfield", "inputs": {"height": "shaped.out"}, "params": {"path": "h.r16"}},
    {"id": "save_color", "type": "WriteImage", "inputs": {"image": "color.image"}, "params": {"path": "c.png"}},
    {"id": "save_normals", "type": "WriteImage", "inputs": {"image": "normals.normals"}, "params": {"path": "n.exr"}},
    {"id": "save_mesh", "type": "WriteMesh", "inputs": {"mesh": "mesh.mesh"}, "params": {"path": "m.ply"}}
  ]
})";

// The same graph in version 2, written by hand.
const char* kVersion2 = R"({
  "format": "orogen-graph",
  "version": 2,
  "domain": {"size": [1000, 1000], "resolution": [65, 65]},
  "nodes": [
    {"id": "hill", "type": "Cone", "params": {"center": [400, 600], "radius": 450, "height": 300}},
    {"id": "island", "type": "RadialFalloff", "params": {"center": [500, 500], "radius": 480}},
    {"id": "shaped", "type": "Multiply", "inputs": {"a": "hill.out", "b": "island.out"}},
    {"id": "slope", "type": "Slope", "inputs": {"in": "shaped.out"}},
    {"id": "aspect", "type": "Aspect", "inputs": {"in": "shaped.out"}, "params": {"output": "northness"}},
    {"id": "curvature", "type": "Curvature", "inputs": {"in": "shaped.out"}, "params": {"type": "plan"}},
    {"id": "normals", "type": "Normals", "inputs": {"in": "shaped.out"}},
    {"id": "steep", "type": "BandMask", "inputs": {"in": "slope.out"}, "params": {"min": 20, "max": 90}},
    {"id": "color", "type": "ColorRamp", "inputs": {"in": "shaped.out"}},
    {"id": "mesh", "type": "HeightfieldToMesh", "inputs": {"in": "shaped.out", "colors": "color.out"},
     "params": {"max_error": 2}},
    {"id": "save_height", "type": "WriteHeightfield", "inputs": {"in": "shaped.out"}, "params": {"path": "h.r16"}},
    {"id": "save_color", "type": "WriteImage", "inputs": {"in": "color.out"}, "params": {"path": "c.png"}},
    {"id": "save_normals", "type": "WriteImage", "inputs": {"in": "normals.out"}, "params": {"path": "n.exr"}},
    {"id": "save_mesh", "type": "WriteMesh", "inputs": {"in": "mesh.out"}, "params": {"path": "m.ply"}}
  ]
})";

Graph load(const char* text) {
  const auto r = parse_graph(text);
  EXPECT_TRUE(r.ok()) << r.error_text();
  return r.ok() ? *r.graph : Graph{};
}

TEST(GraphMigration, Version1WithOldNamesLoadsAsTheVersion2Graph) {
  const Graph old_graph = load(kVersion1);
  const Graph new_graph = load(kVersion2);
  ASSERT_EQ(old_graph.nodes().size(), 14u);
  EXPECT_TRUE(old_graph == new_graph);
  EXPECT_EQ(serialize_graph(old_graph), serialize_graph(new_graph));
  EXPECT_THAT(serialize_graph(old_graph), HasSubstr("\"version\": " + std::to_string(kGraphFormatVersion) + ","));
}

bool same_bits(const PortValue& a, const PortValue& b) {
  if (a.index() != b.index()) return false;
  if (const auto* h = std::get_if<HeightfieldPtr>(&a)) {
    const auto& x = **h;
    const auto& y = *std::get<HeightfieldPtr>(b);
    return x.domain == y.domain && x.data.size() == y.data.size() &&
           std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)) == 0;
  }
  if (const auto* i = std::get_if<ImagePtr>(&a)) {
    const auto& x = **i;
    const auto& y = *std::get<ImagePtr>(b);
    return x.channels == y.channels && x.data.size() == y.data.size() &&
           std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)) == 0;
  }
  if (const auto* m = std::get_if<MeshPtr>(&a)) {
    const auto& x = (*m)->mesh;
    const auto& y = std::get<MeshPtr>(b)->mesh;
    if (x.n_vertices() != y.n_vertices() || x.n_faces() != y.n_faces()) return false;
    for (const auto v : x.vertices())
      if (x.point(v) != y.point(y.vertex_handle(v.idx()))) return false;
    return true;
  }
  return false;
}

std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GraphMigration, Version1FileEvaluatesIdentically) {
  const Graph old_graph = load(kVersion1);
  const Graph new_graph = load(kVersion2);
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {65, 65});
  const std::vector<std::string> nodes = {"slope", "aspect", "curvature", "normals", "steep", "color", "mesh"};
  const std::vector<std::pair<std::string, std::string>> files = {
      {"save_height", "h.r16"}, {"save_color", "c.png"}, {"save_mesh", "m.ply"}};

  auto run = [&](const Graph& g, const std::string& dir_name) {
    const auto dir = test::scratch_dir(dir_name);
    EvaluatorOptions options;
    Evaluator evaluator(options);
    evaluator.set_output_policy({dir, false});
    EvalRequest request;
    request.domain = d;
    request.nodes = nodes;
    for (const auto& [id, file] : files) request.nodes.push_back(id);
    auto result = evaluator.evaluate(g, request);
    EXPECT_TRUE(result.ok());
    return std::make_pair(std::move(result), dir);
  };
  const auto [old_result, old_dir] = run(old_graph, "migration-v1");
  const auto [new_result, new_dir] = run(new_graph, "migration-v2");
  for (const auto& id : nodes) {
    const auto a = old_result.output(id, "out", old_graph);
    const auto b = new_result.output(id, "out", new_graph);
    ASSERT_FALSE(std::holds_alternative<std::monostate>(a)) << id;
    EXPECT_TRUE(same_bits(a, b)) << id;
  }
  for (const auto& [id, file] : files) {
    const auto a = file_bytes(old_dir / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, file_bytes(new_dir / file)) << file;
  }
}

TEST(GraphMigration, OutputRenamesFollowTheSourceNodesTypeOnly) {
  // A link reading "x.mask" is renamed only when x is a node whose "mask" output was renamed; an input
  // named "mask" of another type (Blend) is left alone.
  nlohmann::json file = nlohmann::json::parse(R"({"format": "orogen-graph", "version": 1, "nodes": [
    {"id": "r", "type": "RadialFalloff"}, {"id": "k", "type": "Constant"},
    {"id": "b", "type": "Blend", "inputs": {"a": "k.out", "b": "k.out", "mask": "r.mask"}},
    {"id": "p", "type": "WritePoints", "inputs": {"points": "elsewhere.points"}},
    {"id": "dup", "type": "WriteHeightfield", "inputs": {"height": "k.out", "in": "k.out"}}]})");
  migrate_graph_v1_to_v2(file);
  EXPECT_EQ(file["nodes"][2]["inputs"], nlohmann::json::parse(R"({"a": "k.out", "b": "k.out", "mask": "r.out"})"));
  EXPECT_EQ(file["nodes"][3]["inputs"], nlohmann::json::parse(R"({"in": "elsewhere.points"})"));
  // Both names given: nothing is dropped, the loader reports the old one as unknown.
  EXPECT_EQ(file["nodes"][4]["inputs"], nlohmann::json::parse(R"({"height": "k.out", "in": "k.out"})"));
  // Malformed files are left for the loader to report.
  for (const char* text :
       {R"([])", R"({"nodes": 3})", R"({"nodes": [1, {"type": 2}, {"id": "x", "type": "Slope", "inputs": 4}]})"}) {
    auto j = nlohmann::json::parse(text);
    const auto before = j;
    EXPECT_NO_THROW(migrate_graph_v1_to_v2(j));
    EXPECT_EQ(j, before);
  }
}

TEST(GraphMigration, RenameTableMatchesTheRegistry) { test::expect_renames_match_registry(format_v1_renames()); }

// The convention itself (docs/conventions.md), over every registered type: a single primary input is `in`
// unless the type is a binary op (a, b) or a generator; a single output is `out`; nothing a user types is
// spelled British.
TEST(GraphMigration, EveryNodeFollowsThePortAndSpellingConvention) {
  const std::vector<std::string> british = {"colour", "centre", "normalis", "grey", "neighbour", "analys"};
  auto check_word = [&](const std::string& what, const std::string& word) {
    for (const auto& b : british) {
      EXPECT_EQ(word.find(b), std::string::npos) << what << ": '" << word << "'";
    }
  };
  for (const NodeType* t : NodeRegistry::instance().all()) {
    check_word("type", t->name);
    if (t->outputs.size() == 1) {
      EXPECT_EQ(t->outputs[0].name, "out") << t->name;
    }
    std::set<std::string> required;
    for (const auto& p : t->inputs) {
      check_word(t->name + " input", p.name);
      if (!p.optional) required.insert(p.name);
    }
    if (required.size() == 1) {
      EXPECT_EQ(*required.begin(), "in") << t->name;
    }
    for (const auto& p : t->params) {
      check_word(t->name + " param", p.name);
      for (const auto& c : p.choices) check_word(t->name + "." + p.name + " choice", c);
    }
  }
}

// Version 4: WriteScene takes a Scene from Instance. A version-3 writer with points, class meshes and
// proxies off, an id that collides with the first choice of the inserted node, and editor positions.
const char* kVersion3Scene = R"({
  "format": "orogen-graph",
  "version": 3,
  "domain": {"size": [200, 200], "resolution": [33, 33]},
  "nodes": [
    {"id": "h", "type": "Cone", "params": {"center": [100, 100], "radius": 90, "height": 40}},
    {"id": "pts", "type": "PoissonDisk", "inputs": {"height": "h.out"},
      "params": {"class_count": 2, "radius_0": 20, "radius_1": 25}},
    {"id": "rock", "type": "HullRock"},
    {"id": "terrain", "type": "HeightfieldToMesh", "inputs": {"in": "h.out"}},
    {"id": "write_instance", "type": "Constant"},
    {"id": "write", "type": "WriteScene",
     "inputs": {"in": "pts.out", "terrain": "terrain.out", "mesh_1": "rock.out"},
     "params": {"path": "s.glb", "proxies": false}},
    {"id": "loose", "type": "WriteScene", "inputs": {"in": "pts.out"}, "params": {"path": "t.gltf"}}
  ],
  "editor": {"positions": {"h": [0, 0], "write": [500, 40]}}
})";

// The same graph in version 4, written by hand.
const char* kVersion4Scene = R"({
  "format": "orogen-graph",
  "version": 4,
  "domain": {"size": [200, 200], "resolution": [33, 33]},
  "nodes": [
    {"id": "h", "type": "Cone", "params": {"center": [100, 100], "radius": 90, "height": 40}},
    {"id": "pts", "type": "PoissonDisk", "inputs": {"height": "h.out"},
      "params": {"class_count": 2, "radius_0": 20, "radius_1": 25}},
    {"id": "rock", "type": "HullRock"},
    {"id": "terrain", "type": "HeightfieldToMesh", "inputs": {"in": "h.out"}},
    {"id": "write_instance", "type": "Constant"},
    {"id": "write", "type": "WriteScene", "inputs": {"in": "write_instance_2.out", "terrain": "terrain.out"},
     "params": {"path": "s.glb"}},
    {"id": "loose", "type": "WriteScene", "inputs": {"in": "loose_instance.out"}, "params": {"path": "t.gltf"}},
    {"id": "write_instance_2", "type": "Instance", "inputs": {"in": "pts.out", "mesh_1": "rock.out"},
     "params": {"missing_mesh": "skip"}},
    {"id": "loose_instance", "type": "Instance", "inputs": {"in": "pts.out"}, "params": {"missing_mesh": "proxy"}}
  ],
  "editor": {"positions": {"h": [0, 0], "write": [730, 40], "write_instance_2": [500, 40]}}
})";

TEST(GraphMigration, Version3SceneWriterGetsAnInstanceNode) {
  const Graph old_graph = load(kVersion3Scene);
  const Graph new_graph = load(kVersion4Scene);
  ASSERT_EQ(old_graph.nodes().size(), 9u);
  EXPECT_EQ(old_graph.at("write_instance_2").type->name, "Instance");
  EXPECT_EQ(old_graph.at("write").inputs.at("in"), (PortRef{"write_instance_2", "out"}));
  EXPECT_EQ(old_graph.at("write_instance_2").inputs.at("mesh_1"), (PortRef{"rock", "out"}));
  EXPECT_EQ(std::get<std::string>(old_graph.param("loose_instance", "missing_mesh")), "proxy");
  EXPECT_TRUE(old_graph == new_graph);
  EXPECT_EQ(serialize_graph(old_graph), serialize_graph(new_graph));

  // It evaluates: the writer writes the instances of class 1 (class 0 had no mesh and proxies were off).
  const auto dir = test::scratch_dir("migration-v3-scene");
  Evaluator evaluator{EvaluatorOptions{}};
  evaluator.set_output_policy({dir, false});
  EvalRequest request;
  request.domain = old_graph.domain.to_domain();
  request.nodes = {"write", "loose", "write_instance_2", "pts"};
  const auto result = evaluator.evaluate(old_graph, request);
  ASSERT_TRUE(result.ok());
  const auto scene = std::get<ScenePtr>(result.output("write_instance_2", "out", old_graph));
  const auto points = std::get<PointsPtr>(result.output("pts", "out", old_graph));
  std::size_t class_1 = 0;
  for (const auto c : points->class_id) class_1 += c == 1 ? 1 : 0;
  ASSERT_GT(class_1, 0u);
  ASSERT_LT(class_1, points->size());
  EXPECT_EQ(scene->size(), class_1);
  EXPECT_TRUE(std::filesystem::exists(dir / "s.glb"));
  EXPECT_TRUE(std::filesystem::exists(dir / "t.gltf"));
}

TEST(GraphMigration, Version3MigrationLeavesOtherFilesAlone) {
  nlohmann::json file = nlohmann::json::parse(kVersion1);
  const auto before = file;
  migrate_graph_v3_to_v4(file);
  EXPECT_EQ(file, before);
  for (const char* text :
       {R"([])", R"({"nodes": 3})",
        R"({"nodes": [1, {"type": "WriteScene"}, {"id": "x", "type": "WriteScene", "inputs": 4}]})"}) {
    auto j = nlohmann::json::parse(text);
    const auto original = j;
    EXPECT_NO_THROW(migrate_graph_v3_to_v4(j));
    EXPECT_EQ(j, original);
  }
}

TEST(GraphMigration, ExampleGraphsAreAtTheCurrentVersion) {
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "graphs")) {
    if (entry.path().extension() != ".json") continue;
    const auto j = nlohmann::json::parse(test::read_text(entry.path()));
    EXPECT_EQ(j.at("version").get<int>(), kGraphFormatVersion) << entry.path();
  }
}

// The README and docs link only to files inside the repository that exist (no ../shared/...).
TEST(Docs, LinksStayInsideTheRepository) {
  const auto root = std::filesystem::weakly_canonical(test::source_dir());
  for (const char* doc : {"README.md", "docs/architecture.md", "docs/conventions.md", "editor/README.md"}) {
    const auto file = root / doc;
    ASSERT_TRUE(std::filesystem::exists(file)) << doc;
    std::string text = test::read_text(file);
    // Code blocks are not links ([](ExecContext& ctx) ...).
    for (auto open = text.find("```"); open != std::string::npos; open = text.find("```")) {
      const auto close = text.find("```", open + 3);
      text.erase(open, close == std::string::npos ? std::string::npos : close + 3 - open);
    }
    for (std::size_t at = text.find("]("); at != std::string::npos; at = text.find("](", at + 2)) {
      const auto end = text.find(')', at);
      std::string target = text.substr(at + 2, end - at - 2);
      if (target.rfind("http", 0) == 0 || target.empty() || target[0] == '#') continue;
      target = target.substr(0, target.find('#'));
      const auto resolved = std::filesystem::weakly_canonical(file.parent_path() / target);
      EXPECT_TRUE(std::filesystem::exists(resolved)) << doc << " links to missing " << target;
      EXPECT_EQ(resolved.string().rfind(root.string(), 0), 0u) << doc << " links outside the repository: " << target;
    }
  }
}

}  // namespace
}  // namespace orogen
