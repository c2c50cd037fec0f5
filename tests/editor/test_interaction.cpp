// Interaction on the node canvas, driven headless through the same input events the UI produces.
#include <gtest/gtest.h>

#include "editor/model/canvas_controller.h"
#include "graph/graph_file.h"
#include "graph/registry.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

class Interaction : public ::testing::Test {
 protected:
  Document doc{test::chain_graph()};
  Selection sel;
  ClipboardAccess clipboard = ClipboardAccess::local();
  CanvasController canvas{doc, sel, clipboard};

  void SetUp() override {
    canvas.view().set_viewport({0, 0}, {1600, 900});
    canvas.view().set({-100, -100}, 1.0);
  }
  glm::dvec2 pin(const std::string& node, const std::string& port, bool output) {
    const auto* p = canvas.layout().find(node)->find_pin(port, output);
    EXPECT_NE(p, nullptr) << node << "." << port;
    return canvas.view().to_screen(p->position);
  }
  glm::dvec2 body(const std::string& node) {
    const auto& n = *canvas.layout().find(node);
    return canvas.view().to_screen(glm::dvec2(n.rect.center().x, n.title.center().y));
  }
  void drag(glm::dvec2 from, glm::dvec2 to, MouseButton b = MouseButton::Left, Modifiers mods = {}) {
    canvas.handle(MouseMove{from});
    canvas.handle(MouseDown{b, from, mods});
    for (int k = 1; k <= 8; ++k) canvas.handle(MouseMove{from + (to - from) * (k / 8.0)});
    canvas.handle(MouseUp{b, to, mods});
  }
  void click(glm::dvec2 at, Modifiers mods = {}) { drag(at, at, MouseButton::Left, mods); }
  void key(Key k, Modifiers mods = {}) { canvas.handle(KeyDown{k, mods}); }
  static Modifiers ctrl() { return {true, false, false}; }
  static Modifiers shift() { return {false, true, false}; }
};

TEST_F(Interaction, AddNodeFromPaletteByTypingItsName) {
  canvas.handle(MouseMove{{700, 500}});
  key(Key::Tab);
  ASSERT_EQ(canvas.mode(), CanvasController::Mode::Palette);
  for (char c : std::string("EdScat")) canvas.handle(TextInput{std::string(1, c)});
  ASSERT_NE(canvas.palette().choice(), nullptr);
  EXPECT_EQ(canvas.palette().choice()->name, "EdScatter");
  key(Key::Enter);
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Idle);
  const Node* added = doc.graph().find("edscatter");
  ASSERT_NE(added, nullptr);
  EXPECT_EQ(added->type->name, "EdScatter");
  EXPECT_EQ(doc.graph().editor.positions.at("edscatter"), canvas.view().to_world({700, 500}));
  EXPECT_EQ(sel.active(), "edscatter");
  EXPECT_EQ(doc.history().undo_size(), 1u);
  key(Key::Z, ctrl());
  EXPECT_FALSE(doc.graph().find("edscatter"));
}

TEST_F(Interaction, PaletteFindsRegisteredNodeTypesByName) {
  // Every registered type is found first by typing its exact name.
  for (const NodeType* type : NodeRegistry::instance().all()) {
    key(Key::Tab);
    ASSERT_EQ(canvas.mode(), CanvasController::Mode::Palette);
    canvas.handle(TextInput{type->name});
    ASSERT_NE(canvas.palette().choice(), nullptr) << type->name;
    EXPECT_EQ(canvas.palette().choice()->name, type->name);
    key(Key::Escape);
  }
  EXPECT_FALSE(doc.history().can_undo());
}

TEST_F(Interaction, RightClickOpensPaletteEscapeClosesIt) {
  canvas.handle(MouseDown{MouseButton::Right, {900, 700}, {}});
  canvas.handle(MouseUp{MouseButton::Right, {900, 700}, {}});
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Palette);
  key(Key::Escape);
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Idle);
  EXPECT_FALSE(doc.history().can_undo());
}

TEST_F(Interaction, ConnectCompatiblePins) {
  ASSERT_FALSE(doc.graph().at("out").inputs.count("b"));
  drag(pin("src", "out", true), pin("out", "b", false));
  EXPECT_EQ(canvas.message(), "");
  ASSERT_TRUE(doc.graph().at("out").inputs.count("b"));
  EXPECT_EQ(doc.graph().at("out").inputs.at("b"), (PortRef{"src", "out"}));
  // Dragging from the input end works too.
  doc.undo();
  drag(pin("out", "b", false), pin("src", "out", true));
  EXPECT_EQ(doc.graph().at("out").inputs.at("b"), (PortRef{"src", "out"}));
}

TEST_F(Interaction, IncompatiblePinsAreDimmedAndTheLinkRefused) {
  const Graph before = doc.graph();
  const glm::dvec2 from = pin("scatter", "points", true), to = pin("out", "b", false);
  canvas.handle(MouseMove{from});
  canvas.handle(MouseDown{MouseButton::Left, from, {}});
  canvas.handle(MouseMove{(from + to) * 0.5});
  ASSERT_EQ(canvas.mode(), CanvasController::Mode::DraggingLink);
  // Every Heightfield input is incompatible with a Points output: the canvas dims them.
  EXPECT_FALSE(canvas.link_drag()->compatible(doc.graph(), {"out", "b", false}));
  EXPECT_FALSE(canvas.link_drag()->compatible(doc.graph(), {"mid", "a", false}));
  canvas.handle(MouseMove{to});
  canvas.handle(MouseUp{MouseButton::Left, to, {}});
  EXPECT_NE(canvas.message().find("type mismatch"), std::string::npos) << canvas.message();
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_FALSE(doc.history().can_undo());
}

TEST_F(Interaction, ClickingAPinChangesNothing) {
  const Graph before = doc.graph();
  click(pin("src", "out", true));
  click(pin("out", "a", false));
  EXPECT_EQ(canvas.message(), "");
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_EQ(canvas.mode(), CanvasController::Mode::Idle);
}

TEST_F(Interaction, CycleIsRefused) {
  const Graph before = doc.graph();
  drag(pin("out", "out", true), pin("mid", "b", false));
  EXPECT_NE(canvas.message().find("cycle"), std::string::npos) << canvas.message();
  EXPECT_TRUE(doc.graph() == before);
}

TEST_F(Interaction, DragFromConnectedInputMovesOrDetachesTheLink) {
  drag(pin("out", "a", false), pin("out", "b", false));
  EXPECT_FALSE(doc.graph().at("out").inputs.count("a"));
  EXPECT_EQ(doc.graph().at("out").inputs.at("b"), (PortRef{"mid", "out"}));
  EXPECT_EQ(doc.history().undo_size(), 1u);
  drag(pin("out", "b", false), {1500, 850});  // empty canvas
  EXPECT_TRUE(doc.graph().at("out").inputs.empty());
  EXPECT_EQ(doc.history().undo_size(), 2u);
}

TEST_F(Interaction, LinkDroppedOnEmptyCanvasOffersMatchingNodes) {
  drag(pin("out", "out", true), {1400, 300});
  ASSERT_EQ(canvas.mode(), CanvasController::Mode::Palette);
  for (const auto& m : canvas.palette().results()) {
    bool takes_heightfield = false;
    for (const auto& in : m.type->inputs) takes_heightfield |= in.type == PortType::Heightfield;
    EXPECT_TRUE(takes_heightfield) << m.type->name;
  }
  canvas.handle(TextInput{"EdScatter"});
  key(Key::Enter);
  const Node* added = doc.graph().find("edscatter");
  ASSERT_NE(added, nullptr);
  EXPECT_EQ(added->inputs.at("height"), (PortRef{"out", "out"}));
  EXPECT_EQ(doc.history().undo_size(), 1u);
}

TEST_F(Interaction, ClickShiftClickAndBoxSelection) {
  click(body("src"));
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"src"}));
  click(body("mid"), shift());
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"src", "mid"}));
  EXPECT_EQ(sel.active(), "mid");
  click(body("src"), shift());
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"mid"}));
  click({1500, 850});  // empty canvas clears
  EXPECT_TRUE(sel.empty());
  // A box around src and mid (they sit at y 0; scatter at y 200).
  drag(canvas.view().to_screen({-20, -20}), canvas.view().to_screen({480, 60}));
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"src", "mid"}));
  drag(canvas.view().to_screen({250, 180}), canvas.view().to_screen({480, 260}), MouseButton::Left, shift());
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"src", "mid", "scatter"}));
  key(Key::A, ctrl());
  EXPECT_EQ(sel.size(), 4u);
}

TEST_F(Interaction, DraggingNodesMovesTheSelectionAsOneUndoStep) {
  click(body("src"));
  click(body("mid"), shift());
  const auto p_src = doc.graph().editor.positions.at("src");
  const auto p_mid = doc.graph().editor.positions.at("mid");
  canvas.view().set(canvas.view().scroll(), 2.0);
  drag(body("mid"), body("mid") + glm::dvec2(100, 40));
  EXPECT_EQ(doc.graph().editor.positions.at("src"), p_src + glm::dvec2(50, 20));
  EXPECT_EQ(doc.graph().editor.positions.at("mid"), p_mid + glm::dvec2(50, 20));
  EXPECT_EQ(doc.history().undo_size(), 1u);
  EXPECT_EQ(sel.size(), 2u);
  key(Key::Z, ctrl());
  EXPECT_EQ(doc.graph().editor.positions.at("src"), p_src);
  key(Key::Z, {true, true, false});  // Ctrl+Shift+Z
  EXPECT_EQ(doc.graph().editor.positions.at("src"), p_src + glm::dvec2(50, 20));
}

TEST_F(Interaction, ClickWithoutMovingChangesNothing) {
  click(body("src"));
  EXPECT_FALSE(doc.history().can_undo());
}

TEST_F(Interaction, DeleteAndDuplicate) {
  click(body("mid"));
  key(Key::D, ctrl());
  ASSERT_NE(doc.graph().find("mid2"), nullptr);
  EXPECT_EQ(sel.ids(), (std::set<std::string>{"mid2"}));
  EXPECT_EQ(doc.graph().editor.positions.at("mid2"), doc.graph().editor.positions.at("mid") + glm::dvec2(40));
  key(Key::Delete);
  EXPECT_FALSE(doc.graph().find("mid2"));
  click(body("mid"));
  key(Key::X);
  EXPECT_FALSE(doc.graph().find("mid"));
  EXPECT_FALSE(doc.graph().at("out").inputs.count("a"));
  EXPECT_TRUE(sel.empty());
  key(Key::Z, ctrl());
  EXPECT_EQ(doc.graph().at("out").inputs.at("a"), (PortRef{"mid", "out"}));
}

TEST_F(Interaction, DuplicateKeepsInternalLinks) {
  key(Key::A, ctrl());
  key(Key::D, ctrl());
  EXPECT_EQ(doc.graph().nodes().size(), 8u);
  EXPECT_EQ(doc.graph().at("out2").inputs.at("a"), (PortRef{"mid2", "out"}));
  EXPECT_EQ(doc.graph().at("mid2").inputs.at("a"), (PortRef{"src2", "out"}));
}

TEST_F(Interaction, CopyPasteBetweenTwoDocuments) {
  click(body("src"));
  click(body("mid"), shift());
  key(Key::C, ctrl());
  const std::string text = clipboard.get();
  EXPECT_TRUE(parse_graph(text).ok()) << "the clipboard holds a graph file";

  Document other(test::chain_graph());
  other.set_param("src", "height", 77.0);
  Selection other_sel;
  CanvasController other_canvas(other, other_sel, clipboard);
  other_canvas.view().set_viewport({0, 0}, {1600, 900});
  other_canvas.handle(MouseMove{{1000, 600}});
  other_canvas.handle(KeyDown{Key::V, ctrl()});
  // Both ids were taken: renamed, and the link between them follows.
  ASSERT_NE(other.graph().find("src2"), nullptr);
  ASSERT_NE(other.graph().find("mid2"), nullptr);
  EXPECT_EQ(other.graph().at("mid2").inputs.at("a"), (PortRef{"src2", "out"}));
  EXPECT_EQ(other.graph().at("src2").params, doc.graph().at("src").params);
  EXPECT_EQ(std::get<double>(other.graph().param("src", "height")), 77.0) << "the original is untouched";
  EXPECT_EQ(other_sel.ids(), (std::set<std::string>{"src2", "mid2"}));
  EXPECT_EQ(other.graph().editor.positions.at("src2"), other_canvas.view().to_world({1000, 600}));
  EXPECT_EQ(other.history().undo_size(), 2u);  // the set_param and the paste

  // Into an empty document the ids stay.
  Document empty;
  Selection empty_sel;
  CanvasController empty_canvas(empty, empty_sel, clipboard);
  empty_canvas.paste();
  EXPECT_NE(empty.graph().find("src"), nullptr);
  EXPECT_EQ(empty.graph().at("mid").inputs.at("a"), (PortRef{"src", "out"}));
}

TEST_F(Interaction, PastingGarbageIsRefusedWithAMessage) {
  clipboard.set("this is not json");
  const Graph before = doc.graph();
  key(Key::V, ctrl());
  EXPECT_FALSE(canvas.message().empty());
  EXPECT_TRUE(doc.graph() == before);
}

TEST_F(Interaction, WheelZoomKeepsThePointUnderTheCursor) {
  const glm::dvec2 cursor{640, 410};
  const glm::dvec2 world = canvas.view().to_world(cursor);
  canvas.handle(Wheel{cursor, 3.0});
  EXPECT_GT(canvas.view().zoom(), 1.4);
  EXPECT_NEAR(canvas.view().to_world(cursor).x, world.x, 1e-9);
  EXPECT_NEAR(canvas.view().to_world(cursor).y, world.y, 1e-9);
  canvas.handle(Wheel{cursor, -5.0});
  EXPECT_LT(canvas.view().zoom(), 1.0);
  EXPECT_NEAR(canvas.view().to_world(cursor).x, world.x, 1e-9);
}

TEST_F(Interaction, MiddleDragAndSpaceDragPan) {
  const glm::dvec2 world{0, 0};
  const glm::dvec2 s0 = canvas.view().to_screen(world);
  drag({800, 800}, {850, 780}, MouseButton::Middle);
  EXPECT_EQ(canvas.view().to_screen(world), s0 + glm::dvec2(50, -20));
  canvas.handle(KeyDown{Key::Space, {}});
  drag(body("src"), body("src") + glm::dvec2(-10, 30));  // over a node: pans, does not move it
  canvas.handle(KeyUp{Key::Space});
  EXPECT_EQ(canvas.view().to_screen(world), s0 + glm::dvec2(40, 10));
  EXPECT_FALSE(doc.history().can_undo());
}

TEST_F(Interaction, FrameAllAndSelected) {
  canvas.view().set({5000, 5000}, 0.2);
  key(Key::Home);
  for (const auto& n : canvas.layout().nodes()) EXPECT_TRUE(canvas.view().visible().contains(n.rect.center()));
  click(body("scatter"));
  key(Key::F);
  EXPECT_NEAR(canvas.view().to_screen(canvas.layout().find("scatter")->rect.center()).x, 800, 1e-6);
}

}  // namespace
}  // namespace orogen::editor
