// Subgraphs in the editor: library assets in the palette, grouping and ungrouping (the interface is exactly
// what the links crossing the selection need, evaluation is bit for bit unchanged, undo restores the exact
// document), entering an instance, editing its asset (written to the file, seen by every instance, undo
// steps included) and leaving.
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "editor/model/asset_palette.h"
#include "editor/model/canvas_controller.h"
#include "editor/model/evaluation_controller.h"
#include "editor/model/exposed_params.h"
#include "editor/model/grouping.h"
#include "editor/model/palette.h"
#include "editor/model/subgraph_navigation.h"
#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/points.h"
#include "graph/subgraph.h"
#include "graph/subgraph_extract.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// s1, s2 -> a = blend(s1, s2) -> b = blend(a, s1) -> fin = blend(b); pts = scatter(a).
// Grouping {a, b} crosses: s1 into a.a and b.b (one input), s2 into a.b, a.out to pts, b.out to fin.
Graph diamond_graph() {
  Graph g;
  g.domain.size = {1000.0, 1000.0};
  g.domain.resolution = {48, 48};
  g.add_node("EdSource", "s1");
  g.add_node("EdSource", "s2");
  g.add_node("EdBlend", "a");
  g.add_node("EdBlend", "b");
  g.add_node("EdBlend", "fin");
  g.add_node("EdScatter", "pts");
  g.set_param("s1", "seed", ParamValue(std::uint64_t{5}));
  g.set_param("s2", "tilt", 0.3);
  g.set_param("a", "weight", 0.25);
  g.set_param("b", "mode", std::string("max"));
  g.set_param("b", "weight", 0.75);
  g.connect({"s1", "out"}, "a", "a");
  g.connect({"s2", "out"}, "a", "b");
  g.connect({"a", "out"}, "b", "a");
  g.connect({"s1", "out"}, "b", "b");
  g.connect({"b", "out"}, "fin", "a");
  g.connect({"a", "out"}, "pts", "height");
  g.editor.positions = {{"s1", {0, 0}},  {"s2", {0, 200}},  {"a", {300, 40}},
                        {"b", {600, 0}}, {"fin", {900, 0}}, {"pts", {900, 200}}};
  return g;
}

// The raw bytes of `fin`'s heightfield and of the scattered points' heights.
std::vector<unsigned char> evaluate_bytes(const Graph& graph, std::vector<std::string> nodes = {"fin", "pts"}) {
  Evaluator evaluator;
  EvalRequest request;
  request.domain = graph.domain.to_domain();
  request.nodes = nodes;
  const EvalResult r = evaluator.evaluate(graph, request);
  std::vector<unsigned char> out;
  for (const auto& id : nodes) {
    const auto it = r.outputs.find(id);
    EXPECT_NE(it, r.outputs.end()) << id << " did not evaluate";
    if (it == r.outputs.end()) continue;
    for (const auto& v : it->second) {
      if (const auto* h = std::get_if<HeightfieldPtr>(&v)) {
        const auto* p = reinterpret_cast<const unsigned char*>((*h)->data.data());
        out.insert(out.end(), p, p + (*h)->data.size() * sizeof(float));
      } else if (const auto* pts = std::get_if<PointsPtr>(&v)) {
        for (std::size_t k = 0; k < (*pts)->size(); ++k) {
          const float z = (*pts)->position[k].z;
          const auto* p = reinterpret_cast<const unsigned char*>(&z);
          out.insert(out.end(), p, p + sizeof z);
        }
      }
    }
  }
  EXPECT_FALSE(out.empty());
  return out;
}

// The diamond graph saved in a fresh folder, opened as a document.
Document saved_diamond(const std::string& name, fs::path* dir_out = nullptr) {
  const fs::path dir = test::scratch_dir(name);
  save_graph_file(diamond_graph(), dir / "g.json");
  if (dir_out) *dir_out = dir;
  return Document::open(dir / "g.json");
}

// A second instance "twin" of the group's asset, fed as the group is (one undo step, "second"); with a reader,
// also "fin2", which reads twin's output as "fin" reads the group's.
void add_twin(Document& root, const GroupResult& r, bool with_reader) {
  root.edit("second", [&](Graph& g) {
    const std::string reference = g.at(r.instance).asset;  // a copy: adding a node may move the nodes
    Node& copy = add_subgraph_instance(g, *r.asset, reference, "twin");
    copy.inputs = g.at(r.instance).inputs;
    if (!with_reader) return;
    g.add_node("EdBlend", "fin2");
    g.connect({"twin", g.at("fin").inputs.at("a").port}, "fin2", "a");
  });
}

// Grouping uses the core's extraction (graph/subgraph_extract.h), with writers allowed.
TEST(EditorSubgraphs, PlanListsExactlyTheLinksCrossingTheSelection) {
  ExtractRequest request;
  request.nodes = {"b", "a"};
  request.asset_file = "group.orogen-subgraph.json";
  request.graph_file = "g.json";
  request.allow_writers = true;
  const Extraction plan = make_subgraph_asset(diamond_graph(), request);
  ASSERT_EQ(plan.inputs.size(), 2u);
  EXPECT_EQ(plan.inputs[0].source, (PortRef{"s1", "out"}));  // one input for one outside output ...
  ASSERT_EQ(plan.inputs[0].targets.size(), 2u);              // ... however many inputs it feeds
  EXPECT_EQ(plan.inputs[0].targets[0].str(), "a.a");
  EXPECT_EQ(plan.inputs[0].targets[1].str(), "b.b");
  EXPECT_EQ(plan.inputs[1].source, (PortRef{"s2", "out"}));
  ASSERT_EQ(plan.inputs[1].targets.size(), 1u);
  EXPECT_EQ(plan.inputs[1].targets[0].str(), "a.b");
  EXPECT_EQ(plan.inputs[0].name, "a");
  EXPECT_EQ(plan.inputs[1].name, "b");
  ASSERT_EQ(plan.outputs.size(), 2u);
  EXPECT_EQ(plan.outputs[0].source, (PortRef{"a", "out"}));
  ASSERT_EQ(plan.outputs[0].sinks.size(), 1u);
  EXPECT_EQ(plan.outputs[0].sinks[0], (std::pair<std::string, std::string>{"pts", "height"}));
  EXPECT_EQ(plan.outputs[1].source, (PortRef{"b", "out"}));
  EXPECT_EQ(plan.outputs[1].sinks[0], (std::pair<std::string, std::string>{"fin", "a"}));
  EXPECT_EQ(plan.outputs[0].name, "out");
  EXPECT_EQ(plan.outputs[1].name, "b_out");  // taken: named after its node
}

TEST(EditorSubgraphs, GroupWritesAnAssetWhoseInterfaceIsTheCrossingLinks) {
  fs::path dir;
  Document doc = saved_diamond("group-interface", &dir);
  const GroupResult r = group_nodes(doc, {"a", "b"});
  EXPECT_EQ(r.asset_file, dir / "group.orogen-subgraph.json");
  ASSERT_TRUE(fs::exists(r.asset_file));
  // The file as a library would load it.
  const AssetLoad load = load_subgraph_asset("group.orogen-subgraph.json", dir);
  ASSERT_TRUE(load.asset) << load.error;
  const SubgraphInterface& in = load.asset->interface();
  ASSERT_EQ(in.inputs.size(), 2u);
  EXPECT_EQ(in.inputs[0].targets.size(), 2u);
  EXPECT_EQ(in.inputs[0].port.type, PortType::Heightfield);
  EXPECT_FALSE(in.inputs[0].port.optional);  // a.a is required
  EXPECT_TRUE(in.inputs[1].port.optional);   // a.b alone, and optional
  ASSERT_EQ(in.outputs.size(), 2u);
  EXPECT_EQ(in.outputs[0].source, (PortRef{"a", "out"}));
  EXPECT_EQ(in.outputs[1].source, (PortRef{"b", "out"}));
  EXPECT_TRUE(in.params.empty());
  // Inside: exactly the selection, with its parameters and inner link, positions from 0,0.
  ASSERT_EQ(load.asset->graph.nodes().size(), 2u);
  EXPECT_EQ(load.asset->graph.at("b").inputs.at("a"), (PortRef{"a", "out"}));
  EXPECT_EQ(load.asset->graph.at("b").inputs.count("b"), 0u);  // fed by the interface
  EXPECT_EQ(std::get<std::string>(load.asset->graph.param("b", "mode")), "max");
  EXPECT_EQ(load.asset->graph.editor.positions.at("b"), glm::dvec2(300, 0));

  // The graph: the selection is gone, one instance wired the same way.
  const Graph& g = doc.graph();
  EXPECT_FALSE(g.find("a"));
  EXPECT_FALSE(g.find("b"));
  const Node& inst = g.at(r.instance);
  EXPECT_EQ(inst.asset, "group.orogen-subgraph.json");
  EXPECT_EQ(inst.inputs.at(in.inputs[0].port.name), (PortRef{"s1", "out"}));
  EXPECT_EQ(inst.inputs.at(in.inputs[1].port.name), (PortRef{"s2", "out"}));
  EXPECT_EQ(g.at("fin").inputs.at("a"), (PortRef{r.instance, in.outputs[1].port.name}));
  EXPECT_EQ(g.at("pts").inputs.at("height"), (PortRef{r.instance, in.outputs[0].port.name}));
  EXPECT_EQ(g.editor.positions.at(r.instance), glm::dvec2(300, 0));  // where the selection started
  // A second group does not overwrite the first asset.
  EXPECT_EQ(free_asset_path(dir), dir / "group2.orogen-subgraph.json");
}

TEST(EditorSubgraphs, GroupAndUngroupLeaveEvaluationBitIdentical) {
  Document doc = saved_diamond("group-eval");
  const auto before = evaluate_bytes(doc.graph());
  const GroupResult r = group_nodes(doc, {"a", "b"});
  EXPECT_EQ(evaluate_bytes(doc.graph()), before);
  // Saved and opened again: the file form evaluates the same too.
  doc.save();
  const Document reopened = Document::open(doc.path());
  EXPECT_TRUE(reopened.load_problems().empty());
  EXPECT_EQ(evaluate_bytes(reopened.graph()), before);

  const auto added = ungroup_node(doc, r.instance);
  EXPECT_EQ(added, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(evaluate_bytes(doc.graph()), before);
  // Ungroup gives back the nodes, parameters, links and positions the group took.
  const Graph original = diamond_graph();
  ASSERT_EQ(doc.graph().nodes().size(), original.nodes().size());
  for (const auto& n : original.nodes()) {
    const Node* m = doc.graph().find(n.id);
    ASSERT_TRUE(m) << n.id;
    EXPECT_TRUE(*m == n) << n.id;
    EXPECT_EQ(doc.graph().editor.positions.at(n.id), original.editor.positions.at(n.id)) << n.id;
  }
}

TEST(EditorSubgraphs, UndoRestoresTheExactDocumentAndRedoTheGroup) {
  Document doc = saved_diamond("group-undo");
  const Graph before = doc.graph();
  const std::string before_text = serialize_graph(before);
  const GroupResult r = group_nodes(doc, {"a", "b"});
  const Graph grouped = doc.graph();
  EXPECT_EQ(doc.history().undo_size(), 1u);  // one step
  EXPECT_EQ(doc.history().undo_label(), "Group 2 nodes into group");
  ASSERT_TRUE(doc.undo());
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_EQ(serialize_graph(doc.graph()), before_text);
  EXPECT_FALSE(doc.dirty());
  ASSERT_TRUE(doc.redo());
  EXPECT_TRUE(doc.graph() == grouped);

  ungroup_node(doc, r.instance);
  ASSERT_TRUE(doc.undo());
  EXPECT_TRUE(doc.graph() == grouped);
  ASSERT_TRUE(doc.undo());
  EXPECT_EQ(serialize_graph(doc.graph()), before_text);
}

TEST(EditorSubgraphs, GroupRefusesWhatWouldFeedItselfAndChangesNothing) {
  fs::path dir;
  Document doc = saved_diamond("group-cycle", &dir);
  const Graph before = doc.graph();
  // a -> b -> fin: grouping {a, fin} leaves b both fed by the group and feeding it.
  try {
    group_nodes(doc, {"a", "fin"});
    FAIL() << "expected a refusal";
  } catch (const DocumentError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot group: the selection is not convex: node 'b' (not selected) is fed "
                                         "by selected node 'a' and feeds selected node 'fin'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_FALSE(doc.history().can_undo());
  EXPECT_FALSE(fs::exists(dir / "group.orogen-subgraph.json"));
  // An untitled graph has no folder for the asset unless one is given.
  Document untitled(diamond_graph());
  EXPECT_THROW(group_nodes(untitled, {"a"}), DocumentError);
  const GroupResult r = group_nodes(untitled, {"a"}, dir / "sub" / ".." / "chosen.orogen-subgraph.json");
  EXPECT_EQ(r.asset_file, dir / "chosen.orogen-subgraph.json");
  EXPECT_TRUE(fs::exists(r.asset_file));
}

TEST(EditorSubgraphs, GroupingAnInstanceNestsIt) {
  fs::path dir;
  Document doc = saved_diamond("group-nested", &dir);
  const auto before = evaluate_bytes(doc.graph());
  const GroupResult inner = group_nodes(doc, {"a"});
  const GroupResult outer = group_nodes(doc, {inner.instance, "b"}, dir / "lib" / "outer.orogen-subgraph.json");
  EXPECT_EQ(evaluate_bytes(doc.graph()), before);
  // The nested reference was rebased to the asset's own folder.
  const AssetLoad load = load_subgraph_asset(outer.asset_file.string(), {});
  ASSERT_TRUE(load.asset) << load.error;
  EXPECT_EQ(load.asset->graph.at(inner.instance).asset, "../group.orogen-subgraph.json");
}

TEST(EditorSubgraphs, EnteringEditsTheAssetFileAndEveryInstanceSeesIt) {
  fs::path dir;
  Document root = saved_diamond("enter", &dir);
  const GroupResult r = group_nodes(root, {"a", "b"});
  // A second instance of the same asset, fed the same way, read by a second consumer.
  add_twin(root, r, true);
  root.save();
  const std::string asset_before = read_file(r.asset_file);
  const auto before = evaluate_bytes(root.graph(), {"fin", "fin2"});

  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  EXPECT_EQ(&nav.current(), &inner);
  EXPECT_EQ(nav.breadcrumbs(), (std::vector<std::string>{"g.json", r.instance + " (group)"}));
  EXPECT_EQ(inner.path(), r.asset_file);
  ASSERT_TRUE(inner.graph().find("b"));
  inner.set_param("a", "weight", 0.9);
  EXPECT_EQ(nav.sync(), "");
  // The file has the edit, and both instances evaluate it: as if a's weight were 0.9 inline.
  EXPECT_NE(read_file(r.asset_file), asset_before);
  EXPECT_DOUBLE_EQ(std::get<double>(load_graph_file(r.asset_file).graph->param("a", "weight")), 0.9);
  Graph inline_edit = diamond_graph();
  inline_edit.set_param("a", "weight", 0.9);
  const auto edited = evaluate_bytes(inline_edit, {"fin"});
  const auto both = evaluate_bytes(root.graph(), {"fin", "fin2"});
  EXPECT_NE(both, before);
  ASSERT_EQ(both.size(), 2 * edited.size());
  EXPECT_TRUE(std::equal(edited.begin(), edited.end(), both.begin()));
  EXPECT_TRUE(std::equal(edited.begin(), edited.end(), both.begin() + static_cast<std::ptrdiff_t>(edited.size())));
  EXPECT_FALSE(root.dirty());  // the graph file itself did not change

  // The root's undo steps see the file's content too: undoing the twin keeps the edited asset.
  ASSERT_TRUE(root.undo());
  EXPECT_EQ(evaluate_bytes(root.graph(), {"fin"}), edited);
  ASSERT_TRUE(root.redo());

  // Undo inside writes the file back as it was; every instance follows.
  ASSERT_TRUE(inner.undo());
  EXPECT_EQ(nav.sync(), "");
  EXPECT_EQ(read_file(r.asset_file), asset_before);
  EXPECT_EQ(evaluate_bytes(root.graph(), {"fin", "fin2"}), before);

  EXPECT_TRUE(nav.leave());
  EXPECT_EQ(&nav.current(), &root);
  EXPECT_FALSE(nav.leave());
}

TEST(EditorSubgraphs, AnEditThatBreaksTheAssetIsNotWritten) {
  Document root = saved_diamond("enter-broken");
  const GroupResult r = group_nodes(root, {"a", "b"});
  const std::string asset_before = read_file(r.asset_file);
  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  inner.remove_nodes({"b"});  // the interface presents b.out and feeds b.b
  const std::string error = nav.sync();
  EXPECT_NE(error.find("asset 'group' not saved"), std::string::npos) << error;
  EXPECT_NE(error.find("'b'"), std::string::npos) << error;
  EXPECT_EQ(read_file(r.asset_file), asset_before);
  EXPECT_EQ(root.graph().at(r.instance).type->subgraph, r.asset);
  EXPECT_FALSE(nav.leave());  // leaving would lose the edit: stay
  EXPECT_TRUE(nav.inside());
  inner.undo();
  EXPECT_EQ(nav.sync(), "");
  EXPECT_EQ(nav.sync_error(), "");
  EXPECT_TRUE(nav.leave());
}

TEST(EditorSubgraphs, AnInstanceShowsTheStateOfItsInnerNodes) {
  Document root = saved_diamond("instance-state");
  const GroupResult r = group_nodes(root, {"a", "b"});
  EvaluationController evaluation;
  evaluation.request_preview(root.graph(), {"fin"}, root.content_revision());
  evaluation.wait_idle();
  const NodeRunState s = evaluation.node_state(r.instance);
  EXPECT_EQ(s.phase, NodeRunState::Phase::Computed);
  const double inner_ms =
      evaluation.node_state(r.instance + "/a").milliseconds + evaluation.node_state(r.instance + "/b").milliseconds;
  EXPECT_DOUBLE_EQ(s.milliseconds, inner_ms);
  EXPECT_EQ(evaluation.node_states().at(r.instance).phase, NodeRunState::Phase::Computed);  // what the canvas shows
  // An edit inside the asset runs the instance again; what feeds it is cached.
  SubgraphNavigator nav(root);
  nav.enter(r.instance).set_param("a", "weight", 0.9);
  ASSERT_EQ(nav.sync(), "");
  evaluation.request_preview(root.graph(), {"fin"}, root.content_revision());
  evaluation.wait_idle();
  EXPECT_EQ(evaluation.node_state(r.instance).phase, NodeRunState::Phase::Computed);
  EXPECT_EQ(evaluation.node_state("s1").phase, NodeRunState::Phase::Cached);
}

TEST(EditorSubgraphs, ExposingAnInnerParameterReachesEveryInstance) {
  Document root = saved_diamond("expose");
  const GroupResult r = group_nodes(root, {"a", "b"});
  root.save();
  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  EXPECT_EQ(exposed_as(inner.graph(), "a", "weight"), "");
  EXPECT_EQ(set_exposed(inner, "a", "weight", true), "weight");
  EXPECT_EQ(exposed_as(inner.graph(), "a", "weight"), "weight");
  EXPECT_EQ(set_exposed(inner, "b", "weight", true), "b_weight");  // the name is taken: made unique
  ASSERT_EQ(nav.sync(), "");
  // The instance has the parameters, declared as the inner ones (range, unit, default = the inner value).
  const NodeType& type = *root.graph().at(r.instance).type;
  ASSERT_EQ(type.params.size(), 2u);
  EXPECT_EQ(type.params[0].name, "weight");
  EXPECT_EQ(std::get<double>(type.params[0].default_value), 0.25);
  EXPECT_EQ(type.params[0].max, 1.0);
  EXPECT_EQ(type.version, 3);  // one version per interface change
  EXPECT_TRUE(root.dirty());   // the graph file records the version and interface it was made with
  // Setting it on the instance evaluates as the inline graph with that value.
  root.set_param(r.instance, "weight", 0.9);
  Graph inline_edit = diamond_graph();
  inline_edit.set_param("a", "weight", 0.9);
  EXPECT_EQ(evaluate_bytes(root.graph()), evaluate_bytes(inline_edit));
  root.save();
  const LoadResult reopened = load_graph_file(root.path());
  EXPECT_TRUE(reopened.ok()) << reopened.error_text();

  // Hiding is the reverse, and undo inside brings the exposed parameter back.
  set_exposed(inner, "a", "weight", false);
  EXPECT_EQ(exposed_as(inner.graph(), "a", "weight"), "");
  EXPECT_EQ(exposed_as(inner.graph(), "b", "weight"), "b_weight");
  ASSERT_TRUE(inner.undo());
  EXPECT_EQ(exposed_as(inner.graph(), "a", "weight"), "weight");
  // A plain graph has nothing to expose.
  EXPECT_THROW(set_exposed(root, "fin", "weight", true), DocumentError);
}

TEST(EditorSubgraphs, InnerNodesArePreviewedWithTheInstancesInputs) {
  Document root = saved_diamond("context");
  const GroupResult r = group_nodes(root, {"a", "b"});
  SubgraphNavigator nav(root);
  const Document& inner = nav.enter(r.instance);
  EvaluationController evaluation;
  evaluation.set_context(nav.instance_path() + "/");
  // The asset's own ids, evaluated inside the root graph: b's input comes from s1 outside.
  evaluation.request_preview(root.graph(), {"b"}, root.content_revision());
  evaluation.wait_idle();
  const auto result = evaluation.preview();
  ASSERT_TRUE(result);
  EXPECT_EQ(result->error, "");
  EXPECT_EQ(result->requested, (std::vector<std::string>{"b"}));
  ASSERT_TRUE(result->outputs.count("b"));
  EXPECT_EQ(evaluation.node_state("a").phase, NodeRunState::Phase::Computed);
  EXPECT_EQ(evaluation.node_state("s1").phase, NodeRunState::Phase::Unknown);  // outside: not this level's
  const auto& field = *std::get<HeightfieldPtr>(result->outputs.at("b").front());
  // Bit for bit the inline graph's b at the same (preview) domain.
  Graph plain = diamond_graph();
  Evaluator evaluator;
  EvalRequest request;
  request.domain = result->domain;
  request.nodes = {"b"};
  const EvalResult expected = evaluator.evaluate(plain, request);
  const auto& want = *std::get<HeightfieldPtr>(expected.outputs.at("b").front());
  ASSERT_EQ(field.data.size(), want.data.size());
  EXPECT_EQ(std::memcmp(field.data.data(), want.data.data(), want.data.size() * sizeof(float)), 0);
  // Thumbnails of the level's nodes, by their ids.
  evaluation.request_thumbnails(root.graph(), root.content_revision(), &inner.graph());
  evaluation.wait_idle();
  const auto thumbs = evaluation.thumbnails();
  ASSERT_TRUE(thumbs);
  EXPECT_TRUE(thumbs->outputs.count("a") && thumbs->outputs.count("b"));
  EXPECT_EQ(thumbs->outputs.size(), 2u);
  // Back at the root, ids are the root's again.
  evaluation.set_context("");
  evaluation.request_preview(root.graph(), {"fin"}, root.content_revision());
  evaluation.wait_idle();
  EXPECT_TRUE(evaluation.preview()->outputs.count("fin"));
}

TEST(EditorSubgraphs, RenamingAnInnerNodeKeepsTheInterface) {
  Document root = saved_diamond("rename-inner");
  const GroupResult r = group_nodes(root, {"a", "b"});
  const auto before = evaluate_bytes(root.graph());
  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  set_exposed(inner, "a", "weight", true);
  inner.rename_node("a", "first");
  EXPECT_EQ(exposed_as(inner.graph(), "first", "weight"), "weight");
  ASSERT_EQ(nav.sync(), "");
  const SubgraphInterface& in = root.graph().at(r.instance).type->subgraph->interface();
  EXPECT_EQ(in.inputs[0].targets[0].str(), "first.a");
  EXPECT_EQ(in.outputs[0].source, (PortRef{"first", "out"}));
  EXPECT_EQ(evaluate_bytes(root.graph()), before);
  ASSERT_TRUE(inner.undo());
  EXPECT_EQ(exposed_as(inner.graph(), "a", "weight"), "weight");
}

TEST(EditorSubgraphs, AnAssetContainingItselfIsNotWritten) {
  Document root = saved_diamond("self");
  const GroupResult r = group_nodes(root, {"a", "b"});
  const std::string asset_before = read_file(r.asset_file);
  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  inner.edit("self", [&](Graph& g) { add_subgraph_instance(g, *r.asset, "group.orogen-subgraph.json", "me"); });
  const std::string error = nav.sync();
  EXPECT_NE(error.find("contains itself"), std::string::npos) << error;
  EXPECT_EQ(read_file(r.asset_file), asset_before);
}

TEST(EditorSubgraphs, EnteringRefusesPlainNodes) {
  Document root = saved_diamond("enter-plain");
  SubgraphNavigator nav(root);
  EXPECT_THROW(nav.enter("a"), DocumentError);
  EXPECT_THROW(nav.enter("nope"), DocumentError);
  EXPECT_FALSE(nav.inside());
}

// Make unique: one undo step, evaluation unchanged, the file asset and its other instances untouched.
TEST(EditorSubgraphs, MakeUniqueEmbedsACopyInOneUndoStep) {
  fs::path dir;
  Document root = saved_diamond("make-unique", &dir);
  const GroupResult r = group_nodes(root, {"a", "b"});
  add_twin(root, r, false);
  root.save();
  const Graph before = root.graph();
  const auto bytes = evaluate_bytes(root.graph());
  const std::size_t steps = root.history().undo_size();

  EXPECT_EQ(make_unique_node(root, r.instance), "group");
  const Node& inst = root.graph().at(r.instance);
  EXPECT_EQ(inst.asset, "#group");
  ASSERT_TRUE(inst.type->subgraph);
  EXPECT_EQ(inst.type->subgraph->embedded, "group");
  EXPECT_EQ(root.graph().at("twin").type->subgraph, r.asset);  // the other instance keeps the file
  EXPECT_EQ(root.history().undo_size(), steps + 1);
  EXPECT_EQ(root.history().undo_label(), "Make " + r.instance + " unique (#group)");
  EXPECT_TRUE(root.dirty());
  EXPECT_EQ(evaluate_bytes(root.graph()), bytes);
  // Saved: the file holds the copy; opened again it evaluates the same.
  root.save();
  const Document reopened = Document::open(root.path());
  EXPECT_TRUE(reopened.load_problems().empty()) << reopened.load_problems().diagnostics.front().str();
  EXPECT_EQ(reopened.graph().at(r.instance).asset, "#group");
  EXPECT_EQ(evaluate_bytes(reopened.graph()), bytes);
  // Twice is refused, plain nodes too; nothing changes.
  EXPECT_THROW(make_unique_node(root, r.instance), DocumentError);
  EXPECT_THROW(make_unique_node(root, "fin"), DocumentError);
  EXPECT_EQ(root.history().undo_size(), steps + 1);

  ASSERT_TRUE(root.undo());
  EXPECT_TRUE(root.graph() == before);
  EXPECT_EQ(root.graph().at(r.instance).type->subgraph, r.asset);
  ASSERT_TRUE(root.redo());
  EXPECT_EQ(root.graph().at(r.instance).asset, "#group");
  // Deleting the last instance of the copy says that saving drops it; undo brings it back.
  {
    Selection selection;
    CanvasController canvas(root, selection);
    selection.select_only(r.instance);
    canvas.delete_selection();
    EXPECT_EQ(canvas.message(),
              "embedded asset #group has no instance left: saving the graph drops it (undo keeps it)");
    canvas.undo();
    EXPECT_EQ(root.graph().at(r.instance).asset, "#group");
  }
  // An embedded instance ungroups like any other.
  ungroup_node(root, r.instance);
  EXPECT_FALSE(root.graph().find(r.instance));
  EXPECT_EQ(evaluate_bytes(root.graph()), bytes);
}

// Entering an embedded asset edits the copy inside the document: no file is written, the document is unsaved,
// and only the instances of the copy change.
TEST(EditorSubgraphs, EditingAnEmbeddedAssetChangesTheDocumentNotTheFile) {
  fs::path dir;
  Document root = saved_diamond("edit-embedded", &dir);
  const GroupResult r = group_nodes(root, {"a", "b"});
  add_twin(root, r, true);
  make_unique_node(root, r.instance);
  root.save();
  const std::string asset_text = read_file(r.asset_file);
  const auto twin_before = evaluate_bytes(root.graph(), {"fin2"});

  SubgraphNavigator nav(root);
  Document& inner = nav.enter(r.instance);
  EXPECT_EQ(nav.breadcrumbs(), (std::vector<std::string>{"g.json", r.instance + " (#group)"}));
  EXPECT_FALSE(inner.has_path());
  ASSERT_TRUE(inner.graph().interface);
  inner.set_param("a", "weight", 0.9);
  EXPECT_EQ(nav.sync(), "");
  EXPECT_EQ(read_file(r.asset_file), asset_text);  // the file asset is untouched
  EXPECT_TRUE(root.dirty());                       // the copy is part of the document
  // The made-unique instance evaluates the edit, the twin (the file asset) does not.
  Graph inline_edit = diamond_graph();
  inline_edit.set_param("a", "weight", 0.9);
  EXPECT_EQ(evaluate_bytes(root.graph(), {"fin"}), evaluate_bytes(inline_edit, {"fin"}));
  EXPECT_EQ(evaluate_bytes(root.graph(), {"fin2"}), twin_before);
  // Undo inside puts the copy back as it was.
  ASSERT_TRUE(inner.undo());
  EXPECT_EQ(nav.sync(), "");
  EXPECT_EQ(evaluate_bytes(root.graph(), {"fin"}), evaluate_bytes(diamond_graph(), {"fin"}));
  ASSERT_TRUE(inner.redo());
  EXPECT_EQ(nav.sync(), "");
  // An instance of the copy inside itself is refused and not applied.
  const SubgraphAsset* applied = root.graph().at(r.instance).type->subgraph;
  inner.edit("self", [&](Graph& g) {
    Node& me = add_subgraph_instance(g, *applied, "#group", "me");
    (void)me;
  });
  const std::string error = nav.sync();
  EXPECT_NE(error.find("contains itself"), std::string::npos) << error;
  EXPECT_EQ(root.graph().at(r.instance).type->subgraph, applied);
  EXPECT_FALSE(nav.leave());
  inner.undo();
  EXPECT_TRUE(nav.leave());
  // Saved and opened again: the edited copy is in the file.
  root.save();
  const Document reopened = Document::open(root.path());
  EXPECT_TRUE(reopened.load_problems().empty());
  EXPECT_EQ(evaluate_bytes(reopened.graph(), {"fin"}), evaluate_bytes(inline_edit, {"fin"}));
  EXPECT_DOUBLE_EQ(std::get<double>(reopened.graph().at(r.instance).type->subgraph->graph.param("a", "weight")), 0.9);
}

// Inside an embedded asset, Make unique names the copy freely in the file that will hold it (the root's section
// already has "#group" and "#group2").
TEST(EditorSubgraphs, MakeUniqueInsideAnEmbeddedAssetPicksANameFreeInTheFile) {
  fs::path dir;
  Document root = saved_diamond("unique-nested", &dir);
  const auto before = evaluate_bytes(root.graph());
  const GroupResult inner = group_nodes(root, {"a"});
  const GroupResult outer = group_nodes(root, {inner.instance, "b"});
  root.edit("solo", [&](Graph& g) {
    Node& solo = add_subgraph_instance(g, *inner.asset, "group.orogen-subgraph.json", "solo");
    solo.inputs = {{"a", {"s1", "out"}}};
  });
  EXPECT_EQ(make_unique_node(root, "solo"), "group");
  EXPECT_EQ(make_unique_node(root, outer.instance), "group2");
  SubgraphNavigator nav(root);
  nav.enter(outer.instance);
  EXPECT_EQ(nav.make_unique(inner.instance), "group3");
  EXPECT_EQ(nav.current().graph().at(inner.instance).asset, "#group3");
  ASSERT_EQ(nav.sync(), "");
  ASSERT_TRUE(nav.leave());
  EXPECT_EQ(evaluate_bytes(root.graph()), before);
  root.save();
  const Document reopened = Document::open(root.path());
  ASSERT_TRUE(reopened.load_problems().empty()) << reopened.load_problems().diagnostics.front().str();
  EXPECT_EQ(evaluate_bytes(reopened.graph()), before);
  const std::string text = read_file(root.path());
  EXPECT_NE(text.find("\"group3\": {"), std::string::npos);
  EXPECT_NE(text.find("\"asset\": \"#group3\""), std::string::npos);
}

TEST(EditorSubgraphs, PaletteListsLibraryAssetsAndAddsInstances) {
  const auto types = palette_types_with_library();
  const NodeType* colors = nullptr;
  for (const NodeType* t : types)
    if (t->name == "terrain_colors") colors = t;
  ASSERT_TRUE(colors) << "the library's terrain_colors is not in the palette";
  EXPECT_TRUE(is_asset_entry(*colors));
  EXPECT_EQ(colors->category, "subgraph");
  const auto matches = search_palette("terrain colors", types);
  ASSERT_FALSE(matches.empty());
  EXPECT_EQ(matches.front().type, colors);

  Document doc(test::chain_graph());
  Selection selection;
  CanvasController canvas(doc, selection, ClipboardAccess::local(), types);
  canvas.view().set_viewport({0, 0}, {800, 600});
  canvas.open_palette({400, 300});
  canvas.palette().set_query("terrain colors");
  const std::string id = canvas.confirm_palette();
  ASSERT_EQ(id, "terrain_colors");
  const Node& node = doc.graph().at(id);
  ASSERT_TRUE(node.type->subgraph);
  EXPECT_EQ(node.type->name, "Subgraph");  // the asset's instance type, not the palette entry
  EXPECT_EQ(node.asset, "terrain_colors");
  const SubgraphInterface& in = node.type->subgraph->interface();
  ASSERT_EQ(node.type->inputs.size(), in.inputs.size());
  EXPECT_EQ(node.type->inputs.front().name, "height");
  ASSERT_EQ(node.type->params.size(), in.params.size());
  EXPECT_EQ(node.type->params.front().name, in.params.front().decl.name);
  // Linked and round-tripped like any instance.
  const NodeType* type = node.type;
  doc.connect({"out", "out"}, id, "height");
  const LoadResult loaded = parse_graph(serialize_graph(doc.graph()));
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  EXPECT_EQ(loaded.graph->at(id).type, type);
}

TEST(EditorSubgraphs, KeysGroupEnterLeaveAndUngroup) {
  Document doc = saved_diamond("keys");
  const Graph before = doc.graph();
  Selection selection;
  SubgraphNavigator nav(doc);
  CanvasController canvas(doc, selection);
  canvas.set_navigator(&nav);
  canvas.view().set_viewport({0, 0}, {1000, 700});
  selection.set({"a", "b"});
  canvas.handle(KeyDown{Key::G, {true, false, false}});  // Ctrl+G
  ASSERT_EQ(selection.size(), 1u);
  const std::string inst = selection.active();
  ASSERT_TRUE(doc.graph().at(inst).type->subgraph);

  canvas.handle(KeyDown{Key::Tab, {}});  // into the selected instance
  ASSERT_TRUE(nav.inside());
  EXPECT_EQ(&canvas.document(), &nav.current());
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Idle);  // not the palette
  EXPECT_EQ(canvas.layout().nodes().size(), 2u);

  canvas.handle(KeyDown{Key::Tab, {false, true, false}});  // Shift+Tab: out again
  EXPECT_FALSE(nav.inside());
  EXPECT_EQ(&canvas.document(), &doc);
  EXPECT_EQ(selection.active(), inst);  // the instance left is selected

  canvas.handle(KeyDown{Key::G, {true, true, false}});  // Ctrl+Shift+G
  EXPECT_EQ(selection.size(), 2u);
  EXPECT_TRUE(selection.contains("a") && selection.contains("b"));
  canvas.undo();
  canvas.undo();
  EXPECT_TRUE(doc.graph() == before);

  // Tab with a plain node selected still opens the palette.
  selection.select_only("a");
  canvas.handle(KeyDown{Key::Tab, {}});
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Palette);
}

}  // namespace
}  // namespace orogen::editor
