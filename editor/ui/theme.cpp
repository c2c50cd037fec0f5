#include "editor/ui/theme.h"

#include <cmath>
#include <functional>
#include <string>

namespace orogen::editor::theme {

namespace {
ImU32 hsv(float h, float s, float v) {
  float r, g, b;
  ImGui::ColorConvertHSVtoRGB(h, s, v, r, g, b);
  return IM_COL32(static_cast<int>(r * 255), static_cast<int>(g * 255), static_cast<int>(b * 255), 255);
}
}  // namespace

ImU32 category_color(std::string_view category) {
  struct Entry {
    std::string_view name;
    ImU32 color;
  };
  // Families users will recognise at a glance; unknown ones get a stable hue from their name.
  static constexpr Entry kKnown[] = {
      {"noise", IM_COL32(122, 82, 190, 255)},     {"field", IM_COL32(46, 120, 170, 255)},
      {"shape", IM_COL32(40, 150, 150, 255)},     {"erosion", IM_COL32(170, 100, 50, 255)},
      {"hydrology", IM_COL32(40, 110, 200, 255)}, {"island", IM_COL32(60, 150, 90, 255)},
      {"climate", IM_COL32(190, 150, 40, 255)},   {"scatter", IM_COL32(90, 150, 40, 255)},
      {"geometry", IM_COL32(150, 70, 120, 255)},  {"texture", IM_COL32(190, 80, 90, 255)},
      {"io", IM_COL32(95, 100, 110, 255)},
  };
  for (const auto& e : kKnown)
    if (e.name == category) return e.color;
  const auto h = std::hash<std::string_view>{}(category);
  return hsv(static_cast<float>(h % 360) / 360.0f, 0.55f, 0.62f);
}

ImU32 port_color(PortType type) {
  switch (type) {
    case PortType::Heightfield:
      return IM_COL32(120, 200, 120, 255);
    case PortType::Image:
      return IM_COL32(230, 190, 70, 255);
    case PortType::Points:
      return IM_COL32(90, 170, 240, 255);
    case PortType::Curves:
      return IM_COL32(90, 220, 220, 255);
    case PortType::Mesh:
      return IM_COL32(230, 110, 160, 255);
    case PortType::PolygonMap:
      return IM_COL32(190, 130, 240, 255);
    case PortType::Report:
      return IM_COL32(200, 200, 200, 255);
    case PortType::ModuleString:
      return IM_COL32(150, 210, 90, 255);
    case PortType::Scene:
      return IM_COL32(240, 140, 90, 255);
  }
  return IM_COL32(200, 200, 200, 255);
}

ImU32 status_color(NodeRunState::Phase phase) {
  using P = NodeRunState::Phase;
  switch (phase) {
    case P::Computed:
      return IM_COL32(110, 200, 110, 255);
    case P::Cached:
      return IM_COL32(110, 170, 220, 255);
    case P::Computing:
      return IM_COL32(240, 190, 70, 255);
    case P::Failed:
      return kError;
    case P::Skipped:
      return IM_COL32(200, 130, 90, 255);
    case P::Stale:
      return IM_COL32(150, 150, 150, 255);
    case P::Unknown:
      return IM_COL32(110, 110, 110, 255);
  }
  return kTextDim;
}

ImU32 with_alpha(ImU32 color, float alpha) {
  const auto a = static_cast<ImU32>(std::lround(((color >> IM_COL32_A_SHIFT) & 0xFF) * alpha));
  return (color & ~IM_COL32_A_MASK) | (a << IM_COL32_A_SHIFT);
}

void apply_style() {
  ImGui::StyleColorsDark();
  ImGuiStyle& s = ImGui::GetStyle();
  s.WindowRounding = 0.0f;
  s.ChildRounding = 3.0f;
  s.FrameRounding = 3.0f;
  s.GrabRounding = 3.0f;
  s.PopupRounding = 4.0f;
  s.TabRounding = 3.0f;
  s.WindowBorderSize = 0.0f;
  s.FramePadding = {6, 4};
  s.ItemSpacing = {8, 5};
  s.WindowPadding = {8, 8};
  ImVec4* c = s.Colors;
  c[ImGuiCol_WindowBg] = {0.13f, 0.14f, 0.16f, 1.0f};
  c[ImGuiCol_ChildBg] = {0.0f, 0.0f, 0.0f, 0.0f};  // panels show the window background: no overdraw
  c[ImGuiCol_PopupBg] = {0.11f, 0.12f, 0.14f, 0.98f};
  c[ImGuiCol_MenuBarBg] = {0.10f, 0.11f, 0.12f, 1.0f};
  c[ImGuiCol_FrameBg] = {0.20f, 0.22f, 0.25f, 1.0f};
  c[ImGuiCol_FrameBgHovered] = {0.26f, 0.29f, 0.33f, 1.0f};
  c[ImGuiCol_FrameBgActive] = {0.30f, 0.34f, 0.39f, 1.0f};
  c[ImGuiCol_Header] = {0.24f, 0.32f, 0.42f, 1.0f};
  c[ImGuiCol_HeaderHovered] = {0.30f, 0.40f, 0.52f, 1.0f};
  c[ImGuiCol_HeaderActive] = {0.34f, 0.46f, 0.60f, 1.0f};
  c[ImGuiCol_Button] = {0.24f, 0.27f, 0.31f, 1.0f};
  c[ImGuiCol_ButtonHovered] = {0.32f, 0.37f, 0.43f, 1.0f};
  c[ImGuiCol_ButtonActive] = {0.38f, 0.44f, 0.52f, 1.0f};
  c[ImGuiCol_SliderGrab] = {0.95f, 0.66f, 0.25f, 1.0f};
  c[ImGuiCol_SliderGrabActive] = {1.0f, 0.76f, 0.35f, 1.0f};
  c[ImGuiCol_CheckMark] = {0.95f, 0.66f, 0.25f, 1.0f};
  c[ImGuiCol_Tab] = {0.16f, 0.18f, 0.20f, 1.0f};
  c[ImGuiCol_TabActive] = {0.26f, 0.30f, 0.36f, 1.0f};
  c[ImGuiCol_TabHovered] = {0.32f, 0.37f, 0.43f, 1.0f};
  c[ImGuiCol_TitleBgActive] = {0.16f, 0.18f, 0.21f, 1.0f};
  c[ImGuiCol_PlotHistogram] = {0.95f, 0.66f, 0.25f, 1.0f};
  c[ImGuiCol_Separator] = {0.22f, 0.24f, 0.27f, 1.0f};
}

}  // namespace orogen::editor::theme
