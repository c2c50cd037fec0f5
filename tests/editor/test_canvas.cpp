// Canvas math: zoom around the cursor, panning, framing, node geometry and hit testing.
#include <gtest/gtest.h>

#include "editor/model/canvas_controller.h"
#include "editor/model/canvas_view.h"
#include "editor/model/node_layout.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

void expect_near(glm::dvec2 a, glm::dvec2 b, double tol = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
}

TEST(CanvasView, WorldScreenRoundTrip) {
  CanvasView v;
  v.set_viewport({100, 50}, {800, 600});
  v.set({-30, 20}, 1.7);
  for (glm::dvec2 p : {glm::dvec2(0, 0), glm::dvec2(123.5, -88), glm::dvec2(1e4, 3)})
    expect_near(v.to_world(v.to_screen(p)), p, 1e-9);
  expect_near(v.to_screen(v.scroll()), v.origin());
}

TEST(CanvasView, ZoomKeepsThePointUnderTheCursorFixed) {
  CanvasView v;
  v.set_viewport({100, 50}, {800, 600});
  v.set({-30, 20}, 1.0);
  const glm::dvec2 cursor{437.0, 291.0};
  const glm::dvec2 world = v.to_world(cursor);
  for (double f : {1.15, 1.15, 2.0, 0.5, 0.87, 10.0, 0.01}) {
    v.zoom_at(cursor, f);
    expect_near(v.to_world(cursor), world, 1e-9);
    EXPECT_GE(v.zoom(), CanvasView::kMinZoom);
    EXPECT_LE(v.zoom(), CanvasView::kMaxZoom);
  }
  // Zoom really changed scale: a point 100 world units right of the anchor moves accordingly.
  v.set(v.scroll(), 1.0);
  v.zoom_at(cursor, 2.0);
  expect_near(v.to_screen(v.to_world(cursor) + glm::dvec2(100, 0)), cursor + glm::dvec2(200, 0), 1e-9);
}

TEST(CanvasView, PanFollowsTheMouse) {
  CanvasView v;
  v.set({0, 0}, 2.0);
  const glm::dvec2 world{50, 60};
  const glm::dvec2 before = v.to_screen(world);
  v.pan({30, -10});
  expect_near(v.to_screen(world), before + glm::dvec2(30, -10));
}

TEST(CanvasView, FrameFitsTheRectangle) {
  CanvasView v;
  v.set_viewport({0, 0}, {1000, 500});
  const Rect box{{200, 300}, {1200, 700}};
  v.frame(box, 40);
  EXPECT_TRUE(v.visible().contains(box.min));
  EXPECT_TRUE(v.visible().contains(box.max));
  expect_near(v.to_screen(box.center()), {500, 250}, 1e-9);
  EXPECT_NEAR(v.zoom(), 920.0 / 1000.0, 1e-12);  // width-limited: (1000 - 80) / 1000 < (500 - 80) / 400
}

TEST(CanvasView, TheOpeningViewIsReadableAndStartsAtTheTopLeft) {
  CanvasView v;
  v.set_viewport({10, 20}, {800, 600});
  const Rect wide{{-100, 50}, {3900, 550}};  // fits only at 0.18: titles would be 2.5 px
  v.frame_readable(wide, CanvasView::kReadableZoom, 40);
  EXPECT_DOUBLE_EQ(v.zoom(), CanvasView::kReadableZoom);
  EXPECT_NEAR(v.to_screen(wide.min).x, 10 + 40, 1e-9) << "x overflows: its start at the margin";
  EXPECT_NEAR(v.to_screen(wide.center()).y, 20 + 300, 1e-9) << "y fits (500 x 0.75 + 80 < 600): centered";

  const Rect small{{0, 0}, {300, 200}};  // fits at more than the readable zoom: as Home frames it
  CanvasView home = v;
  home.frame(small, 40);
  v.frame_readable(small, CanvasView::kReadableZoom, 40);
  EXPECT_DOUBLE_EQ(v.zoom(), home.zoom());
  expect_near(v.scroll(), home.scroll());
}

TEST(CanvasView, SeamscapeOpensWithReadableTitles) {
  // The example of the report: 43 nodes in a canvas of 1020 x 820 pixels (a 1600 x 900 window).
  Document doc = Document::open(std::filesystem::path(OROGEN_SOURCE_DIR) / "graphs/seamscape.json");
  Selection sel;
  CanvasController canvas(doc, sel);
  canvas.view().set_viewport({0, 22}, {1020, 820});
  canvas.frame(false);
  EXPECT_LT(canvas.view().zoom(), CanvasView::kReadableZoom) << "Home fits it all, too small to read";
  canvas.frame_opening();
  const CanvasView& v = canvas.view();
  EXPECT_GE(v.zoom(), CanvasView::kReadableZoom);
  // The first node of the flow (the top-left one) has its title bar on screen.
  const auto& nodes = canvas.layout().nodes();
  ASSERT_FALSE(nodes.empty());
  const auto first = std::min_element(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) {
    return a.rect.min.x + a.rect.min.y < b.rect.min.x + b.rect.min.y;
  });
  const Rect title = v.to_screen(first->title);
  EXPECT_TRUE(v.viewport().contains(title.min) && v.viewport().contains(title.max)) << first->id;
}

TEST(NodeLayout, PinsSitOnTheEdgesInDeclarationOrder) {
  const Graph g = test::chain_graph();
  const NodeLayout l = layout_node(g.at("mid"), {100, 200});
  EXPECT_EQ(l.rect.min, glm::dvec2(100, 200));
  ASSERT_EQ(l.inputs.size(), 2u);
  ASSERT_EQ(l.outputs.size(), 1u);
  EXPECT_EQ(l.inputs[0].pin.port, "a");
  EXPECT_EQ(l.inputs[1].pin.port, "b");
  EXPECT_LT(l.inputs[0].position.y, l.inputs[1].position.y);
  EXPECT_EQ(l.inputs[0].position.x, l.rect.min.x);
  EXPECT_EQ(l.outputs[0].position.x, l.rect.max.x);
  EXPECT_GT(l.inputs[0].position.y, l.title.max.y);
  EXPECT_LT(l.inputs[1].position.y, l.status.min.y);
}

TEST(NodeLayout, ThumbnailsBetweenPinsAndStatusForFieldImagePointsAndCurveOutputs) {
  const Graph g = test::chain_graph();
  const NodeLayout plain = layout_node(g.at("mid"), {100, 200});
  const NodeLayout with = layout_node(g.at("mid"), {100, 200}, monospace_width, true);
  EXPECT_FALSE(plain.thumbnail);
  ASSERT_TRUE(with.thumbnail);
  EXPECT_NEAR(with.rect.size().y - plain.rect.size().y, NodeMetrics::kThumbnailHeight + 6.0, 1e-9);
  EXPECT_GT(with.thumbnail->min.y, with.inputs.back().position.y);
  EXPECT_LE(with.thumbnail->max.y, with.status.min.y);
  EXPECT_GE(with.thumbnail->min.x, with.rect.min.x);
  EXPECT_LE(with.thumbnail->max.x, with.rect.max.x);
  EXPECT_EQ(with.inputs[1].position, plain.inputs[1].position) << "pins stay where they were";
  EXPECT_TRUE(layout_node(g.at("scatter"), {0, 0}, monospace_width, true).thumbnail) << "points: a drawing of them";
}

TEST(NodeLayout, RoomForThumbnailsWithoutOverlaps) {
  Graph g = test::chain_graph();
  // Stacked as tightly as nodes without thumbnails allow.
  g.editor.positions = {{"src", {0, 0}}, {"mid", {20, 90}}, {"out", {0, 180}}, {"scatter", {600, 95}}};
  const Graph before = g;
  EXPECT_EQ(make_room_for_thumbnails(g), 2u);  // mid and out move; scatter is in another column
  std::vector<Rect> rects;
  for (const auto& n : g.nodes())
    rects.push_back(layout_node(n, g.editor.positions.at(n.id), monospace_width, true).rect);
  for (std::size_t a = 0; a < rects.size(); ++a)
    for (std::size_t b = a + 1; b < rects.size(); ++b) EXPECT_FALSE(rects[a].overlaps(rects[b])) << a << " " << b;
  for (const auto& [id, p] : g.editor.positions) {
    EXPECT_EQ(p.x, before.editor.positions.at(id).x) << id;  // only downwards
    EXPECT_GE(p.y, before.editor.positions.at(id).y) << id;
  }
  EXPECT_EQ(g.editor.positions.at("src"), glm::dvec2(0, 0));
  EXPECT_EQ(g.editor.positions.at("scatter"), glm::dvec2(600, 95));
  EXPECT_EQ(make_room_for_thumbnails(g), 0u) << "a second pass has nothing to do";
}

TEST(CanvasLayout, HitTestingNodesPinsAndBoxes) {
  const Graph g = test::chain_graph();
  const CanvasLayout layout(g);
  const auto* mid = layout.find("mid");
  ASSERT_NE(mid, nullptr);
  EXPECT_EQ(layout.node_at(mid->rect.center()), "mid");
  EXPECT_FALSE(layout.node_at({-500, -500}));
  const auto pin = layout.pin_at(mid->inputs[1].position + glm::dvec2(2, 1), 8);
  ASSERT_TRUE(pin);
  EXPECT_EQ(pin->pin, (PinId{"mid", "b", false}));
  EXPECT_FALSE(layout.pin_at(mid->rect.center(), 8));
  const auto boxed = layout.nodes_in({{-10, -10}, {320, 50}});
  EXPECT_EQ(boxed, (std::vector<std::string>{"src", "mid"}));
  const auto all = layout.bounds();
  ASSERT_TRUE(all);
  for (const auto& n : layout.nodes()) EXPECT_TRUE(all->contains(n.rect.min) && all->contains(n.rect.max));
}

TEST(CanvasLayout, UnplacedNodesGetColumnsByDepth) {
  Graph g = test::chain_graph();
  g.editor.positions.clear();
  place_unpositioned_nodes(g);
  const auto& p = g.editor.positions;
  ASSERT_EQ(p.size(), 4u);
  EXPECT_LT(p.at("src").x, p.at("mid").x);
  EXPECT_LT(p.at("mid").x, p.at("out").x);
  EXPECT_EQ(p.at("mid").x, p.at("scatter").x);
  const CanvasLayout layout(g);
  for (const auto& a : layout.nodes())
    for (const auto& b : layout.nodes())
      if (a.id != b.id) {
        EXPECT_FALSE(a.rect.overlaps(b.rect)) << a.id << " overlaps " << b.id;
      }
}

}  // namespace
}  // namespace orogen::editor
