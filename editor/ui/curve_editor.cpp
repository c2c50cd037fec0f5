#include "editor/ui/curve_editor.h"

#include <algorithm>
#include <cmath>

#include "editor/ui/theme.h"
#include "nodes/common/color_space.h"

namespace orogen::editor {

namespace {

constexpr float kHandle = 5.0f;
constexpr double kMinGap = 1e-3;  // minimum x distance between curve points

ImU32 to_u32(const glm::vec4& c) {
  return ImGui::ColorConvertFloat4ToU32(
      {linear_to_srgb(c.r), linear_to_srgb(c.g), linear_to_srgb(c.b), std::clamp(c.a, 0.0f, 1.0f)});
}

}  // namespace

WidgetEdit curve_editor(const char* id, CurveValue& curve, float width) {
  WidgetEdit edit;
  ImGui::PushID(id);
  ImGuiStorage* storage = ImGui::GetStateStorage();
  const ImGuiID drag_key = ImGui::GetID("drag");
  int dragging = storage->GetInt(drag_key, -1);

  // The shown range: [0, 1] in both axes, grown to hold every point.
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  for (const auto& p : curve.points) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  const float height = std::max(120.0f, width * 0.6f);
  const ImVec2 a = ImGui::GetCursorScreenPos();
  const ImVec2 b{a.x + width, a.y + height};
  const float pad = 8.0f;
  auto to_screen = [&](glm::dvec2 p) {
    return ImVec2{a.x + pad + static_cast<float>((p.x - x0) / (x1 - x0)) * (width - 2 * pad),
                  b.y - pad - static_cast<float>((p.y - y0) / (y1 - y0)) * (height - 2 * pad)};
  };
  auto to_curve = [&](ImVec2 s) {
    return glm::dvec2{x0 + (s.x - a.x - pad) / (width - 2 * pad) * (x1 - x0),
                      y0 + (b.y - pad - s.y) / (height - 2 * pad) * (y1 - y0)};
  };

  ImGui::InvisibleButton("##area", {width, height},
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  int near = -1;
  for (int k = 0; k < static_cast<int>(curve.points.size()); ++k) {
    const ImVec2 s = to_screen(curve.points[static_cast<std::size_t>(k)]);
    if (std::abs(s.x - mouse.x) <= kHandle + 3 && std::abs(s.y - mouse.y) <= kHandle + 3) near = k;
  }

  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left) && near >= 0) dragging = near;
  if (dragging >= 0 && dragging < static_cast<int>(curve.points.size()) && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    glm::dvec2 p = to_curve(mouse);
    const auto k = static_cast<std::size_t>(dragging);
    const double lo = k > 0 ? curve.points[k - 1].x + kMinGap : -1e300;
    const double hi = k + 1 < curve.points.size() ? curve.points[k + 1].x - kMinGap : 1e300;
    p.x = std::clamp(p.x, std::max(lo, x0), std::min(hi, x1));
    p.y = std::clamp(p.y, y0, y1);
    if (p != curve.points[k]) {
      curve.points[k] = p;
      edit.changed = true;
    }
  }
  if (dragging >= 0 && ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    dragging = -1;
    edit.finished = true;
  }
  if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left) && near < 0) {
    glm::dvec2 p = to_curve(mouse);
    p.x = std::clamp(p.x, x0, x1);
    auto it = std::lower_bound(curve.points.begin(), curve.points.end(), p.x,
                               [](const glm::dvec2& q, double x) { return q.x < x; });
    const bool clash = (it != curve.points.end() && it->x - p.x < kMinGap) ||
                       (it != curve.points.begin() && p.x - (it - 1)->x < kMinGap);
    if (!clash) {
      curve.points.insert(it, p);
      edit.changed = edit.finished = true;
    }
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && near >= 0 && curve.points.size() > 2) {
    curve.points.erase(curve.points.begin() + near);
    edit.changed = edit.finished = true;
    near = -1;
  }
  storage->SetInt(drag_key, dragging);

  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(a, b, IM_COL32(24, 26, 30, 255), 4.0f);
  for (int k = 1; k < 4; ++k) {
    const float gx = a.x + pad + (width - 2 * pad) * k / 4.0f, gy = a.y + pad + (height - 2 * pad) * k / 4.0f;
    dl->AddLine({gx, a.y + pad}, {gx, b.y - pad}, IM_COL32(50, 54, 60, 255));
    dl->AddLine({a.x + pad, gy}, {b.x - pad, gy}, IM_COL32(50, 54, 60, 255));
  }
  dl->AddLine(to_screen({x0, y0}), to_screen({x1, y1}), IM_COL32(70, 74, 82, 255));  // identity reference
  if (!curve.points.empty()) {
    const int n = 96;
    for (int k = 0; k <= n; ++k) {
      const double x = x0 + (x1 - x0) * k / n;
      dl->PathLineTo(to_screen({x, curve.evaluate(x)}));
    }
    dl->PathStroke(IM_COL32(255, 190, 90, 255), 0, 2.0f);
  }
  for (int k = 0; k < static_cast<int>(curve.points.size()); ++k) {
    const ImVec2 s = to_screen(curve.points[static_cast<std::size_t>(k)]);
    const bool hot = k == near || k == dragging;
    dl->AddRectFilled({s.x - kHandle, s.y - kHandle}, {s.x + kHandle, s.y + kHandle},
                      hot ? IM_COL32(255, 255, 255, 255) : IM_COL32(220, 220, 220, 200), 2.0f);
  }
  if (hovered && dragging < 0) {
    ImGui::BeginTooltip();
    if (near >= 0) {
      const auto& p = curve.points[static_cast<std::size_t>(near)];
      ImGui::Text("(%.3f, %.3f)  drag to move, right-click to remove", p.x, p.y);
    } else {
      ImGui::TextUnformatted("Double-click to add a point");
    }
    ImGui::EndTooltip();
  }
  ImGui::PopID();
  return edit;
}

WidgetEdit gradient_editor(const char* id, GradientValue& gradient, float width) {
  WidgetEdit edit;
  ImGui::PushID(id);
  ImGuiStorage* storage = ImGui::GetStateStorage();
  const ImGuiID drag_key = ImGui::GetID("drag"), sel_key = ImGui::GetID("selected");
  int dragging = storage->GetInt(drag_key, -1);
  int selected = std::clamp(storage->GetInt(sel_key, 0), 0, std::max(0, static_cast<int>(gradient.stops.size()) - 1));

  const float bar_h = 22.0f, marker_h = 12.0f;
  const ImVec2 a = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##bar", {width, bar_h + marker_h},
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  auto x_of = [&](double t) { return a.x + static_cast<float>(std::clamp(t, 0.0, 1.0)) * width; };
  auto t_of = [&](float x) { return std::clamp(static_cast<double>((x - a.x) / width), 0.0, 1.0); };

  int near = -1;
  for (int k = 0; k < static_cast<int>(gradient.stops.size()); ++k)
    if (std::abs(x_of(gradient.stops[static_cast<std::size_t>(k)].position) - mouse.x) <= 6.0f &&
        mouse.y >= a.y + bar_h - 2.0f)
      near = k;

  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left) && near >= 0) dragging = selected = near;
  if (dragging >= 0 && dragging < static_cast<int>(gradient.stops.size()) &&
      ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    const double t = t_of(mouse.x);
    auto& stop = gradient.stops[static_cast<std::size_t>(dragging)];
    if (t != stop.position) {
      stop.position = t;
      // Keep the stops sorted, following the dragged one.
      const auto moved = stop;
      std::stable_sort(gradient.stops.begin(), gradient.stops.end(),
                       [](const auto& l, const auto& r) { return l.position < r.position; });
      for (int k = 0; k < static_cast<int>(gradient.stops.size()); ++k)
        if (gradient.stops[static_cast<std::size_t>(k)] == moved) dragging = selected = k;
      edit.changed = true;
    }
  }
  if (dragging >= 0 && ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    dragging = -1;
    edit.finished = true;
  }
  if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left) && near < 0) {
    const double t = t_of(mouse.x);
    GradientValue::Stop stop{t, gradient.stops.empty() ? glm::vec4(1.0f) : gradient.evaluate(t)};
    auto it = std::upper_bound(gradient.stops.begin(), gradient.stops.end(), t,
                               [](double v, const auto& s) { return v < s.position; });
    selected = static_cast<int>(it - gradient.stops.begin());
    gradient.stops.insert(it, stop);
    edit.changed = edit.finished = true;
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && near >= 0 && gradient.stops.size() > 1) {
    gradient.stops.erase(gradient.stops.begin() + near);
    selected = std::min(selected, static_cast<int>(gradient.stops.size()) - 1);
    edit.changed = edit.finished = true;
  }

  ImDrawList* dl = ImGui::GetWindowDrawList();
  // Checkerboard under the bar shows alpha.
  for (float x = a.x; x < a.x + width; x += 8.0f)
    for (int r = 0; r < 3; ++r)
      if ((static_cast<int>((x - a.x) / 8.0f) + r) % 2)
        dl->AddRectFilled({x, a.y + r * 8.0f},
                          {std::min(x + 8.0f, a.x + width), std::min(a.y + (r + 1) * 8.0f, a.y + bar_h)},
                          IM_COL32(90, 90, 90, 255));
  const int steps = std::max(8, static_cast<int>(width / 3.0f));
  for (int k = 0; k < steps; ++k) {
    const float xa = a.x + width * k / steps, xb = a.x + width * (k + 1) / steps;
    dl->AddRectFilled({xa, a.y}, {xb + 0.5f, a.y + bar_h}, to_u32(gradient.evaluate((k + 0.5) / steps)));
  }
  dl->AddRect(a, {a.x + width, a.y + bar_h}, IM_COL32(20, 20, 20, 255));
  for (int k = 0; k < static_cast<int>(gradient.stops.size()); ++k) {
    const auto& s = gradient.stops[static_cast<std::size_t>(k)];
    const float x = x_of(s.position), y = a.y + bar_h;
    const ImU32 outline = k == selected ? IM_COL32(255, 190, 90, 255) : IM_COL32(220, 220, 220, 255);
    dl->AddTriangleFilled({x, y}, {x - 6, y + marker_h}, {x + 6, y + marker_h}, to_u32(s.color));
    dl->AddTriangle({x, y}, {x - 6, y + marker_h}, {x + 6, y + marker_h}, outline, k == selected ? 2.0f : 1.0f);
  }
  if (hovered && dragging < 0) {
    ImGui::BeginTooltip();
    ImGui::TextUnformatted(near >= 0 ? "Drag to move, click to edit, right-click to remove"
                                     : "Double-click to add a stop");
    ImGui::EndTooltip();
  }

  // The selected stop's colour and position.
  if (selected >= 0 && selected < static_cast<int>(gradient.stops.size())) {
    auto& s = gradient.stops[static_cast<std::size_t>(selected)];
    float c[4] = {s.color.r, s.color.g, s.color.b, s.color.a};
    // The stop's colour as a swatch (click for the picker) and its position.
    if (ImGui::ColorEdit4(
            "##stop", c,
            ImGuiColorEditFlags_Float | ImGuiColorEditFlags_AlphaPreviewHalf | ImGuiColorEditFlags_NoInputs)) {
      s.color = {c[0], c[1], c[2], c[3]};
      edit.changed = true;
    }
    if (ImGui::IsItemDeactivatedAfterEdit()) edit.finished = true;
    ImGui::SameLine();
    ImGui::TextDisabled("stop %d of %zu at", selected + 1, gradient.stops.size());
    ImGui::SameLine();
    ImGui::SetNextItemWidth(std::max(60.0f, ImGui::GetContentRegionAvail().x));
    double pos = s.position;
    const double lo = 0.0, hi = 1.0;
    if (ImGui::DragScalar("##pos", ImGuiDataType_Double, &pos, 0.002f, &lo, &hi, "%.3f")) {
      s.position = pos;
      const auto moved = s;
      std::stable_sort(gradient.stops.begin(), gradient.stops.end(),
                       [](const auto& l, const auto& r) { return l.position < r.position; });
      for (int k = 0; k < static_cast<int>(gradient.stops.size()); ++k)
        if (gradient.stops[static_cast<std::size_t>(k)] == moved) selected = k;
      edit.changed = true;
    }
    if (ImGui::IsItemDeactivatedAfterEdit()) edit.finished = true;
  }
  storage->SetInt(drag_key, dragging);
  storage->SetInt(sel_key, selected);
  ImGui::PopID();
  return edit;
}

}  // namespace orogen::editor
