#include "editor/ui/table_editor.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/model/table_edit.h"

namespace orogen::editor {
namespace {

// printf format with the column's unit ('%' escaped).
std::string cell_format(const TableColumn& c, bool integer) {
  std::string unit;
  for (char ch : unit_suffix(c.unit)) {
    unit += ch;
    if (ch == '%') unit += '%';
  }
  return std::string(integer ? "%" PRId64 : "%.4g") + (unit.empty() ? "" : " " + unit);
}

float cell_speed(const TableColumn& c, double value) {
  if (c.min && c.max && std::isfinite(*c.max - *c.min) && *c.max > *c.min)
    return static_cast<float>(std::min((*c.max - *c.min) / 400.0, std::max(std::abs(value) * 0.01, 0.01)));
  return static_cast<float>(std::max(std::abs(value) * 0.005, 0.001));
}

void column_tooltip(const TableColumn& c) {
  if (!ImGui::IsItemHovered() || ImGui::IsMouseDown(0)) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 24.0f);
  ImGui::Text("%s", c.name.c_str());
  ImGui::SameLine();
  const std::string unit = c.unit == Unit::None ? "" : std::string(unit_name(c.unit));
  ImGui::TextDisabled("(%s%s%s%s)", std::string(to_string(c.type)).c_str(), unit.empty() ? "" : ", ", unit.c_str(),
                      c.required ? "" : ", optional");
  ImGui::TextUnformatted(c.description.c_str());
  if (c.min || c.max) ImGui::TextDisabled("range %g .. %g", c.min.value_or(-INFINITY), c.max.value_or(INFINITY));
  if (!c.required) ImGui::TextDisabled("right-click a cell to clear it");
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

// One cell's widget; true when `cell` changed this frame. `finished` is set when a drag or text edit ends.
bool cell_widget(const TableColumn& c, TableCell& cell, bool& finished) {
  bool changed = false;
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (std::holds_alternative<std::monostate>(cell)) {
    if (ImGui::Button("+", {-FLT_MIN, 0})) {
      TableColumn required = c;
      required.required = true;
      cell = new_cell(required);
      changed = finished = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: not set; click to set it", c.name.c_str());
    return changed;
  }
  const double lo = c.min.value_or(-std::numeric_limits<double>::infinity());
  const double hi = c.max.value_or(std::numeric_limits<double>::infinity());
  switch (c.type) {
    case ColumnType::Text: {
      auto& s = std::get<std::string>(cell);
      changed = ImGui::InputText("##c", &s);
      break;
    }
    case ColumnType::Enum: {
      auto& s = std::get<std::string>(cell);
      if (ImGui::BeginCombo("##c", s.c_str())) {
        for (const auto& choice : c.choices)
          if (ImGui::Selectable(choice.c_str(), choice == s) && choice != s) {
            s = choice;
            changed = finished = true;
          }
        ImGui::EndCombo();
      }
      break;
    }
    case ColumnType::Number: {
      auto& v = std::get<double>(cell);
      changed = ImGui::DragScalar("##c", ImGuiDataType_Double, &v, cell_speed(c, v), c.min ? &lo : nullptr,
                                  c.max ? &hi : nullptr, cell_format(c, false).c_str());
      if (changed) v = std::clamp(v, lo, hi);
      break;
    }
    case ColumnType::Integer: {
      auto& v = std::get<std::int64_t>(cell);
      const std::int64_t ilo = c.min ? static_cast<std::int64_t>(*c.min) : std::numeric_limits<std::int64_t>::min() / 2;
      const std::int64_t ihi = c.max ? static_cast<std::int64_t>(*c.max) : std::numeric_limits<std::int64_t>::max() / 2;
      changed = ImGui::DragScalar("##c", ImGuiDataType_S64, &v, 0.1f, &ilo, &ihi, cell_format(c, true).c_str());
      if (changed) v = std::clamp(v, ilo, ihi);
      break;
    }
    case ColumnType::Range: {
      auto& r = std::get<glm::dvec2>(cell);
      double v[2] = {r.x, r.y};
      const float speed = cell_speed(
          c, std::max(std::isfinite(v[0]) ? std::abs(v[0]) : 0.0, std::isfinite(v[1]) ? std::abs(v[1]) : 0.0));
      // Open ends (infinite) show as -inf / inf and stay put while dragged.
      changed = ImGui::DragScalarN("##c", ImGuiDataType_Double, v, 2, speed, c.min ? &lo : nullptr,
                                   c.max ? &hi : nullptr, cell_format(c, false).c_str());
      if (changed) {
        const glm::dvec2 before = r;
        if (std::isfinite(r.x)) r.x = std::clamp(v[0], lo, hi);
        if (std::isfinite(r.y)) r.y = std::clamp(v[1], lo, hi);
        // Keep min <= max: the end being dragged pushes the other.
        if (r.x > r.y) {
          if (r.x != before.x)
            r.y = r.x;
          else
            r.x = r.y;
        }
      }
      break;
    }
    case ColumnType::Color: {
      auto& s = std::get<Srgb8>(cell);
      float rgb[3] = {s.r / 255.0f, s.g / 255.0f, s.b / 255.0f};
      if (ImGui::ColorEdit3("##c", rgb, ImGuiColorEditFlags_NoInputs | ImGuiColorEditFlags_DisplayHex)) {
        auto byte = [](float f) { return static_cast<std::uint8_t>(std::lround(std::clamp(f, 0.0f, 1.0f) * 255.0f)); };
        const Srgb8 next{byte(rgb[0]), byte(rgb[1]), byte(rgb[2])};
        changed = !(next == s);
        s = next;
      }
      ImGui::SameLine();
      ImGui::TextUnformatted(s.hex().c_str());
      break;
    }
  }
  if (c.type != ColumnType::Enum && ImGui::IsItemDeactivated()) finished = true;
  if (!c.required && ImGui::BeginPopupContextItem("##clear")) {
    if (ImGui::MenuItem("Clear (no value)")) {
      cell = std::monostate{};
      changed = finished = true;
    }
    ImGui::EndPopup();
  }
  return changed;
}

}  // namespace

WidgetEdit table_editor(const char* id, const TableSchema& schema, TableValue& table, float width) {
  WidgetEdit edit;
  ImGui::PushID(id);
  const int columns = static_cast<int>(schema.columns.size());
  // No scrolling: the table is as tall as its rows, so the next table and the "+ row" button stay visible.
  const ImGuiTableFlags flags =
      ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_Resizable;
  const float controls = 3.0f * ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().ItemSpacing.x;
  if (ImGui::BeginTable("##table", columns + 1, flags, {width, 0.0f})) {
    for (const auto& c : schema.columns) {
      // Ranges and text want more room than single numbers.
      const float weight = c.type == ColumnType::Range ? 1.6f : c.type == ColumnType::Text ? 1.3f : 1.0f;
      ImGui::TableSetupColumn(c.name.c_str(), ImGuiTableColumnFlags_WidthStretch, weight);
    }
    ImGui::TableSetupColumn("##rows", ImGuiTableColumnFlags_WidthFixed, controls);
    ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
    for (int c = 0; c < columns; ++c) {
      ImGui::TableSetColumnIndex(c);
      ImGui::TableHeader(schema.columns[static_cast<std::size_t>(c)].name.c_str());
      column_tooltip(schema.columns[static_cast<std::size_t>(c)]);
    }
    std::optional<TableValue> structural;  // a row added, moved or removed: applied after the loop
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      ImGui::PushID(static_cast<int>(r));
      ImGui::TableNextRow();
      for (int c = 0; c < columns && static_cast<std::size_t>(c) < table.rows[r].size(); ++c) {
        ImGui::TableSetColumnIndex(c);
        ImGui::PushID(c);
        if (cell_widget(schema.columns[static_cast<std::size_t>(c)], table.rows[r][static_cast<std::size_t>(c)],
                        edit.finished))
          edit.changed = true;
        ImGui::PopID();
      }
      ImGui::TableSetColumnIndex(columns);
      const ImVec2 button{ImGui::GetFrameHeight(), 0};
      ImGui::BeginDisabled(r == 0);
      if (ImGui::ArrowButton("##up", ImGuiDir_Up)) structural = move_row(table, r, r - 1);
      ImGui::EndDisabled();
      ImGui::SameLine();
      ImGui::BeginDisabled(r + 1 == table.rows.size());
      if (ImGui::ArrowButton("##down", ImGuiDir_Down)) structural = move_row(table, r, r + 1);
      ImGui::EndDisabled();
      ImGui::SameLine();
      ImGui::BeginDisabled(table.rows.size() <= schema.min_rows);
      if (ImGui::Button("x", button)) structural = remove_row(table, r);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Delete row %zu", r);
      ImGui::EndDisabled();
      ImGui::PopID();
    }
    ImGui::EndTable();
    ImGui::BeginDisabled(table.rows.size() >= schema.max_rows);
    if (ImGui::Button("+ row")) structural = insert_row(schema, table, table.rows.size());
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::TextDisabled("%zu rows", table.rows.size());
    if (structural) {
      table = std::move(*structural);
      edit.changed = edit.finished = true;
    }
  }
  ImGui::PopID();
  return edit;
}

}  // namespace orogen::editor
