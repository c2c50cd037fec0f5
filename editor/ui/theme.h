#pragma once
// Colours of the editor: node titles by category, pins and links by value type, node status; and the
// ImGui style.
#include <string_view>

#include <imgui.h>

#include "editor/model/evaluation_controller.h"
#include "graph/value_type.h"

namespace orogen::editor::theme {

ImU32 category_color(std::string_view category);
ImU32 port_color(PortType type);
ImU32 status_color(NodeRunState::Phase phase);
ImU32 with_alpha(ImU32 color, float alpha);

inline constexpr ImU32 kCanvasBackground = IM_COL32(30, 32, 36, 255);
inline constexpr ImU32 kGridMinor = IM_COL32(44, 47, 53, 255);
inline constexpr ImU32 kGridMajor = IM_COL32(58, 62, 70, 255);
inline constexpr ImU32 kNodeBody = IM_COL32(50, 53, 60, 245);
inline constexpr ImU32 kNodeBorder = IM_COL32(20, 21, 24, 255);
inline constexpr ImU32 kNodeSelected = IM_COL32(255, 176, 60, 255);
inline constexpr ImU32 kNodeActive = IM_COL32(255, 214, 120, 255);
inline constexpr ImU32 kText = IM_COL32(230, 232, 236, 255);
inline constexpr ImU32 kTextDim = IM_COL32(160, 165, 175, 255);
inline constexpr ImU32 kError = IM_COL32(240, 90, 80, 255);

// A dark theme with rounded widgets, applied once at start.
void apply_style();

}  // namespace orogen::editor::theme
