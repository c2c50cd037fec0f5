#pragma once
// What the mouse and keyboard do on the node canvas, without any drawing: selection (click, Shift-click,
// box), moving nodes, panning and zooming, link dragging, the palette, delete, duplicate, copy and paste,
// framing, undo and redo. The UI feeds it InputEvents and draws its state; tests do the same headless.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "editor/model/canvas_view.h"
#include "editor/model/document.h"
#include "editor/model/input_events.h"
#include "editor/model/link_drag.h"
#include "editor/model/node_layout.h"
#include "editor/model/palette.h"
#include "editor/model/selection.h"
#include "editor/model/subgraph_navigation.h"

namespace orogen::editor {

// Access to the system clipboard (ImGui's in the app, a string in tests).
struct ClipboardAccess {
  std::function<std::string()> get;
  std::function<void(const std::string&)> set;
  static ClipboardAccess local();  // a private in-memory clipboard
};

class CanvasController {
 public:
  enum class Mode { Idle, Panning, MovingNodes, BoxSelecting, DraggingLink, Palette };

  CanvasController(Document& document, Selection& selection, ClipboardAccess clipboard = ClipboardAccess::local(),
                   std::vector<const NodeType*> palette_types = {});

  // Which document the canvas edits (File > Open replaces it). Resets the interaction state.
  void set_document(Document& document);
  // Entering subgraphs: the navigator whose current level the canvas edits (the app's; none in tests that do
  // not enter). The canvas follows it on enter and leave.
  void set_navigator(SubgraphNavigator* navigator) { navigator_ = navigator; }
  SubgraphNavigator* navigator() { return navigator_; }
  Document& document() { return *document_; }

  void handle(const InputEvent& event);

  CanvasView& view() { return view_; }
  const CanvasView& view() const { return view_; }
  // The node geometry of the current graph (rebuilt after every change).
  const CanvasLayout& layout();
  // How the canvas font measures text (the UI's real font; monospace estimate by default).
  void set_text_measure(TextMeasure measure);
  // Whether nodes make room for a thumbnail of their output (View > Node Thumbnails).
  void set_thumbnails(bool on) {
    if (on != thumbnails_) layout_revision_ = ~std::uint64_t(0);
    thumbnails_ = on;
  }
  bool thumbnails() const { return thumbnails_; }
  Mode mode() const { return mode_; }
  glm::dvec2 mouse() const { return mouse_; }  // screen
  glm::dvec2 mouse_world() const { return view_.to_world(mouse_); }
  bool space_held() const { return space_held_; }

  // Hover state, for highlighting and tooltips.
  const std::optional<PinLayout>& hovered_pin() const { return hovered_pin_; }
  const std::optional<std::string>& hovered_node() const { return hovered_node_; }
  bool is_selected(const std::string& id) const { return selection_.contains(id); }
  const std::string& active_node() const { return selection_.active(); }
  Selection& selection() { return selection_; }
  // The link being dragged, and the screen box being drawn.
  const std::optional<LinkDrag>& link_drag() const { return link_drag_; }
  std::optional<Rect> selection_box() const;  // screen

  // The palette: open at a screen point (Tab, right-click, or a link dropped on empty canvas).
  void open_palette(glm::dvec2 screen);
  void close_palette();
  PaletteState& palette() { return palette_; }
  glm::dvec2 palette_position() const { return palette_screen_; }  // screen
  // The link dropped on empty canvas that opened the palette (drawn to it until a node is chosen).
  const std::optional<LinkDrag>& palette_link() const { return palette_link_; }
  // Adds the highlighted (or given) type where the palette was opened, connecting it to the link that
  // opened the palette if any. Returns the new node's id, or "" if nothing was chosen.
  std::string confirm_palette(const NodeType* type = nullptr);

  // Commands, also bound to menus.
  void delete_selection();
  void duplicate_selection();
  void copy_selection();
  void paste();
  void select_all();
  void frame(bool selected_only);  // F: selection (or everything); Home: everything
  void frame_opening();            // a graph just opened: everything, or its start at a readable zoom
  void undo();
  void redo();
  // Subgraphs (editor/model/grouping.h): Ctrl+G groups the selection into an asset written beside the
  // document (or to `asset_file`) and selects the new instance; Ctrl+Shift+G ungroups the selected
  // instances. Refusals go to message().
  std::string group_selection(const std::filesystem::path& asset_file = {});
  void ungroup_selection();
  // Tab (one instance selected) or double-click: enter the instance (the active node by default);
  // Shift+Tab or a breadcrumb: leave, back to the view the level above had. Need a navigator.
  bool enter_subgraph(const std::string& id = {});
  bool leave_subgraph();
  void leave_subgraph_to(std::size_t depth);

  // The last refused action (wrong link, failed paste), for the status bar; cleared by the next action.
  const std::string& message() const { return message_; }
  void clear_message() { message_.clear(); }

 private:
  void on_mouse_move(const MouseMove& e);
  void on_mouse_down(const MouseDown& e);
  void on_mouse_up(const MouseUp& e);
  void on_key_down(const KeyDown& e);
  void on_palette_key(const KeyDown& e);
  void update_hover();
  std::optional<PinId> drop_target(glm::dvec2 screen) const;
  double pin_radius() const;  // world units: a comfortable grab size in pixels at any zoom
  void after_edit();

  Document* document_;
  Selection& selection_;
  ClipboardAccess clipboard_;
  CanvasView view_;
  CanvasLayout layout_;
  TextMeasure measure_ = monospace_width;
  std::uint64_t layout_revision_ = ~std::uint64_t(0);
  bool thumbnails_ = false;

  Mode mode_ = Mode::Idle;
  glm::dvec2 mouse_{0.0}, press_{0.0};
  bool space_held_ = false;
  bool moved_ = false;         // a press turned into a drag
  bool move_started_ = false;  // nodes have been moved in this drag
  std::string pressed_node_;
  bool box_additive_ = false;
  std::vector<std::string> box_base_;  // selection before an additive box
  std::optional<LinkDrag> link_drag_;
  std::optional<PinLayout> hovered_pin_;
  std::optional<std::string> hovered_node_;

  PaletteState palette_;
  glm::dvec2 palette_screen_{0.0};
  std::optional<LinkDrag> palette_link_;  // the link dropped on empty canvas that opened the palette
  std::vector<const NodeType*> palette_types_;

  std::string message_;

  SubgraphNavigator* navigator_ = nullptr;
  struct SavedLevel {
    CanvasView view;
    std::string instance;
  };
  std::vector<SavedLevel> outer_views_;  // the views of the levels above the current one
};

}  // namespace orogen::editor
