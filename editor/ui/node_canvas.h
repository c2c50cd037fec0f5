#pragma once
// The node canvas view: draws the graph (grid, links, nodes with their status, the link being dragged,
// the selection box, the palette) and turns this frame's ImGui input into InputEvents for the
// CanvasController, which does all the deciding.
#include <functional>
#include <map>
#include <optional>
#include <string>

#include <imgui.h>

#include "editor/model/canvas_controller.h"
#include "editor/model/evaluation_controller.h"
#include "editor/model/preview_image.h"
#include "editor/ui/gl_texture.h"

namespace orogen::editor {

class NodeCanvasView {
 public:
  // World units of the canvas font at zoom 1.
  static constexpr float kFontSize = 14.0f;

  NodeCanvasView(CanvasController& controller, const EvaluationController& evaluation);
  // Text is drawn with the bake closest to its size: `small` when zoomed out, `large` when zoomed in
  // (glyphs minified far below their bake size break up). Null: the current font.
  // What a heightfield output holds, for its thumbnail's colors (the app's: inside a subgraph it looks through
  // the instance's inputs). Default: resolve_output_kind on the canvas's graph.
  void set_output_kind(std::function<OutputKind(const std::string& node, const std::string& port)> kind) {
    output_kind_ = std::move(kind);
  }
  void set_fonts(ImFont* small, ImFont* large) {
    small_font_ = small;
    large_font_ = large;
  }

  // Draws the canvas into the remaining space of the current window and feeds it input.
  // `previewed` is the node shown in the preview (marked on its title bar).
  void draw(const std::string& previewed);
  // Another document: its problems banner shows again, thumbnails are dropped.
  void document_changed() {
    dismissed_problems_ = false;
    show_problem_list_ = true;
    thumbnails_.clear();
  }

  // A node double-clicked this frame (the app pins the preview to it).
  const std::optional<std::string>& double_clicked() const { return double_clicked_; }

 private:
  void feed_input(bool hovered);
  void draw_grid(ImDrawList* dl);
  void draw_links(ImDrawList* dl);
  void draw_nodes(ImDrawList* dl, const std::string& previewed);
  void draw_palette();
  void draw_tooltips();
  void draw_problems_banner(ImVec2 origin, ImVec2 size);
  void draw_thumbnail(ImDrawList* dl, const Node& node, const Rect& screen_box);

  struct Thumbnail {
    GlTexture texture;
    const void* data = nullptr;  // the result shown (held below, so the address stays its own)
    PortValue value;             // holds the data shown
  };
  std::map<std::string, Thumbnail> thumbnails_;

  ImFont* text_font(float size) const;

  CanvasController& controller_;
  std::function<OutputKind(const std::string&, const std::string&)> output_kind_;
  ImFont* small_font_ = nullptr;
  ImFont* large_font_ = nullptr;
  const EvaluationController& evaluation_;
  std::map<std::string, NodeRunState> states_;  // this frame's snapshot
  bool pressed_[3] = {false, false, false};
  ImVec2 last_mouse_{-1e9f, -1e9f};
  bool space_down_ = false;
  bool palette_focus_ = false;
  std::string palette_buffer_;
  glm::dvec2 palette_size_{320.0, 420.0};  // last drawn
  bool show_problem_list_ = true;
  bool dismissed_problems_ = false;  // the user dismissed the load problems of this document
  std::optional<std::string> double_clicked_;
  std::string hover_key_;
  double hover_since_ = 0.0;
};

}  // namespace orogen::editor
