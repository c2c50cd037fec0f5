// Document and undo history: every edit is one step, drags merge, undo restores exact states, the dirty
// flag and title follow saves, and files round-trip.
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "editor/model/document.h"
#include "editor/model/evaluation_controller.h"
#include "graph/graph_file.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

TEST(Document, EditIsOneUndoStepAndUndoRestoresExactly) {
  Document doc(test::chain_graph());
  const auto before = serialize_graph(doc.graph());
  doc.set_param("src", "height", 42.0);
  EXPECT_EQ(std::get<double>(doc.graph().param("src", "height")), 42.0);
  EXPECT_TRUE(doc.history().can_undo());
  EXPECT_TRUE(doc.undo());
  EXPECT_EQ(serialize_graph(doc.graph()), before);
  EXPECT_TRUE(doc.redo());
  EXPECT_EQ(std::get<double>(doc.graph().param("src", "height")), 42.0);
}

TEST(Document, FailingEditLeavesDocumentUnchanged) {
  Document doc(test::chain_graph());
  const Graph before = doc.graph();
  const auto revision = doc.revision();
  EXPECT_THROW(doc.set_param("src", "height", 1e9), GraphError);             // out of range
  EXPECT_THROW(doc.connect({"scatter", "points"}, "out", "b"), GraphError);  // Points into a Heightfield input
  EXPECT_THROW(doc.connect({"out", "out"}, "mid", "b"), GraphError);         // a cycle
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_EQ(doc.revision(), revision);
  EXPECT_FALSE(doc.history().can_undo());
  EXPECT_FALSE(doc.dirty());
}

TEST(Document, NoOpEditRecordsNothing) {
  Document doc(test::chain_graph());
  doc.set_param("src", "height", 10.0);  // already the default, but now explicitly set: a change
  const auto steps = doc.history().undo_size();
  doc.set_param("src", "height", 10.0);  // same again: nothing
  EXPECT_EQ(doc.history().undo_size(), steps);
}

TEST(Document, ParameterDragMergesIntoOneStep) {
  Document doc(test::chain_graph());
  const auto before = serialize_graph(doc.graph());
  for (int k = 1; k <= 30; ++k) doc.set_param("src", "height", 10.0 + k, /*gesture=*/true);
  doc.end_gesture();
  EXPECT_EQ(doc.history().undo_size(), 1u);
  EXPECT_EQ(std::get<double>(doc.graph().param("src", "height")), 40.0);
  // A second drag of the same parameter is a second step.
  for (int k = 1; k <= 5; ++k) doc.set_param("src", "height", 40.0 - k, true);
  doc.end_gesture();
  EXPECT_EQ(doc.history().undo_size(), 2u);
  doc.undo();
  EXPECT_EQ(std::get<double>(doc.graph().param("src", "height")), 40.0);
  doc.undo();
  EXPECT_EQ(serialize_graph(doc.graph()), before);
}

TEST(Document, DragsOfDifferentParametersDoNotMerge) {
  Document doc(test::chain_graph());
  doc.set_param("src", "height", 20.0, true);
  doc.set_param("src", "tilt", 0.5, true);
  doc.end_gesture();
  EXPECT_EQ(doc.history().undo_size(), 2u);
}

TEST(Document, DirtyFlagAndTitleFollowSaveAndUndo) {
  const auto dir = test::scratch_dir("dirty");
  Document doc(test::chain_graph());
  doc.save_as(dir / "g.json");
  EXPECT_FALSE(doc.dirty());
  EXPECT_EQ(doc.window_title(), "g.json - Orogen");
  doc.set_param("mid", "weight", 0.25);
  EXPECT_TRUE(doc.dirty());
  EXPECT_EQ(doc.window_title(), "g.json* - Orogen");
  doc.undo();
  EXPECT_FALSE(doc.dirty()) << "undoing back to the saved state is clean";
  doc.redo();
  EXPECT_TRUE(doc.dirty());
  doc.save();
  EXPECT_FALSE(doc.dirty());
  doc.undo();
  EXPECT_TRUE(doc.dirty()) << "the saved state is the edited one now";
}

TEST(Document, LayoutChangesDoNotBumpContentRevision) {
  Document doc(test::chain_graph());
  const auto content = doc.content_revision();
  doc.move_nodes({"src", "mid"}, {10.0, 5.0});
  EXPECT_EQ(doc.content_revision(), content);
  EXPECT_EQ(doc.graph().editor.positions.at("src"), glm::dvec2(10.0, 5.0));
  doc.set_param("mid", "weight", 0.1);
  EXPECT_GT(doc.content_revision(), content);
}

TEST(Document, SaveReopenCompare) {
  const auto dir = test::scratch_dir("reopen");
  Document doc(test::chain_graph());
  doc.set_param("src", "seed", std::uint64_t{99});
  doc.set_param("mid", "mode", std::string("max"));
  doc.add_node("EdBlend", {900.0, 40.0});  // its required input stays unconnected: work in progress
  doc.save_as(dir / "saved.json");
  const Document reopened = Document::open(dir / "saved.json");
  EXPECT_TRUE(reopened.graph() == doc.graph());
  EXPECT_EQ(serialize_graph(reopened.graph()), serialize_graph(doc.graph()));
  EXPECT_FALSE(reopened.dirty());
  EXPECT_EQ(reopened.path(), dir / "saved.json");
  // Relative input paths resolve beside the file, before and after reopening it.
  EXPECT_EQ(doc.graph().directory, dir.lexically_normal());
  EXPECT_EQ(reopened.graph().directory, dir.lexically_normal());
}

TEST(Document, OpenReportsWhatCannotBeReadAtAll) {
  const auto dir = test::scratch_dir("bad");
  { std::ofstream(dir / "bad.json") << R"({"format": "orogen-graph", "version": 99, "nodes": []})"; }
  try {
    Document::open(dir / "bad.json");
    FAIL() << "expected an error";
  } catch (const DocumentError& e) {
    EXPECT_NE(std::string(e.what()).find("version"), std::string::npos) << e.what();
  }
}

TEST(Document, ABrokenFileOpensWithItsProblemsOnTheNodes) {
  const auto dir = test::scratch_dir("broken");
  {
    std::ofstream(dir / "broken.json") << R"({"format": "orogen-graph", "version": 1, "nodes": [
      {"id": "src", "type": "EdSource", "params": {"height": 1e9}},
      {"id": "a", "type": "EdSorce"},
      {"id": "mid", "type": "EdBlend", "inputs": {"a": "src.out", "b": "a.out"}},
      {"id": "pts", "type": "EdScatter", "inputs": {"height": "src.nope"}}]})";
  }
  const Document doc = Document::open(dir / "broken.json");
  EXPECT_EQ(doc.graph().nodes().size(), 4u);
  EXPECT_TRUE(doc.dirty()) << "what is shown differs from the file";
  const auto& p = doc.load_problems();
  EXPECT_FALSE(p.empty());
  ASSERT_EQ(p.for_node("a").size(), 1u);
  EXPECT_NE(p.for_node("a")[0].find("EdSource"), std::string::npos) << "the typo's suggestion: " << p.for_node("a")[0];
  EXPECT_EQ(p.for_node("src").size(), 1u);  // the out-of-range height
  ASSERT_EQ(p.for_node("pts").size(), 1u);  // the link to a missing output, left out
  EXPECT_FALSE(doc.graph().at("pts").inputs.count("height"));
  EXPECT_TRUE(p.for_node("mid").empty());  // its links are fine (a is a placeholder with an output 'out')
  EXPECT_EQ(doc.graph().at("mid").inputs.at("b"), (PortRef{"a", "out"}));
  // Evaluating reports the placeholder as failed with the reason, and the rest still evaluates.
  EvaluationController ec;
  ec.request_preview(doc.graph(), {"mid", "src"}, 1);
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("a").phase, NodeRunState::Phase::Failed);
  EXPECT_NE(ec.node_state("a").message.find("unknown node type"), std::string::npos) << ec.node_state("a").message;
  EXPECT_EQ(ec.node_state("src").phase, NodeRunState::Phase::Computed);
}

// Random edits, undos and redos, checked against a plain list of the expected serialized states.
TEST(Document, LongRandomUndoRedoSequencesRestoreExactGraphFiles) {
  std::mt19937 rng(1234);
  Document doc(test::chain_graph());
  std::vector<std::string> states{serialize_graph(doc.graph())};
  std::size_t pos = 0;
  auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
  auto random_node = [&]() -> std::string {
    const auto& nodes = doc.graph().nodes();
    return nodes.empty() ? std::string() : nodes[static_cast<std::size_t>(pick(static_cast<int>(nodes.size())))].id;
  };
  int edits = 0, undos = 0, redos = 0;
  for (int step = 0; step < 1500; ++step) {
    // Bursts of undo and redo between edits: 0-1 undo, 2 redo, 3.. edits (redo is likelier after undos).
    int action = pick(10);
    if (doc.history().can_redo() && pick(3) == 0) action = 2;
    if (action < 2) {
      if (doc.undo()) {
        --pos;
        ++undos;
      } else {
        EXPECT_EQ(pos, 0u);
      }
    } else if (action < 3) {
      if (doc.redo()) {
        ++pos;
        ++redos;
      } else {
        EXPECT_EQ(pos + 1, states.size());
      }
    } else {
      const auto rev = doc.revision();
      try {
        const std::string n = random_node();
        switch (action) {
          case 3:
            doc.add_node(pick(2) ? "EdBlend" : "EdSource", {pick(1000) * 1.0, pick(1000) * 1.0});
            break;
          case 4:
            if (!n.empty() && doc.graph().nodes().size() > 2) doc.remove_nodes({n});
            break;
          case 5: {
            const std::string m = random_node();
            doc.connect({n, "out"}, m, pick(2) ? "a" : "b");
            break;
          }
          case 6:
            if (doc.graph().at(n).type->find_param("weight"))
              doc.set_param(n, "weight", pick(101) / 100.0);
            else
              doc.set_param(n, "height", pick(200) * 1.0);
            break;
          case 7:
            doc.move_nodes({n}, {pick(50) - 25.0, pick(50) - 25.0});
            break;
          case 8: {
            // A drag: many merged changes, one step.
            const bool blend = doc.graph().at(n).type->find_param("weight") != nullptr;
            for (int k = 0; k < 5; ++k) doc.set_param(n, blend ? "weight" : "tilt", (pick(100) / 100.0), true);
            doc.end_gesture();
            break;
          }
          default:
            if (!n.empty()) doc.rename_node(n, doc.graph().unique_id("renamed"));
            break;
        }
      } catch (const GraphError&) {
        // refused edits (cycles, mismatches) change nothing
      }
      if (doc.revision() != rev) {
        states.resize(pos + 1);
        states.push_back(serialize_graph(doc.graph()));
        ++pos;
        ++edits;
      }
    }
    ASSERT_EQ(serialize_graph(doc.graph()), states[pos]) << "step " << step;
  }
  EXPECT_GT(edits, 300);
  EXPECT_GT(undos, 100);
  EXPECT_GT(redos, 50);
  // And all the way back to the start.
  while (doc.undo()) --pos;
  EXPECT_EQ(pos, 0u);
  EXPECT_EQ(serialize_graph(doc.graph()), states[0]);
}

}  // namespace
}  // namespace orogen::editor
