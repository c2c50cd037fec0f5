#include "editor/ui/inspector.h"

#include "editor/model/exposed_params.h"
#include "editor/model/grouping.h"
#include "graph/subgraph.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/model/text_summary.h"
#include "editor/ui/curve_editor.h"
#include "editor/ui/table_editor.h"
#include "editor/ui/theme.h"

namespace orogen::editor {

namespace {

// printf format for a value with its unit ('%' in units escaped).
std::string number_format(const ParamDecl& decl, bool integer) {
  std::string unit;
  for (char c : unit_suffix(decl.unit)) {
    unit += c;
    if (c == '%') unit += '%';
  }
  return std::string(integer ? "%" PRId64 : "%.4g") + (unit.empty() ? "" : " " + unit);
}

// A small circular-arrow button; returns true when clicked.
bool reset_button(const char* id) {
  const float s = ImGui::GetFrameHeight();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const bool clicked = ImGui::InvisibleButton(id, {s, s});
  const ImU32 col = ImGui::IsItemHovered() ? IM_COL32(255, 200, 110, 255) : IM_COL32(170, 175, 185, 255);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 c{p.x + s * 0.5f, p.y + s * 0.5f};
  const float r = s * 0.26f;
  dl->PathArcTo(c, r, 0.9f, 5.6f, 16);
  dl->PathStroke(col, 0, 1.6f);
  const ImVec2 tip{c.x + r * std::cos(0.9f), c.y + r * std::sin(0.9f)};
  dl->AddTriangleFilled({tip.x + 3.5f, tip.y - 1.0f}, {tip.x - 2.5f, tip.y - 2.5f}, {tip.x + 0.5f, tip.y + 4.0f}, col);
  return clicked;
}

void describe_tooltip(const ParamDecl& decl) {
  if (!ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled) || ImGui::IsMouseDown(0)) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 26.0f);
  ImGui::Text("%s", decl.display_label().c_str());
  ImGui::SameLine();
  const std::string unit = decl.unit == Unit::None ? "" : std::string(unit_name(decl.unit));
  ImGui::TextDisabled("(%s, %s%s%s)", decl.name.c_str(), std::string(to_string(decl.type)).c_str(),
                      unit.empty() ? "" : ", ", unit.c_str());
  if (!decl.description.empty()) ImGui::TextUnformatted(decl.description.c_str());
  if (decl.min || decl.max)
    ImGui::TextDisabled("range %s .. %s", decl.min ? describe(ParamValue(*decl.min)).c_str() : "-inf",
                        decl.max ? describe(ParamValue(*decl.max)).c_str() : "inf");
  ImGui::TextDisabled("default %s", describe(decl.default_value).c_str());
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

// Drag speed that feels right for a value of this magnitude and range.
float drag_speed(double value, double lo, double hi) {
  if (std::isfinite(hi - lo) && hi > lo) return static_cast<float>((hi - lo) / 400.0);
  return static_cast<float>(std::max(std::abs(value) * 0.005, 0.001));
}

}  // namespace

void Inspector::apply(Document& document, const Node& node, const ParamDecl& decl, const ParamValue& value,
                      bool gesture) {
  const std::string key = node.id + "." + decl.name;
  try {
    document.set_param(node.id, decl.name, value, gesture);
    if (error_key_ == key) error_.clear();
  } catch (const std::exception& e) {
    error_key_ = key;
    error_ = e.what();
  }
}

void Inspector::draw(Document& document, Selection& selection) {
  if (const auto chosen = file_dialog_.draw(); chosen && document.graph().find(browse_node_)) {
    const Node node = document.graph().at(browse_node_);
    if (const auto* decl = node.type->find_param(browse_param_)) {
      apply(document, node, *decl, chosen->string(), false);
      text_.erase(browse_node_ + "." + browse_param_);
    }
  }
  const Node* node = selection.active().empty() ? nullptr : document.graph().find(selection.active());
  if (!node) {
    draw_graph(document);
    return;
  }
  // A copy: every edit replaces the document's graph, which would leave a reference dangling.
  const Node snapshot = *node;
  draw_node(document, selection, snapshot);
}

void Inspector::draw_node(Document& document, Selection& selection, const Node& node) {
  // Header: editable id, type and category, description, status.
  if (rename_of_ != node.id) {
    rename_of_ = node.id;
    rename_text_ = node.id;
  }
  ImGui::PushStyleColor(ImGuiCol_FrameBg, ImGui::ColorConvertU32ToFloat4(theme::category_color(node.type->category)));
  ImGui::SetNextItemWidth(-1);
  const bool renamed = ImGui::InputText("##id", &rename_text_, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::PopStyleColor();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Node id: edit and press Enter to rename");
  if ((renamed || ImGui::IsItemDeactivatedAfterEdit()) && rename_text_ != node.id) {
    const std::string old_id = node.id;
    try {
      document.rename_node(old_id, rename_text_);
      selection.select_only(rename_text_);
      rename_of_ = rename_text_;
      error_.clear();
      return;  // `node` refers to the old graph
    } catch (const std::exception& e) {
      error_key_ = old_id + ".";
      error_ = e.what();
      rename_text_ = old_id;
    }
  }
  if (const SubgraphAsset* asset = node.type->subgraph) {
    // An instance: which asset, and the ways into it. Its exposed parameters are below like any node's.
    if (!asset->embedded.empty()) {
      ImGui::TextDisabled("subgraph  /  embedded asset #%s  v%d", asset->embedded.c_str(), node.type->version);
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A unique copy saved inside this graph file: editing it changes no other graph");
    } else {
      ImGui::TextDisabled("subgraph  /  asset %s  v%d", asset->name.c_str(), node.type->version);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", asset->file.string().c_str());
    }
    if (ImGui::SmallButton("Enter")) {
      if (enter_) enter_(node.id);
      return;  // another level: `node` is not on the canvas any more
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(asset->embedded.empty()
                            ? "Edit the asset's nodes here (Tab or double-click); every instance follows the edits"
                            : "Edit the embedded copy's nodes here (Tab or double-click); the graph file keeps them");
    if (asset->embedded.empty()) {
      ImGui::SameLine();
      if (ImGui::SmallButton("Open asset")) {
        if (open_asset_) open_asset_(asset->file);
        return;
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Open %s as the document", asset->file.filename().string().c_str());
    }
    // A shared asset (a file, or an embedded copy other instances use too) can become this instance's own.
    bool shared = asset->embedded.empty();
    for (const auto& other : document.graph().nodes())
      if (other.id != node.id && other.type->subgraph && other.type->subgraph->embedded == asset->embedded &&
          !asset->embedded.empty())
        shared = true;
    if (shared) {
      ImGui::SameLine();
      if (ImGui::SmallButton("Make unique")) {
        const std::string id = node.id;
        try {
          if (make_unique_)
            make_unique_(id);
          else
            make_unique_node(document, id);
          error_.clear();
        } catch (const std::exception& e) {
          error_key_ = id + ".";
          error_ = e.what();
        }
        return;  // the node has a new type
      }
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Give this instance its own copy of the asset, saved inside this graph file, so that "
            "editing it changes no other instance or graph");
    }
  } else {
    ImGui::TextDisabled("%s  /  %s  v%d", node.type->category.c_str(), node.type->name.c_str(), node.type->version);
  }
  if (!node.type->library.empty()) ImGui::TextDisabled("from node library %s", node.type->library.c_str());
  // The description in a few lines, so that a long one (a citation, the attributes a node writes) does not
  // push the parameters out of view: "more" shows it whole, hovering shows it in a tooltip.
  bool cut = false;
  if (!node.type->description.empty()) {
    const float width = ImGui::GetContentRegionAvail().x - 6.0f;
    const bool whole = description_open_ == node.type->name;
    const TextSummary summary =
        summarize_text(node.type->description, width, whole ? 0 : kDescriptionLines,
                       [](std::string_view t) { return ImGui::CalcTextSize(t.data(), t.data() + t.size()).x; });
    cut = summary.cut || whole;
    ImGui::BeginGroup();
    for (const auto& line : summary.lines) ImGui::TextUnformatted(line.c_str());
    ImGui::EndGroup();
    if (summary.cut && ImGui::IsItemHovered()) {
      ImGui::BeginTooltip();
      ImGui::PushTextWrapPos(ImGui::GetFontSize() * 32.0f);
      ImGui::TextUnformatted(node.type->description.c_str());
      ImGui::PopTextWrapPos();
      ImGui::EndTooltip();
    }
  }
  const NodeRunState state = evaluation_.node_state(node.id);
  ImGui::TextColored(ImColor(theme::status_color(state.phase)), "%s", std::string(to_string(state.phase)).c_str());
  if (state.milliseconds > 0.0) {
    ImGui::SameLine();
    ImGui::TextDisabled("last computed in %.1f ms", state.milliseconds);
  }
  if (cut) {
    const bool whole = description_open_ == node.type->name;
    const char* label = whole ? "less" : "more";
    ImGui::SameLine(std::max(ImGui::GetCursorPosX() + 8.0f,
                             ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize(label).x - 26.0f));
    if (ImGui::SmallButton(label)) description_open_ = whole ? std::string() : node.type->name;
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(whole ? "Show the description in a few lines" : "Show the whole description");
  }
  if (!state.message.empty()) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + ImGui::GetContentRegionAvail().x - 6.0f);
    ImGui::TextColored(ImColor(theme::kError), "%s", state.message.c_str());
    ImGui::PopTextWrapPos();
  }
  if (error_key_ == node.id + "." && !error_.empty()) ImGui::TextColored(ImColor(theme::kError), "%s", error_.c_str());
  ImGui::Separator();

  if (node.type->params.empty()) {
    ImGui::TextDisabled("This node has no parameters.");
    return;
  }
  if (ImGui::BeginTable("##params", 3, ImGuiTableFlags_SizingStretchProp)) {
    ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthStretch, 0.38f);
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 0.62f);
    ImGui::TableSetupColumn("reset", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFrameHeight());
    for (const auto& decl : node.type->params) {
      if (decl.type == ParamType::Table) continue;  // below, at full width
      ImGui::PushID(decl.name.c_str());
      draw_param(document, node, decl);
      ImGui::PopID();
    }
    ImGui::EndTable();
  }
  for (const auto& decl : node.type->params) {
    if (decl.type != ParamType::Table) continue;
    ImGui::PushID(decl.name.c_str());
    draw_table_param(document, node, decl);
    ImGui::PopID();
  }
}

void Inspector::draw_table_param(Document& document, const Node& node, const ParamDecl& decl) {
  const std::string key = node.id + "." + decl.name;
  const bool is_set = node.params.count(decl.name) != 0 && !(node.params.at(decl.name) == decl.default_value);
  ImGui::Spacing();
  ImGui::AlignTextToFramePadding();
  if (is_set)
    ImGui::TextUnformatted(decl.display_label().c_str());
  else
    ImGui::TextColored(ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled), "%s", decl.display_label().c_str());
  describe_tooltip(decl);
  if (is_set) {
    ImGui::SameLine(ImGui::GetContentRegionAvail().x - ImGui::GetFrameHeight());
    if (reset_button("##reset")) {
      document.reset_param(node.id, decl.name);
      if (error_key_ == key) error_.clear();
      return;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Reset to the default table");
  }
  TableValue v = std::get<TableValue>(document.graph().param(node.id, decl.name));
  const WidgetEdit e = table_editor("##table", decl.table, v, ImGui::GetContentRegionAvail().x);
  if (e.changed) apply(document, node, decl, v, !e.finished);
  if (e.finished) document.end_gesture();
  if (error_key_ == key && !error_.empty()) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + ImGui::GetContentRegionAvail().x - 6.0f);
    ImGui::TextColored(ImColor(theme::kError), "%s", error_.c_str());
    ImGui::PopTextWrapPos();
  }
}

void Inspector::draw_param(Document& document, const Node& node, const ParamDecl& decl) {
  const std::string key = node.id + "." + decl.name;
  const ParamValue value = document.graph().param(node.id, decl.name);
  const bool is_set = node.params.count(decl.name) != 0 && !(node.params.at(decl.name) == decl.default_value);

  ImGui::TableNextRow();
  ImGui::TableSetColumnIndex(0);
  ImGui::AlignTextToFramePadding();
  if (document.graph().interface) {
    // Editing an asset: which inner parameters its instances expose (editor/model/exposed_params.h).
    const std::string as = exposed_as(document.graph(), node.id, decl.name);
    bool on = !as.empty();
    ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, {2, 2});
    if (ImGui::Checkbox("##expose", &on)) {
      try {
        set_exposed(document, node.id, decl.name, on);
        error_.clear();
      } catch (const std::exception& e) {
        error_key_ = key;
        error_ = e.what();
      }
    }
    ImGui::PopStyleVar();
    if (ImGui::IsItemHovered()) {
      if (as.empty())
        ImGui::SetTooltip("Expose on every instance of this asset");
      else
        ImGui::SetTooltip("Exposed on every instance as '%s': uncheck to hide", as.c_str());
    }
    ImGui::SameLine(0, 4);
  }
  if (is_set)
    ImGui::TextUnformatted(decl.display_label().c_str());
  else
    ImGui::TextColored(ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled), "%s", decl.display_label().c_str());
  describe_tooltip(decl);
  ImGui::TableSetColumnIndex(1);
  const float width = ImGui::GetContentRegionAvail().x;
  ImGui::SetNextItemWidth(-FLT_MIN);

  const double hard_lo = decl.min.value_or(-std::numeric_limits<double>::infinity());
  const double hard_hi = decl.max.value_or(std::numeric_limits<double>::infinity());
  const double lo = decl.soft_min.value_or(hard_lo), hi = decl.soft_max.value_or(hard_hi);
  const bool ranged = std::isfinite(lo) && std::isfinite(hi) && hi > lo;

  switch (decl.type) {
    case ParamType::Float: {
      double v = std::get<double>(value);
      bool changed;
      const std::string fmt = number_format(decl, false);
      if (ranged) {
        ImGuiSliderFlags flags = 0;
        if (lo > 0.0 && hi / lo >= 100.0) flags |= ImGuiSliderFlags_Logarithmic;
        changed = ImGui::SliderScalar("##v", ImGuiDataType_Double, &v, &lo, &hi, fmt.c_str(), flags);
      } else {
        changed = ImGui::DragScalar("##v", ImGuiDataType_Double, &v, drag_speed(v, lo, hi),
                                    decl.min ? &hard_lo : nullptr, decl.max ? &hard_hi : nullptr, fmt.c_str());
      }
      describe_tooltip(decl);
      if (changed) apply(document, node, decl, std::clamp(v, hard_lo, hard_hi), true);
      if (ImGui::IsItemDeactivated()) document.end_gesture();
      break;
    }
    case ParamType::Int: {
      std::int64_t v = std::get<std::int64_t>(value);
      const std::int64_t ilo = ranged ? static_cast<std::int64_t>(lo) : std::numeric_limits<std::int64_t>::min() / 2;
      const std::int64_t ihi = ranged ? static_cast<std::int64_t>(hi) : std::numeric_limits<std::int64_t>::max() / 2;
      const std::string fmt = number_format(decl, true);
      bool changed;
      if (ranged && hi - lo <= 1e6)
        changed = ImGui::SliderScalar("##v", ImGuiDataType_S64, &v, &ilo, &ihi, fmt.c_str());
      else
        changed = ImGui::DragScalar("##v", ImGuiDataType_S64, &v, 1.0f, &ilo, &ihi, fmt.c_str());
      describe_tooltip(decl);
      if (changed) {
        v = std::clamp<std::int64_t>(v, static_cast<std::int64_t>(std::max(hard_lo, -9e18)),
                                     static_cast<std::int64_t>(std::min(hard_hi, 9e18)));
        apply(document, node, decl, v, true);
      }
      if (ImGui::IsItemDeactivated()) document.end_gesture();
      break;
    }
    case ParamType::Bool: {
      bool v = std::get<bool>(value);
      if (ImGui::Checkbox("##v", &v)) apply(document, node, decl, v, false);
      describe_tooltip(decl);
      break;
    }
    case ParamType::Vec2:
    case ParamType::Vec3: {
      const int n = decl.type == ParamType::Vec2 ? 2 : 3;
      double v[3] = {0, 0, 0};
      if (n == 2) {
        const auto p = std::get<glm::dvec2>(value);
        v[0] = p.x;
        v[1] = p.y;
      } else {
        const auto p = std::get<glm::dvec3>(value);
        v[0] = p.x;
        v[1] = p.y;
        v[2] = p.z;
      }
      const std::string fmt = number_format(decl, false);
      const float speed = drag_speed(std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}), lo, hi);
      if (ImGui::DragScalarN("##v", ImGuiDataType_Double, v, n, speed, decl.min ? &hard_lo : nullptr,
                             decl.max ? &hard_hi : nullptr, fmt.c_str())) {
        for (double& c : v) c = std::clamp(c, hard_lo, hard_hi);
        if (n == 2)
          apply(document, node, decl, glm::dvec2(v[0], v[1]), true);
        else
          apply(document, node, decl, glm::dvec3(v[0], v[1], v[2]), true);
      }
      describe_tooltip(decl);
      if (ImGui::IsItemDeactivated()) document.end_gesture();
      break;
    }
    case ParamType::Color: {
      const auto c = std::get<glm::vec4>(value);
      float v[4] = {c.r, c.g, c.b, c.a};
      if (ImGui::ColorEdit4("##v", v, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_AlphaPreviewHalf))
        apply(document, node, decl, glm::vec4(v[0], v[1], v[2], v[3]), true);
      describe_tooltip(decl);
      if (ImGui::IsItemDeactivated()) document.end_gesture();
      break;
    }
    case ParamType::Enum: {
      const auto& v = std::get<std::string>(value);
      if (ImGui::BeginCombo("##v", v.c_str())) {
        for (const auto& choice : decl.choices)
          if (ImGui::Selectable(choice.c_str(), choice == v)) apply(document, node, decl, choice, false);
        ImGui::EndCombo();
      }
      describe_tooltip(decl);
      break;
    }
    case ParamType::String:
    case ParamType::Path: {
      auto it = text_.find(key);
      if (it == text_.end()) it = text_.emplace(key, std::get<std::string>(value)).first;
      const bool path = decl.type == ParamType::Path;
      if (path) ImGui::SetNextItemWidth(width - ImGui::GetFrameHeight() - ImGui::GetStyle().ItemSpacing.x);
      ImGui::InputText("##v", &it->second);
      describe_tooltip(decl);
      // Text applies when the field is left (one undo step per edit, not per keystroke).
      if (ImGui::IsItemDeactivatedAfterEdit())
        apply(document, node, decl, it->second, false);
      else if (!ImGui::IsItemActive())
        it->second = std::get<std::string>(value);
      if (path) {
        ImGui::SameLine();
        if (ImGui::Button("...", {ImGui::GetFrameHeight(), 0})) {
          browse_node_ = node.id;
          browse_param_ = decl.name;
          std::filesystem::path start = std::get<std::string>(value);
          if (!start.is_absolute() && document.has_path()) start = document.path().parent_path() / start;
          file_dialog_.show(decl.output_file ? FileDialog::Mode::Save : FileDialog::Mode::Open, decl.name, start,
                            decl.extensions);
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Browse...");
        if (decl.output_file) ImGui::TextDisabled("written inside the build's output folder");
      }
      break;
    }
    case ParamType::Seed: {
      std::uint64_t v = std::get<std::uint64_t>(value);
      ImGui::SetNextItemWidth(width - 70.0f);
      if (ImGui::InputScalar("##v", ImGuiDataType_U64, &v)) apply(document, node, decl, v, false);
      describe_tooltip(decl);
      ImGui::SameLine();
      if (ImGui::Button("Re-roll", {-FLT_MIN, 0})) {
        static std::mt19937_64 rng{std::random_device{}()};
        apply(document, node, decl, std::uint64_t{rng() % 1000000}, false);
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("A new random seed");
      break;
    }
    case ParamType::Curve: {
      CurveValue v = std::get<CurveValue>(value);
      const WidgetEdit e = curve_editor("##curve", v, width);
      if (e.changed) apply(document, node, decl, v, true);
      if (e.finished) document.end_gesture();
      break;
    }
    case ParamType::Gradient: {
      GradientValue v = std::get<GradientValue>(value);
      const WidgetEdit e = gradient_editor("##gradient", v, width);
      if (e.changed) apply(document, node, decl, v, true);
      if (e.finished) document.end_gesture();
      break;
    }
    case ParamType::Table:
      break;  // draw_table_param, at full width
  }
  if (error_key_ == key && !error_.empty()) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + ImGui::GetContentRegionAvail().x - 6.0f);
    ImGui::TextColored(ImColor(theme::kError), "%s", error_.c_str());
    ImGui::PopTextWrapPos();
  }

  ImGui::TableSetColumnIndex(2);
  if (is_set) {
    if (reset_button("##reset")) {
      document.reset_param(node.id, decl.name);
      text_.erase(key);
      if (error_key_ == key) error_.clear();
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Reset to default (%s)", describe(decl.default_value).c_str());
  }
}

void Inspector::draw_graph(Document& document) {
  ImGui::TextUnformatted("Graph");
  ImGui::TextDisabled("%zu nodes. Select a node to edit its parameters.", document.graph().nodes().size());
  ImGui::Separator();
  GraphDomain d = document.graph().domain;
  bool changed = false;
  ImGui::TextUnformatted("Domain: the world rectangle a build covers");
  bool done = false;
  const float half = (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x) * 0.5f;
  // One drag per component: each shows its own axis and unit.
  auto component = [&](const char* id, double& v, float speed, double lo, double hi, const char* fmt, bool same_line) {
    if (same_line) ImGui::SameLine();
    ImGui::SetNextItemWidth(half);
    if (ImGui::DragScalar(id, ImGuiDataType_Double, &v, speed, &lo, &hi, fmt)) changed = true;
    done |= ImGui::IsItemDeactivated();
  };
  component("##ox", d.origin.x, 1.0f, -1e9, 1e9, "origin x %.0f m", false);
  component("##oy", d.origin.y, 1.0f, -1e9, 1e9, "origin y %.0f m", true);
  component("##sx", d.size.x, 4.0f, 1.0, 1e7, "width %.0f m", false);
  component("##sy", d.size.y, 4.0f, 1.0, 1e7, "height %.0f m", true);
  double rx = d.resolution.x, ry = d.resolution.y;
  component("##rx", rx, 4.0f, 2.0, 32768.0, "%.0f samples", false);
  component("##ry", ry, 4.0f, 2.0, 32768.0, "x %.0f samples", true);
  d.resolution = {static_cast<int>(std::lround(rx)), static_cast<int>(std::lround(ry))};
  if (changed)
    document.edit(
        "Change domain", [&](Graph& g) { g.domain = d; }, "domain");
  if (done) document.end_gesture();
  ImGui::TextDisabled("spacing %.3g x %.3g m", d.size.x / std::max(1, d.resolution.x - 1),
                      d.size.y / std::max(1, d.resolution.y - 1));
  ImGui::Separator();
  ImGui::TextUnformatted("Preview");
  int preview = evaluation_.preview_resolution();
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (ImGui::SliderInt("##preview", &preview, 64, 2048, "%d samples on the longer side", ImGuiSliderFlags_Logarithmic))
    evaluation_.set_preview_resolution(preview);
  ImGui::TextDisabled("Same world, fewer samples: the preview matches the build.");
}

}  // namespace orogen::editor
