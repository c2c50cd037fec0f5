#include "editor/ui/node_canvas.h"

#include "editor/model/preview_image.h"
#include "editor/model/text_summary.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

#include <GLFW/glfw3.h>
#include <imgui_stdlib.h>

#include "editor/ui/theme.h"
#include "graph/subgraph.h"

namespace orogen::editor {

namespace {

ImVec2 iv(glm::dvec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }
glm::dvec2 gv(ImVec2 v) { return {v.x, v.y}; }

std::string format_ms(double ms) {
  char buf[32];
  if (ms < 1.0)
    std::snprintf(buf, sizeof buf, "%.2f ms", ms);
  else if (ms < 1000.0)
    std::snprintf(buf, sizeof buf, "%.0f ms", ms);
  else
    std::snprintf(buf, sizeof buf, "%.1f s", ms / 1000.0);
  return buf;
}

constexpr double kTooltipDelay = 0.35;  // seconds of hovering before a tooltip

}  // namespace

NodeCanvasView::NodeCanvasView(CanvasController& controller, const EvaluationController& evaluation)
    : controller_(controller), evaluation_(evaluation) {}

ImFont* NodeCanvasView::text_font(float size) const {
  ImFont* small = small_font_ ? small_font_ : ImGui::GetFont();
  ImFont* large = large_font_ ? large_font_ : small;
  return size > small->FontSize * 1.15f ? large : small;
}

void NodeCanvasView::draw(const std::string& previewed) {
  double_clicked_.reset();
  // Thumbnails of nodes that are gone are released.
  std::erase_if(thumbnails_, [&](const auto& kv) { return !controller_.document().graph().find(kv.first); });
  states_ = evaluation_.node_states();
  ImFont* font = small_font_ ? small_font_ : ImGui::GetFont();
  controller_.set_text_measure([font](std::string_view s) {
    return static_cast<double>(font->CalcTextSizeA(kFontSize, FLT_MAX, 0.0f, s.data(), s.data() + s.size()).x);
  });

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 50.0f);
  size.y = std::max(size.y, 50.0f);
  controller_.view().set_viewport(gv(origin), gv(size));

  ImGui::InvisibleButton(
      "##canvas", size,
      ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight | ImGuiButtonFlags_MouseButtonMiddle);
  const bool hovered = ImGui::IsItemHovered();
  feed_input(hovered);

  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->PushClipRect(origin, {origin.x + size.x, origin.y + size.y}, true);
  dl->AddRectFilled(origin, {origin.x + size.x, origin.y + size.y}, theme::kCanvasBackground);
  draw_grid(dl);
  draw_links(dl);
  draw_nodes(dl, previewed);
  if (auto box = controller_.selection_box()) {
    dl->AddRectFilled(iv(box->min), iv(box->max), IM_COL32(255, 176, 60, 30));
    dl->AddRect(iv(box->min), iv(box->max), IM_COL32(255, 176, 60, 160));
  }
  if (controller_.document().graph().nodes().empty()) {
    const char* hint = "Press Tab or right-click to add a node";
    const ImVec2 ts = ImGui::CalcTextSize(hint);
    dl->AddText({origin.x + (size.x - ts.x) * 0.5f, origin.y + (size.y - ts.y) * 0.5f}, theme::kTextDim, hint);
  }
  dl->PopClipRect();
  draw_problems_banner(origin, size);
  if (hovered) draw_tooltips();
  draw_palette();
}

void NodeCanvasView::draw_thumbnail(ImDrawList* dl, const Node& node, const Rect& box) {
  dl->AddRectFilled(iv(box.min), iv(box.max), IM_COL32(24, 25, 28, 255), 3.0f);
  const auto thumbs = evaluation_.thumbnails();
  if (!thumbs) return;
  const auto it = thumbs->outputs.find(node.id);
  if (it == thumbs->outputs.end()) return;
  // The first output that can be pictured: a heightfield in the colours of its kind, an image, points (or a
  // scene's instances) or curves drawn in the world rectangle.
  const PortValue* shown = nullptr;
  std::string port;
  for (std::size_t k = 0; k < it->second.size() && k < node.type->outputs.size(); ++k) {
    const PortValue& v = it->second[k];
    if (!has_value(v) || std::holds_alternative<MeshPtr>(v) || std::holds_alternative<PolygonMapPtr>(v) ||
        std::holds_alternative<ReportPtr>(v))
      continue;
    shown = &v;
    port = node.type->outputs[k].name;
    break;
  }
  if (!shown) return;
  const void* data = std::visit(
      [](const auto& v) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return nullptr;
        else
          return v.get();
      },
      *shown);
  Thumbnail& t = thumbnails_[node.id];
  if (t.data != data) {
    PreviewPixels px;
    if (auto* h = std::get_if<HeightfieldPtr>(shown))
      px = render_heightfield(
          **h, style_for(output_kind_ ? output_kind_(node.id, port)
                                      : resolve_output_kind(controller_.document().graph(), node.id, port)));
    else if (auto* im = std::get_if<ImagePtr>(shown))
      px = render_image(**im);
    else if (auto* p = std::get_if<PointsPtr>(shown))
      px = render_points(**p, thumbs->domain);
    else if (auto* sc = std::get_if<ScenePtr>(shown); sc && (*sc)->instances)
      px = render_points(*(*sc)->instances, thumbs->domain);
    else if (auto* c = std::get_if<CurvesPtr>(shown))
      px = render_curves(**c, thumbs->domain);
    if (px.width <= 0) return;
    t.texture.upload(px.width, px.height, px.rgba.data());
    t.data = data;
    t.value = *shown;
  }
  // Fitted, keeping the world's aspect ratio.
  const double aspect = static_cast<double>(t.texture.width()) / std::max(1, t.texture.height());
  glm::dvec2 size = box.size();
  if (size.x / size.y > aspect)
    size.x = size.y * aspect;
  else
    size.y = size.x / aspect;
  const glm::dvec2 a = box.center() - size * 0.5;
  dl->AddImage(t.texture.imgui_id(), iv(a), iv(a + size));
}

void NodeCanvasView::draw_problems_banner(ImVec2 origin, ImVec2 size) {
  const auto& problems = controller_.document().load_problems();
  if (problems.empty() || dismissed_problems_) return;
  ImGui::SetCursorScreenPos({origin.x + 10, origin.y + 8});
  ImGui::PushStyleColor(ImGuiCol_ChildBg, IM_COL32(90, 30, 30, 235));
  const float line = ImGui::GetTextLineHeightWithSpacing();
  const std::size_t lines = 1 + (show_problem_list_ ? problems.diagnostics.size() : 0);
  const float height =
      std::min(size.y * 0.4f, static_cast<float>(lines) * line + 2.0f * ImGui::GetStyle().WindowPadding.y + 4.0f);
  ImGui::BeginChild("##problems", {std::min(size.x - 20.0f, 760.0f), height}, true,
                    ImGuiWindowFlags_AlwaysUseWindowPadding);
  ImGui::TextColored(ImVec4(1, 0.85f, 0.8f, 1),
                     "%zu problem%s in %s: what could be read is shown; the nodes concerned are framed in red",
                     problems.diagnostics.size(), problems.diagnostics.size() == 1 ? "" : "s",
                     controller_.document().display_name().c_str());
  ImGui::SameLine();
  if (ImGui::SmallButton(show_problem_list_ ? "Hide" : "Details")) show_problem_list_ = !show_problem_list_;
  ImGui::SameLine();
  if (ImGui::SmallButton("Dismiss")) dismissed_problems_ = true;
  if (show_problem_list_) {
    ImGui::PushTextWrapPos(std::min(size.x - 40.0f, 740.0f));
    for (const auto& d : problems.diagnostics) ImGui::BulletText("%s", d.str().c_str());
    ImGui::PopTextWrapPos();
  }
  ImGui::EndChild();
  ImGui::PopStyleColor();
}

void NodeCanvasView::feed_input(bool hovered) {
  ImGuiIO& io = ImGui::GetIO();
  const Modifiers mods{io.KeyCtrl, io.KeyShift, io.KeyAlt};
  const bool dragging =
      controller_.mode() != CanvasController::Mode::Idle && controller_.mode() != CanvasController::Mode::Palette;
  if ((hovered || dragging) && (io.MousePos.x != last_mouse_.x || io.MousePos.y != last_mouse_.y) &&
      ImGui::IsMousePosValid()) {
    controller_.handle(MouseMove{gv(io.MousePos)});
    last_mouse_ = io.MousePos;
  }
  static constexpr MouseButton kButtons[3] = {MouseButton::Left, MouseButton::Right, MouseButton::Middle};
  for (int b = 0; b < 3; ++b) {
    if (hovered && ImGui::IsMouseClicked(b)) {
      pressed_[b] = true;
      controller_.handle(MouseDown{kButtons[b], gv(io.MousePos), mods});
      if (b == 0 && ImGui::IsMouseDoubleClicked(0) && controller_.hovered_node() && !controller_.hovered_pin())
        double_clicked_ = *controller_.hovered_node();
    }
    if (pressed_[b] && ImGui::IsMouseReleased(b)) {
      pressed_[b] = false;
      controller_.handle(MouseUp{kButtons[b], gv(io.MousePos), mods});
    }
  }
  if (hovered && io.MouseWheel != 0.0f) controller_.handle(Wheel{gv(io.MousePos), io.MouseWheel});

  // Keys go to the canvas while it is hovered or focused and no text field has the keyboard.
  const bool palette = controller_.mode() == CanvasController::Mode::Palette;
  if (palette || io.WantTextInput) return;
  if (!hovered && !ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows)) return;
  const bool space = ImGui::IsKeyDown(GLFW_KEY_SPACE);
  if (space != space_down_) {
    space_down_ = space;
    if (space)
      controller_.handle(KeyDown{Key::Space, mods});
    else
      controller_.handle(KeyUp{Key::Space});
  }
  static constexpr std::pair<int, Key> kKeys[] = {
      {GLFW_KEY_TAB, Key::Tab},   {GLFW_KEY_DELETE, Key::Delete}, {GLFW_KEY_X, Key::X},
      {GLFW_KEY_D, Key::D},       {GLFW_KEY_C, Key::C},           {GLFW_KEY_V, Key::V},
      {GLFW_KEY_A, Key::A},       {GLFW_KEY_F, Key::F},           {GLFW_KEY_G, Key::G},
      {GLFW_KEY_HOME, Key::Home}, {GLFW_KEY_ESCAPE, Key::Escape}, {GLFW_KEY_BACKSPACE, Key::Delete}};
  for (const auto& [glfw_key, key] : kKeys)
    if (ImGui::IsKeyPressed(glfw_key, false)) controller_.handle(KeyDown{key, mods});
}

void NodeCanvasView::draw_grid(ImDrawList* dl) {
  const CanvasView& v = controller_.view();
  const Rect vis = v.visible();
  const auto draw_lines = [&](double step, ImU32 color) {
    if (step * v.zoom() < 8.0) return;
    for (double x = std::floor(vis.min.x / step) * step; x <= vis.max.x; x += step) {
      const float sx = static_cast<float>(v.to_screen({x, 0}).x);
      dl->AddLine({sx, static_cast<float>(v.origin().y)}, {sx, static_cast<float>(v.origin().y + v.size().y)}, color);
    }
    for (double y = std::floor(vis.min.y / step) * step; y <= vis.max.y; y += step) {
      const float sy = static_cast<float>(v.to_screen({0, y}).y);
      dl->AddLine({static_cast<float>(v.origin().x), sy}, {static_cast<float>(v.origin().x + v.size().x), sy}, color);
    }
  };
  draw_lines(32.0, theme::kGridMinor);
  draw_lines(256.0, theme::kGridMajor);
}

void NodeCanvasView::draw_links(ImDrawList* dl) {
  const CanvasView& v = controller_.view();
  const auto& layout = controller_.layout();
  const Graph& graph = controller_.document().graph();
  const float zoom = static_cast<float>(v.zoom());
  const auto& drag = controller_.link_drag();
  const auto bezier = [&](glm::dvec2 a, glm::dvec2 b, ImU32 color, float thickness) {
    const float d = std::max(40.0f * zoom, static_cast<float>(std::abs(b.x - a.x)) * 0.5f);
    dl->AddBezierCubic(iv(a), {static_cast<float>(a.x) + d, static_cast<float>(a.y)},
                       {static_cast<float>(b.x) - d, static_cast<float>(b.y)}, iv(b), color, thickness);
  };
  for (const auto& node : graph.nodes()) {
    const auto* to = layout.find(node.id);
    for (const auto& [port, src] : node.inputs) {
      // The link picked up by a drag follows the mouse instead.
      if (drag && drag->detached() && drag->detached()->node == node.id && drag->detached()->port == port) continue;
      const auto* from = layout.find(src.node);
      if (!from || !to) continue;
      const auto* out = from->find_pin(src.port, true);
      const auto* in = to->find_pin(port, false);
      if (!out || !in) continue;
      // Links of the selected nodes stand out.
      const bool lit = controller_.is_selected(node.id) || controller_.is_selected(src.node);
      const ImU32 color = theme::with_alpha(theme::port_color(out->type), lit ? 1.0f : 0.7f);
      bezier(v.to_screen(out->position), v.to_screen(in->position), color, std::max(1.5f, (lit ? 3.5f : 2.5f) * zoom));
    }
  }
  // Links of the file left out when it was opened (broken, or closing a cycle): dashed red from where they
  // came (the source node's right edge when its port does not exist) to the input, while it stays empty.
  for (const auto& d : controller_.document().load_problems().dropped_links) {
    const Node* dst = graph.find(d.to_node);
    const auto* to = layout.find(d.to_node);
    const auto* from = layout.find(d.from.node);
    if (!dst || !to || !from || dst->inputs.count(d.to_port)) continue;
    const auto* in = to->find_pin(d.to_port, false);
    const auto* out = from->find_pin(d.from.port, true);
    const glm::dvec2 a = v.to_screen(out ? out->position : glm::dvec2(from->rect.max.x, from->title.center().y));
    const glm::dvec2 b = v.to_screen(in ? in->position : glm::dvec2(to->rect.min.x, to->title.center().y));
    const int dashes = std::max(4, static_cast<int>(glm::length(b - a) / 14.0));
    for (int k = 0; k < dashes; k += 2) {
      const glm::dvec2 p0 = a + (b - a) * (static_cast<double>(k) / dashes);
      const glm::dvec2 p1 = a + (b - a) * (static_cast<double>(k + 1) / dashes);
      dl->AddLine(iv(p0), iv(p1), theme::kError, std::max(1.5f, 2.5f * zoom));
    }
  }
  // The link being dragged follows the mouse; a link dropped on empty canvas leads to the palette.
  const bool palette = controller_.mode() == CanvasController::Mode::Palette;
  const auto& pending = palette ? controller_.palette_link() : drag;
  if (pending) {
    const auto* anchor_node = layout.find(pending->anchor().node);
    const auto* anchor =
        anchor_node ? anchor_node->find_pin(pending->anchor().port, pending->anchor().output) : nullptr;
    if (anchor) {
      glm::dvec2 end = palette ? controller_.palette_position() : controller_.mouse();
      if (const auto& hp = controller_.hovered_pin(); !palette && hp && pending->compatible(graph, hp->pin))
        end = v.to_screen(hp->position);
      const glm::dvec2 a = v.to_screen(anchor->position);
      const ImU32 color = theme::port_color(pending->type());
      if (pending->anchor().output)
        bezier(a, end, color, std::max(2.0f, 3.0f * zoom));
      else
        bezier(end, a, color, std::max(2.0f, 3.0f * zoom));
    }
  }
}

void NodeCanvasView::draw_nodes(ImDrawList* dl, const std::string& previewed) {
  const CanvasView& v = controller_.view();
  const auto& layout = controller_.layout();
  const Graph& graph = controller_.document().graph();
  const float zoom = static_cast<float>(v.zoom());
  const float font_size = kFontSize * zoom;
  const bool show_text = zoom >= 0.45f;
  ImFont* font = text_font(font_size);
  const auto& drag = controller_.link_drag();
  const Rect viewport = v.viewport();

  // In an asset (a subgraph entered or opened): the inner ports its interface feeds and presents, drawn as
  // linked to the outside, with the interface port's name.
  std::map<std::pair<std::string, std::string>, std::string> interface_ports;
  std::vector<std::tuple<ImVec2, std::string, ImU32>> stub_labels;
  if (graph.interface) {
    for (const auto& in : graph.interface->inputs)
      for (const auto& t : in.targets) interface_ports[{t.node, t.name}] = in.port.name;
    for (const auto& out : graph.interface->outputs)
      interface_ports[{out.source.node, out.source.port}] = out.port.name;
  }
  // Which outputs are used, to fill their pins.
  std::set<std::pair<std::string, std::string>> used_outputs;
  for (const auto& n : graph.nodes())
    for (const auto& [port, src] : n.inputs) used_outputs.insert({src.node, src.port});

  for (const auto& nl : layout.nodes()) {
    const Rect r = v.to_screen(nl.rect);
    if (!r.overlaps(viewport.expanded(20))) continue;
    const Node& node = graph.at(nl.id);
    const bool selected = controller_.is_selected(nl.id);
    const bool active = controller_.active_node() == nl.id;
    const float rounding = 6.0f * zoom;
    const Rect title = v.to_screen(nl.title);
    const Rect status = v.to_screen(nl.status);

    // Shadow, body, title bar, border.
    dl->AddRectFilled(iv(r.min + glm::dvec2(3, 4) * static_cast<double>(zoom)),
                      iv(r.max + glm::dvec2(3, 4) * static_cast<double>(zoom)), IM_COL32(0, 0, 0, 70), rounding);
    dl->AddRectFilled(iv(r.min), iv(r.max), theme::kNodeBody, rounding);
    dl->AddRectFilled(iv(title.min), iv(title.max), theme::category_color(node.type->category), rounding,
                      ImDrawFlags_RoundCornersTop);
    dl->AddRectFilled(iv(status.min), iv(status.max), IM_COL32(38, 40, 46, 255), rounding,
                      ImDrawFlags_RoundCornersBottom);
    const ImU32 border = active ? theme::kNodeActive : selected ? theme::kNodeSelected : theme::kNodeBorder;
    dl->AddRect(iv(r.min), iv(r.max), border, rounding, 0, selected ? 2.0f : 1.0f);
    // A problem of the file it was loaded from: a red frame and a "!" (the tooltip explains).
    const bool problem = !controller_.document().load_problems().for_node(nl.id).empty();
    if (problem) {
      dl->AddRect(iv(r.min - glm::dvec2(3.0 * zoom)), iv(r.max + glm::dvec2(3.0 * zoom)), theme::kError,
                  rounding + 3.0f * zoom, 0, std::max(1.5f, 2.5f * zoom));
      const ImVec2 c{static_cast<float>(r.min.x), static_cast<float>(r.min.y)};
      dl->AddCircleFilled(c, 8.0f * std::max(zoom, 0.6f), theme::kError);
      const float fs = 13.0f * std::max(zoom, 0.6f);
      const ImVec2 ts = font->CalcTextSizeA(fs, FLT_MAX, 0.0f, "!");
      dl->AddText(font, fs, {c.x - ts.x * 0.5f, c.y - ts.y * 0.5f}, IM_COL32(255, 255, 255, 255), "!");
    }

    const NodeRunState state = [&] {
      auto it = states_.find(nl.id);
      return it == states_.end() ? NodeRunState{} : it->second;
    }();

    if (show_text) {
      const ImVec2 tp{static_cast<float>(title.min.x) + 8.0f * zoom,
                      static_cast<float>(title.center().y) - font_size * 0.5f};
      dl->PushClipRect(iv(title.min), iv(title.max - glm::dvec2(16.0 * zoom, 0)), true);
      dl->AddText(font, font_size, tp, theme::kText, node_title(node).c_str());
      dl->PopClipRect();
    }
    if (nl.id == previewed) {
      // The previewed node: an eye-like dot on the title bar.
      const ImVec2 c{static_cast<float>(title.max.x) - 10.0f * zoom, static_cast<float>(title.center().y)};
      dl->AddCircleFilled(c, 4.5f * zoom, IM_COL32(255, 255, 255, 230));
      dl->AddCircleFilled(c, 2.0f * zoom, IM_COL32(40, 40, 40, 255));
    }

    // Pins.
    for (const auto* pins : {&nl.inputs, &nl.outputs})
      for (const auto& p : *pins) {
        const ImVec2 c = iv(v.to_screen(p.position));
        const auto exposed = interface_ports.find({nl.id, p.pin.port});
        const bool connected =
            exposed != interface_ports.end() ||
            (p.pin.output ? used_outputs.count({nl.id, p.pin.port}) != 0 : node.inputs.count(p.pin.port) != 0);
        float alpha = 1.0f;
        bool highlight = false;
        if (drag) {
          const bool ok = drag->compatible(graph, p.pin);
          alpha = ok ? 1.0f : 0.22f;
          highlight = ok && controller_.hovered_pin() && controller_.hovered_pin()->pin == p.pin;
        } else if (controller_.hovered_pin() && controller_.hovered_pin()->pin == p.pin) {
          highlight = true;
        }
        const ImU32 color = theme::with_alpha(theme::port_color(p.type), alpha);
        const float radius = static_cast<float>(NodeMetrics::kPinRadius) * zoom;
        dl->AddCircleFilled(c, radius, connected ? color : theme::with_alpha(IM_COL32(30, 32, 36, 255), alpha));
        dl->AddCircle(c, radius, color, 0, 1.8f * std::max(zoom, 0.6f));
        if (highlight) dl->AddCircle(c, radius + 3.0f * zoom, IM_COL32(255, 255, 255, 200), 0, 1.5f);
        if (exposed != interface_ports.end()) {
          // A stub out of the node to the interface port it is linked to.
          const float dir = p.pin.output ? 1.0f : -1.0f, stub = 26.0f * zoom;
          dl->AddLine({c.x + dir * radius, c.y}, {c.x + dir * stub, c.y}, theme::with_alpha(color, 0.8f * alpha),
                      2.0f * std::max(zoom, 0.6f));
          dl->AddCircle({c.x + dir * stub, c.y}, radius * 0.7f, color, 0, 1.5f);
          if (show_text) {
            const std::string& label = exposed->second;
            const ImVec2 ts = font->CalcTextSizeA(font_size * 0.85f, FLT_MAX, 0.0f, label.c_str());
            const float x = p.pin.output ? c.x + stub + 8.0f * zoom : c.x - stub - 8.0f * zoom - ts.x;
            stub_labels.emplace_back(ImVec2{x, c.y - font_size * 0.45f}, label,
                                     theme::with_alpha(theme::kTextDim, alpha));
          }
        }
        if (show_text) {
          const char* label = p.pin.port.c_str();
          const ImVec2 ts = font->CalcTextSizeA(font_size, FLT_MAX, 0.0f, label);
          const float x = p.pin.output ? c.x - ts.x - 10.0f * zoom : c.x + 10.0f * zoom;
          const bool optional = !p.pin.output && node.type->find_input(p.pin.port)->optional;
          dl->AddText(font, font_size, {x, c.y - font_size * 0.5f},
                      theme::with_alpha(optional ? theme::kTextDim : theme::kText, alpha), label);
        }
      }

    if (nl.thumbnail) draw_thumbnail(dl, node, v.to_screen(*nl.thumbnail));

    // Status line: phase and last time, or a progress bar while computing.
    if (show_text) {
      const float pad = 6.0f * zoom;
      const ImU32 sc = theme::status_color(state.phase);
      const ImVec2 dot{static_cast<float>(status.min.x) + pad + 3.0f * zoom, static_cast<float>(status.center().y)};
      dl->AddCircleFilled(dot, 3.5f * zoom, sc);
      const float text_x = dot.x + 8.0f * zoom;
      const float text_y = static_cast<float>(status.center().y) - font_size * 0.45f;
      const float small = font_size * 0.9f;
      if (state.phase == NodeRunState::Phase::Computing) {
        const ImVec2 b0{text_x, static_cast<float>(status.center().y) - 4.0f * zoom};
        const ImVec2 b1{static_cast<float>(status.max.x) - pad, static_cast<float>(status.center().y) + 4.0f * zoom};
        dl->AddRectFilled(b0, b1, IM_COL32(25, 26, 30, 255), 3.0f * zoom);
        dl->AddRectFilled(b0, {b0.x + (b1.x - b0.x) * static_cast<float>(std::clamp(state.progress, 0.0, 1.0)), b1.y},
                          sc, 3.0f * zoom);
      } else {
        std::string text(to_string(state.phase));
        // Previews never write files: writers run in builds only.
        if (node.type->writes_files && state.phase == NodeRunState::Phase::Unknown) text = "runs on build";
        if (state.milliseconds > 0.0 &&
            (state.phase == NodeRunState::Phase::Computed || state.phase == NodeRunState::Phase::Cached ||
             state.phase == NodeRunState::Phase::Stale))
          text = format_ms(state.milliseconds) + (state.phase == NodeRunState::Phase::Cached ? "  cached" : "");
        dl->PushClipRect(iv(status.min), iv(status.max), true);
        dl->AddText(font, small, {text_x, text_y},
                    state.phase == NodeRunState::Phase::Failed ? theme::kError : theme::kTextDim, text.c_str());
        dl->PopClipRect();
      }
    }
  }
  // Interface stubs' labels over every node: they stick out into the space between nodes.
  for (const auto& [pos, label, color] : stub_labels) {
    const ImVec2 ts = font->CalcTextSizeA(font_size * 0.85f, FLT_MAX, 0.0f, label.c_str());
    const float pad = 3.0f * zoom;
    dl->AddRectFilled({pos.x - pad, pos.y - pad * 0.5f}, {pos.x + ts.x + pad, pos.y + ts.y + pad * 0.5f},
                      IM_COL32(24, 26, 30, 235), 3.0f * zoom);
    dl->AddText(font, font_size * 0.85f, pos, color, label.c_str());
  }
}

void NodeCanvasView::draw_tooltips() {
  const Graph& graph = controller_.document().graph();
  std::string key;
  if (controller_.mode() != CanvasController::Mode::Idle) {
    hover_key_.clear();
    return;
  }
  if (const auto& p = controller_.hovered_pin())
    key = "pin:" + p->pin.node + "." + p->pin.port;
  else if (const auto& n = controller_.hovered_node())
    key = "node:" + *n;
  if (key != hover_key_) {
    hover_key_ = key;
    hover_since_ = ImGui::GetTime();
  }
  if (key.empty() || ImGui::GetTime() - hover_since_ < kTooltipDelay) return;

  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 28.0f);
  if (const auto& p = controller_.hovered_pin()) {
    const Node* node = graph.find(p->pin.node);
    const PortDecl* decl =
        node ? (p->pin.output ? node->type->find_output(p->pin.port) : node->type->find_input(p->pin.port)) : nullptr;
    if (decl) {
      ImGui::TextColored(ImColor(theme::port_color(decl->type)), "%s  (%s%s)", decl->name.c_str(),
                         std::string(to_string(decl->type)).c_str(), decl->optional ? ", optional" : "");
      if (!decl->description.empty()) ImGui::TextUnformatted(decl->description.c_str());
      if (!p->pin.output)
        if (auto it = node->inputs.find(decl->name); it != node->inputs.end())
          ImGui::TextDisabled("from %s", it->second.str().c_str());
    }
  } else if (const auto& id = controller_.hovered_node()) {
    const Node* node = graph.find(*id);
    if (node) {
      ImGui::Text("%s", node_title(*node).c_str());
      ImGui::TextDisabled("%s / %s", node->type->category.c_str(), node->type->name.c_str());
      if (!node->type->description.empty()) ImGui::TextUnformatted(node->type->description.c_str());
      const auto problems = controller_.document().load_problems().for_node(*id);
      if (!problems.empty()) {
        ImGui::Separator();
        ImGui::TextColored(ImColor(theme::kError), "When the file was opened:");
        for (const auto& m : problems) ImGui::BulletText("%s", m.c_str());
      }
      auto it = states_.find(*id);
      if (it != states_.end()) {
        const auto& s = it->second;
        ImGui::Separator();
        ImGui::TextColored(ImColor(theme::status_color(s.phase)), "%s", std::string(to_string(s.phase)).c_str());
        if (s.milliseconds > 0.0) {
          ImGui::SameLine();
          ImGui::TextDisabled("last computed in %s", format_ms(s.milliseconds).c_str());
        }
        if (!s.message.empty()) ImGui::TextColored(ImColor(theme::kError), "%s", s.message.c_str());
      }
    }
  }
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

void NodeCanvasView::draw_palette() {
  if (controller_.mode() != CanvasController::Mode::Palette) {
    palette_focus_ = false;
    return;
  }
  PaletteState& palette = controller_.palette();
  const bool opening = !palette_focus_;
  if (opening) palette_buffer_ = palette.query();
  // Kept on screen near the window's edges, using the size it had last frame.
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const glm::dvec2 at =
      place_popup(controller_.palette_position(), palette_size_, Rect{{0.0, 0.0}, {display.x, display.y}});
  ImGui::SetNextWindowPos(iv(at), ImGuiCond_Always);
  ImGui::SetNextWindowSize({320, 0}, ImGuiCond_Always);
  ImGui::Begin("##palette", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize);
  if (opening) {
    ImGui::SetKeyboardFocusHere();
    palette_focus_ = true;
  }
  ImGui::SetNextItemWidth(-1);
  if (ImGui::InputTextWithHint("##query", "Search nodes...", &palette_buffer_)) palette.set_query(palette_buffer_);
  if (!opening && !ImGui::IsItemActive() && !ImGui::IsWindowFocused()) {
    // Focus went elsewhere: the palette closes like a popup.
    ImGui::End();
    controller_.close_palette();
    return;
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_DOWN)) palette.move_highlight(+1);
  if (ImGui::IsKeyPressed(GLFW_KEY_UP)) palette.move_highlight(-1);
  const NodeType* chosen = nullptr;
  bool confirm = ImGui::IsKeyPressed(GLFW_KEY_ENTER) || ImGui::IsKeyPressed(GLFW_KEY_KP_ENTER);
  const bool cancel = ImGui::IsKeyPressed(GLFW_KEY_ESCAPE);

  // One size whatever the results: a list of kVisibleRows rows and a description of kDescriptionLines lines
  // (the whole of it on hover), so the palette stays where it is as typing narrows the results.
  const auto& results = palette.results();
  const float row_h = ImGui::GetTextLineHeightWithSpacing();
  ImGui::BeginChild("##results", {0, PaletteState::kVisibleRows * row_h + 6}, false);
  if (results.empty()) ImGui::TextDisabled("No node type matches.");
  for (int k = 0; k < static_cast<int>(results.size()); ++k) {
    const NodeType* t = results[static_cast<std::size_t>(k)].type;
    ImGui::PushID(k);
    const bool highlighted = k == palette.highlighted();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    if (ImGui::Selectable("##row", highlighted)) {
      chosen = t;
      confirm = true;
    }
    if (ImGui::IsItemHovered() && ImGui::GetIO().MouseDelta.x * ImGui::GetIO().MouseDelta.y != 0.0f)
      palette.set_highlight(k);
    if (highlighted && (ImGui::IsKeyPressed(GLFW_KEY_DOWN) || ImGui::IsKeyPressed(GLFW_KEY_UP)))
      ImGui::SetScrollHereY();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float h = ImGui::GetTextLineHeight();
    dl->AddRectFilled({p.x + 2, p.y + 3}, {p.x + 8, p.y + h - 3}, theme::category_color(t->category), 2.0f);
    // The name with the matched characters highlighted.
    float x = p.x + 14;
    const auto& hits = results[static_cast<std::size_t>(k)].name_positions;
    for (std::size_t c = 0; c < t->name.size(); ++c) {
      const bool hit = std::find(hits.begin(), hits.end(), static_cast<int>(c)) != hits.end();
      const char ch[2] = {t->name[c], 0};
      dl->AddText({x, p.y}, hit ? IM_COL32(255, 190, 90, 255) : theme::kText, ch);
      x += ImGui::CalcTextSize(ch).x;
    }
    // The category, and the node library a type comes from.
    const std::string where = t->library.empty() ? t->category : t->category + " \xc2\xb7 " + t->library;
    const ImVec2 cs = ImGui::CalcTextSize(where.c_str());
    dl->AddText({p.x + ImGui::GetContentRegionAvail().x - cs.x - 4, p.y}, theme::kTextDim, where.c_str());
    ImGui::PopID();
  }
  ImGui::EndChild();
  ImGui::Separator();
  const float wrap = ImGui::GetContentRegionAvail().x;
  const NodeType* described = palette.choice();
  const TextSummary summary =
      summarize_text(described ? described->description : std::string(), wrap, PaletteState::kDescriptionLines,
                     [](std::string_view s) { return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x; });
  ImGui::BeginChild("##description", {0, PaletteState::kDescriptionLines * ImGui::GetTextLineHeightWithSpacing()},
                    false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  for (const auto& line : summary.lines) ImGui::TextDisabled("%s", line.c_str());
  if (summary.cut && ImGui::IsWindowHovered()) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 28.0f);
    ImGui::TextUnformatted(described->description.c_str());
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
  }
  ImGui::EndChild();
  palette_size_ = {ImGui::GetWindowSize().x, ImGui::GetWindowSize().y};
  ImGui::End();

  if (cancel)
    controller_.close_palette();
  else if (confirm)
    controller_.confirm_palette(chosen);
}

}  // namespace orogen::editor
