#include "editor/model/canvas_controller.h"

#include "editor/model/asset_palette.h"
#include "editor/model/grouping.h"
#include "graph/subgraph.h"

#include <cmath>
#include <map>
#include <memory>

#include <glm/geometric.hpp>

#include "editor/model/clipboard.h"
#include "graph/registry.h"

namespace orogen::editor {

namespace {
constexpr double kDragThreshold = 3.0;  // pixels before a press becomes a drag
constexpr double kPinGrabPixels = 9.0;
constexpr double kZoomStep = 1.15;  // per wheel notch
constexpr double kDuplicateOffset = 40.0;
}  // namespace

ClipboardAccess ClipboardAccess::local() {
  auto text = std::make_shared<std::string>();
  return {[text] { return *text; }, [text](const std::string& s) { *text = s; }};
}

CanvasController::CanvasController(Document& document, Selection& selection, ClipboardAccess clipboard,
                                   std::vector<const NodeType*> palette_types)
    : document_(&document),
      selection_(selection),
      clipboard_(std::move(clipboard)),
      palette_types_(palette_types.empty() ? NodeRegistry::instance().all() : std::move(palette_types)) {
  palette_.set_types(palette_types_);
}

void CanvasController::set_document(Document& document) {
  document_ = &document;
  layout_revision_ = ~std::uint64_t(0);
  mode_ = Mode::Idle;
  link_drag_.reset();
  palette_link_.reset();
  hovered_pin_.reset();
  hovered_node_.reset();
  selection_.clear();
  // Views saved for levels that are gone (another root document, levels left).
  if (outer_views_.size() > (navigator_ ? navigator_->depth() : 0))
    outer_views_.resize(navigator_ ? navigator_->depth() : 0);
}

const CanvasLayout& CanvasController::layout() {
  if (layout_revision_ != document_->revision()) {
    layout_.build(document_->graph(), measure_, thumbnails_);
    layout_revision_ = document_->revision();
  }
  return layout_;
}

void CanvasController::set_text_measure(TextMeasure measure) {
  measure_ = std::move(measure);
  layout_revision_ = ~std::uint64_t(0);
}

void CanvasController::after_edit() {
  selection_.prune(document_->graph());
  layout();
}

double CanvasController::pin_radius() const { return kPinGrabPixels / view_.zoom(); }

std::optional<Rect> CanvasController::selection_box() const {
  if (mode_ != Mode::BoxSelecting || !moved_) return std::nullopt;
  return Rect::spanning(press_, mouse_);
}

void CanvasController::handle(const InputEvent& event) {
  std::visit(
      [this](const auto& e) {
        using E = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<E, MouseMove>) {
          on_mouse_move(e);
        } else if constexpr (std::is_same_v<E, MouseDown>) {
          on_mouse_down(e);
        } else if constexpr (std::is_same_v<E, MouseUp>) {
          on_mouse_up(e);
        } else if constexpr (std::is_same_v<E, Wheel>) {
          if (mode_ != Mode::Palette) view_.zoom_at(e.pos, std::pow(kZoomStep, e.notches));
        } else if constexpr (std::is_same_v<E, KeyDown>) {
          if (mode_ == Mode::Palette)
            on_palette_key(e);
          else
            on_key_down(e);
        } else if constexpr (std::is_same_v<E, KeyUp>) {
          if (e.key == Key::Space) space_held_ = false;
        } else if constexpr (std::is_same_v<E, TextInput>) {
          if (mode_ == Mode::Palette) palette_.type_text(e.text);
        }
      },
      event);
}

void CanvasController::update_hover() {
  const auto& l = layout();
  const glm::dvec2 world = mouse_world();
  hovered_pin_ = l.pin_at(world, pin_radius());
  hovered_node_ = l.node_at(world);
}

void CanvasController::on_mouse_move(const MouseMove& e) {
  const glm::dvec2 delta = e.pos - mouse_;
  mouse_ = e.pos;
  if (glm::length(mouse_ - press_) > kDragThreshold) moved_ = true;
  switch (mode_) {
    case Mode::Panning:
      view_.pan(delta);
      break;
    case Mode::MovingNodes:
      if (moved_ && !selection_.empty()) {
        // The first movement past the threshold also applies the distance travelled so far.
        const glm::dvec2 step = move_started_ ? delta : mouse_ - press_;
        move_started_ = true;
        document_->move_nodes(selection_.ordered(document_->graph()), step / view_.zoom(), true);
      }
      break;
    case Mode::BoxSelecting:
      if (moved_) {
        auto ids = layout().nodes_in(view_.to_world(Rect::spanning(press_, mouse_)));
        if (box_additive_) ids.insert(ids.begin(), box_base_.begin(), box_base_.end());
        selection_.set(ids);
      }
      break;
    default:
      break;
  }
  update_hover();
}

void CanvasController::on_mouse_down(const MouseDown& e) {
  mouse_ = press_ = e.pos;
  moved_ = false;
  move_started_ = false;
  message_.clear();
  if (mode_ == Mode::Palette) close_palette();
  if (mode_ != Mode::Idle) return;
  update_hover();

  if (e.button == MouseButton::Middle || (e.button == MouseButton::Left && space_held_)) {
    mode_ = Mode::Panning;
    return;
  }
  if (e.button == MouseButton::Right) return;  // palette on release, if the mouse did not move

  if (hovered_pin_) {
    link_drag_ = LinkDrag::begin(document_->graph(), hovered_pin_->pin);
    if (link_drag_) mode_ = Mode::DraggingLink;
    return;
  }
  if (hovered_node_) {
    pressed_node_ = *hovered_node_;
    if (e.mods.shift || e.mods.ctrl) {
      selection_.toggle(pressed_node_);
      if (!selection_.contains(pressed_node_)) return;  // toggled off: nothing to drag
    } else if (!selection_.contains(pressed_node_)) {
      selection_.select_only(pressed_node_);
    } else {
      selection_.add(pressed_node_);  // make it the active node, keep the group for dragging
    }
    mode_ = Mode::MovingNodes;
    return;
  }
  box_additive_ = e.mods.shift || e.mods.ctrl;
  box_base_ = box_additive_ ? selection_.ordered(document_->graph()) : std::vector<std::string>{};
  if (!box_additive_) selection_.clear();
  mode_ = Mode::BoxSelecting;
}

std::optional<PinId> CanvasController::drop_target(glm::dvec2 screen) const {
  if (!link_drag_) return std::nullopt;
  const glm::dvec2 world = view_.to_world(screen);
  if (auto pin = layout_.pin_at(world, kPinGrabPixels * 1.5 / view_.zoom())) return pin->pin;
  // Dropped on a node's body: its first pin that accepts the link.
  if (auto node = layout_.node_at(world)) {
    const auto* n = layout_.find(*node);
    for (const auto& p : link_drag_->anchor().output ? n->inputs : n->outputs)
      if (link_drag_->compatible(document_->graph(), p.pin)) return p.pin;
    for (const auto& p : link_drag_->anchor().output ? n->inputs : n->outputs) return p.pin;  // to report why
  }
  return std::nullopt;
}

void CanvasController::on_mouse_up(const MouseUp& e) {
  mouse_ = e.pos;
  switch (mode_) {
    case Mode::Panning:
      if (e.button == MouseButton::Middle || e.button == MouseButton::Left) mode_ = Mode::Idle;
      break;
    case Mode::MovingNodes:
      if (e.button != MouseButton::Left) break;
      document_->end_gesture();
      if (!moved_ && !(e.mods.shift || e.mods.ctrl)) selection_.select_only(pressed_node_);
      mode_ = Mode::Idle;
      break;
    case Mode::BoxSelecting:
      if (e.button == MouseButton::Left) mode_ = Mode::Idle;
      break;
    case Mode::DraggingLink: {
      if (e.button != MouseButton::Left) break;
      layout();
      const auto target = drop_target(e.pos);
      const LinkDrag drag = *link_drag_;
      link_drag_.reset();
      mode_ = Mode::Idle;
      if (!moved_) break;  // a click on a pin is not a link
      if (!target && !drag.detached() && moved_) {
        // A new link dropped on empty canvas: offer the nodes that can take it, Blender-style.
        palette_link_ = drag;
        open_palette(e.pos);
        break;
      }
      message_ = drag.drop(*document_, target);
      after_edit();
      break;
    }
    case Mode::Idle:
      if (e.button == MouseButton::Right && !moved_) open_palette(e.pos);
      break;
    default:
      break;
  }
  update_hover();
}

void CanvasController::on_key_down(const KeyDown& e) {
  const bool ctrl = e.mods.ctrl;
  switch (e.key) {
    case Key::Space:
      space_held_ = true;
      break;
    case Key::Tab:
      if (mode_ != Mode::Idle) break;
      if (e.mods.shift) {
        leave_subgraph();
        break;
      }
      // Like Blender's node groups: Tab on a selected instance goes into it; elsewhere it adds a node.
      if (navigator_ && selection_.size() == 1 && !selection_.active().empty())
        if (const Node* n = document_->graph().find(selection_.active()); n && n->type->subgraph) {
          enter_subgraph(n->id);
          break;
        }
      open_palette(view_.viewport().contains(mouse_) ? mouse_ : view_.viewport().center());
      break;
    case Key::G:
      if (ctrl && mode_ == Mode::Idle) e.mods.shift ? ungroup_selection() : (void)group_selection();
      break;
    case Key::Delete:
    case Key::X:
      if (!ctrl && mode_ == Mode::Idle)
        delete_selection();
      else if (ctrl && e.key == Key::X && mode_ == Mode::Idle) {
        copy_selection();
        delete_selection();
      }
      break;
    case Key::D:
      if (ctrl && mode_ == Mode::Idle) duplicate_selection();
      break;
    case Key::C:
      if (ctrl) copy_selection();
      break;
    case Key::V:
      if (ctrl && mode_ == Mode::Idle) paste();
      break;
    case Key::A:
      if (ctrl) select_all();
      break;
    case Key::F:
      if (!ctrl) frame(true);
      break;
    case Key::Home:
      frame(false);
      break;
    case Key::Z:
      if (ctrl && mode_ == Mode::Idle) e.mods.shift ? redo() : undo();
      break;
    case Key::Y:
      if (ctrl && mode_ == Mode::Idle) redo();
      break;
    case Key::Escape:
      if (mode_ == Mode::DraggingLink) link_drag_.reset();
      if (mode_ == Mode::BoxSelecting && box_additive_) selection_.set(box_base_);
      if (mode_ != Mode::MovingNodes) mode_ = Mode::Idle;
      break;
    default:
      break;
  }
}

void CanvasController::on_palette_key(const KeyDown& e) {
  switch (e.key) {
    case Key::Escape:
      close_palette();
      break;
    case Key::Enter:
      confirm_palette();
      break;
    case Key::Up:
      palette_.move_highlight(-1);
      break;
    case Key::Down:
    case Key::Tab:
      palette_.move_highlight(+1);
      break;
    case Key::Backspace:
      palette_.backspace();
      break;
    default:
      break;
  }
}

void CanvasController::open_palette(glm::dvec2 screen) {
  palette_screen_ = screen;
  std::vector<const NodeType*> types;
  if (palette_link_) {
    // Only the types with a pin that could take the dropped link.
    const bool want_input = palette_link_->anchor().output;
    for (const NodeType* t : palette_types_)
      for (const auto& port : want_input ? t->inputs : t->outputs)
        if (port.type == palette_link_->type()) {
          types.push_back(t);
          break;
        }
  } else {
    types = palette_types_;
  }
  palette_.set_types(std::move(types));
  palette_.set_query({});
  mode_ = Mode::Palette;
}

void CanvasController::close_palette() {
  palette_link_.reset();
  if (mode_ == Mode::Palette) mode_ = Mode::Idle;
}

std::string CanvasController::confirm_palette(const NodeType* type) {
  if (!type) type = palette_.choice();
  if (!type) return {};
  const glm::dvec2 at = view_.to_world(palette_screen_);
  std::string id;
  try {
    document_->edit("Add " + type->name, [&](Graph& g) {
      // A library asset's entry stands for an instance of it, named in files by its library name.
      id = is_asset_entry(*type) ? add_subgraph_instance(g, *type->subgraph, type->name).id : g.add_node(*type).id;
      g.editor.positions[id] = at;
      if (palette_link_) {
        // Connect the link that opened the palette to the new node's first matching pin.
        const PinId& anchor = palette_link_->anchor();
        for (const auto& port : anchor.output ? type->inputs : type->outputs) {
          if (port.type != palette_link_->type()) continue;
          if (anchor.output)
            g.connect(PortRef{anchor.node, anchor.port}, id, port.name);
          else
            g.connect(PortRef{id, port.name}, anchor.node, anchor.port);
          break;
        }
      }
    });
  } catch (const std::exception& e) {
    message_ = e.what();
    id.clear();
  }
  close_palette();
  after_edit();
  if (!id.empty()) selection_.select_only(id);
  return id;
}

void CanvasController::delete_selection() {
  // An embedded asset lives as long as an instance uses it: say so when the last one goes, so that it is not
  // dropped from the file without the user knowing (docs/subgraphs.md, "Embedded assets").
  auto embedded_names = [&] {
    std::map<std::string, const SubgraphAsset*> names;
    try {
      names = embedded_assets_of(document_->graph());
    } catch (const GraphError&) {}
    return names;
  };
  const auto before = embedded_names();
  document_->remove_nodes(selection_.ordered(document_->graph()));
  const auto after = embedded_names();
  std::string lost;
  for (const auto& [name, asset] : before)
    if (!after.count(name)) lost += std::string(lost.empty() ? "" : ", ") + "#" + name;
  if (!lost.empty())
    message_ = "embedded asset " + lost + " has no instance left: saving the graph drops it (undo keeps it)";
  after_edit();
}

void CanvasController::duplicate_selection() {
  const auto ids = selection_.ordered(document_->graph());
  if (ids.empty()) return;
  const auto box = layout().bounds(ids);
  const auto text = copy_fragment(document_->graph(), ids);
  std::vector<std::string> pasted;
  document_->edit("Duplicate",
                  [&](Graph& g) { pasted = paste_fragment(g, text, box->min + glm::dvec2(kDuplicateOffset)); });
  after_edit();
  selection_.set(pasted);
}

void CanvasController::copy_selection() {
  const auto ids = selection_.ordered(document_->graph());
  if (ids.empty()) return;
  clipboard_.set(copy_fragment(document_->graph(), ids));
}

void CanvasController::paste() {
  const std::string text = clipboard_.get();
  if (text.empty()) return;
  const glm::dvec2 at = view_.to_world(view_.viewport().contains(mouse_) ? mouse_ : view_.viewport().center());
  std::vector<std::string> pasted;
  try {
    document_->edit("Paste", [&](Graph& g) { pasted = paste_fragment(g, text, at); });
  } catch (const std::exception& e) {
    message_ = e.what();
    return;
  }
  after_edit();
  selection_.set(pasted);
}

void CanvasController::select_all() {
  std::vector<std::string> ids;
  for (const auto& n : document_->graph().nodes()) ids.push_back(n.id);
  selection_.set(ids);
}

void CanvasController::frame(bool selected_only) {
  const auto& l = layout();
  std::optional<Rect> box;
  if (selected_only && !selection_.empty()) box = l.bounds(selection_.ordered(document_->graph()));
  if (!box) box = l.bounds();
  if (box) view_.frame(*box);
}

void CanvasController::frame_opening() {
  if (const auto box = layout().bounds()) view_.frame_readable(*box);
}

void CanvasController::undo() {
  document_->undo();
  after_edit();
}

void CanvasController::redo() {
  document_->redo();
  after_edit();
}

std::string CanvasController::group_selection(const std::filesystem::path& asset_file) {
  message_.clear();
  try {
    const GroupResult r = group_nodes(*document_, selection_.ordered(document_->graph()), asset_file);
    after_edit();
    selection_.select_only(r.instance);
    return r.instance;
  } catch (const std::exception& e) {
    message_ = e.what();
    return {};
  }
}

void CanvasController::ungroup_selection() {
  message_.clear();
  std::vector<std::string> instances, added;
  for (const auto& id : selection_.ordered(document_->graph()))
    if (document_->graph().at(id).type->subgraph) instances.push_back(id);
  if (instances.empty()) {
    message_ = "nothing to ungroup: select a subgraph instance";
    return;
  }
  try {
    if (instances.size() == 1) {
      added = ungroup_node(*document_, instances.front());
    } else {
      const auto dir = document_directory(*document_);
      document_->edit("Ungroup " + std::to_string(instances.size()) + " instances", [&](Graph& g) {
        added.clear();
        for (const auto& id : instances) {
          auto more = inline_instance(g, id, dir);
          added.insert(added.end(), more.begin(), more.end());
        }
      });
    }
  } catch (const std::exception& e) {
    message_ = e.what();
    added.clear();
  }
  after_edit();
  selection_.set(added);
}

bool CanvasController::enter_subgraph(const std::string& id) {
  message_.clear();
  const std::string target = id.empty() ? selection_.active() : id;
  if (!navigator_ || target.empty()) return false;
  try {
    navigator_->sync();
    navigator_->enter(target);
  } catch (const std::exception& e) {
    message_ = e.what();
    return false;
  }
  const CanvasView outer = view_;
  set_document(navigator_->current());
  outer_views_.push_back({outer, target});
  frame(false);
  return true;
}

bool CanvasController::leave_subgraph() {
  if (!navigator_ || !navigator_->inside()) return false;
  if (!navigator_->leave()) {
    message_ = navigator_->sync_error() + " (undo or fix it before leaving)";
    return false;
  }
  std::optional<SavedLevel> saved;
  if (!outer_views_.empty()) {
    saved = outer_views_.back();
    outer_views_.pop_back();
  }
  set_document(navigator_->current());
  if (saved) {
    // Back to where the user was, with the instance they left selected.
    const Rect viewport = view_.viewport();  // the canvas panel may have been resized inside
    view_ = saved->view;
    view_.set_viewport(viewport.min, viewport.max - viewport.min);
    if (document_->graph().find(saved->instance)) selection_.select_only(saved->instance);
  }
  return true;
}

void CanvasController::leave_subgraph_to(std::size_t depth) {
  while (navigator_ && navigator_->depth() > depth && leave_subgraph()) {}
}

}  // namespace orogen::editor
