#include "graph/graph_migrations.h"

#include "graph/angles.h"
#include "graph/calendar.h"
#include "graph/table_migration.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

namespace orogen {

const std::vector<NodeRenamesV1>& format_v1_renames() {
  static const std::vector<NodeRenamesV1> table = {
      {"Slope", {{"height", "in"}}, {{"slope", "out"}}, {}, {}},
      {"Aspect", {{"height", "in"}}, {{"aspect", "out"}}, {}, {}},
      {"Curvature", {{"height", "in"}}, {{"curvature", "out"}}, {}, {}},
      {"Normals", {{"height", "in"}}, {{"normals", "out"}}, {}, {}},
      {"BandMask", {}, {{"mask", "out"}}, {}, {}},
      {"ColorRamp", {}, {{"image", "out"}}, {}, {}},
      {"RadialFalloff", {}, {{"mask", "out"}}, {{"centre", "center"}}, {}},
      {"Cone", {}, {{"height", "out"}}, {{"centre", "center"}}, {}},
      {"ReadHeightfield", {}, {{"height", "out"}}, {}, {}},
      {"HeightfieldToMesh", {{"height", "in"}}, {{"mesh", "out"}}, {}, {}},
      {"WriteHeightfield", {{"height", "in"}}, {}, {}, {}},
      {"WriteImage", {{"image", "in"}}, {}, {}, {}},
      {"WriteMesh", {{"mesh", "in"}}, {}, {}, {}},
      {"WritePoints", {{"points", "in"}}, {}, {}, {}},
  };
  return table;
}

namespace {

using nlohmann::json;

const NodeRenamesV1* renames_for(const json& node, const std::vector<NodeRenamesV1>& table) {
  if (!node.is_object() || !node.contains("type") || !node["type"].is_string()) return nullptr;
  const auto type = node["type"].get<std::string>();
  for (const auto& r : table)
    if (r.type == type) return &r;
  return nullptr;
}

// Renames the key `from` of `object` to `to`, unless `to` is already there (the loader then reports the
// old name as unknown rather than silently dropping a value).
void rename_key(json& object, const std::string& from, const std::string& to) {
  if (!object.is_object() || !object.contains(from) || object.contains(to)) return;
  object[to] = std::move(object[from]);
  object.erase(from);
}

// Applies one version's renames: input port names in "inputs", output port names in every link that reads a
// renamed output, parameter names and enum values in "params".
void apply_renames(json& file, const std::vector<NodeRenamesV1>& table) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  json& nodes = file["nodes"];

  // Output renames by node id, for the links that read them.
  std::map<std::string, const NodeRenamesV1*> by_id;
  for (const json& node : nodes)
    if (const auto* r = renames_for(node, table); r && node.contains("id") && node["id"].is_string())
      by_id[node["id"].get<std::string>()] = r;

  for (json& node : nodes) {
    if (!node.is_object()) continue;
    if (const auto* r = renames_for(node, table)) {
      if (node.contains("inputs"))
        for (const auto& [from, to] : r->inputs) rename_key(node["inputs"], from, to);
      if (node.contains("params")) {
        json& params = node["params"];
        for (const auto& [from, to] : r->params) rename_key(params, from, to);
        for (const auto& e : r->enum_values)
          if (params.is_object() && params.contains(e.param) && params[e.param] == e.from) params[e.param] = e.to;
      }
    }
    if (!node.contains("inputs") || !node["inputs"].is_object()) continue;
    for (auto& [port, link] : node["inputs"].items()) {
      if (!link.is_string()) continue;
      const auto text = link.get<std::string>();
      const auto dot = text.find('.');
      if (dot == std::string::npos) continue;
      const auto source = by_id.find(text.substr(0, dot));
      if (source == by_id.end()) continue;
      const auto output = text.substr(dot + 1);
      for (const auto& [from, to] : source->second->outputs)
        if (output == from) link = text.substr(0, dot + 1) + to;
    }
  }
}

}  // namespace

void migrate_graph_v1_to_v2(json& file) { apply_renames(file, format_v1_renames()); }

const std::vector<ChangedDefault>& format_v2_changed_defaults() {
  static const std::vector<ChangedDefault> table = {
      {"ReadHeightfield", "size", "[1024, 1024]"},
  };
  return table;
}

void migrate_graph_v2_to_v3(json& file) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  for (json& node : file["nodes"]) {
    if (!node.is_object() || !node.contains("type") || !node["type"].is_string()) continue;
    const auto type = node["type"].get<std::string>();
    for (const auto& c : format_v2_changed_defaults()) {
      if (c.type != type) continue;
      if (!node.contains("params")) node["params"] = json::object();
      json& params = node["params"];
      if (params.is_object() && !params.contains(c.param)) params[c.param] = json::parse(c.old_default);
    }
  }
}

void migrate_graph_v3_to_v4(json& file) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  json& nodes = file["nodes"];
  std::set<std::string> ids;
  for (const json& node : nodes)
    if (node.is_object() && node.contains("id") && node["id"].is_string()) ids.insert(node["id"].get<std::string>());
  json inserted = json::array();
  std::vector<std::pair<std::string, std::string>> placed;  // (writer, instance) for the editor positions
  for (json& node : nodes) {
    if (!node.is_object() || !node.contains("type") || node["type"] != "WriteScene") continue;
    if (!node.contains("id") || !node["id"].is_string()) continue;
    const std::string writer = node["id"].get<std::string>();
    // Whatever feeds the instances: the old `in` (points) and the class meshes.
    json instance_inputs = json::object();
    if (node.contains("inputs") && node["inputs"].is_object()) {
      json& inputs = node["inputs"];
      for (auto it = inputs.begin(); it != inputs.end();) {
        if (it.key() == "in" || it.key().rfind("mesh_", 0) == 0) {
          instance_inputs[it.key()] = it.value();
          it = inputs.erase(it);
        } else {
          ++it;
        }
      }
    }
    bool proxies = true;
    if (node.contains("params") && node["params"].is_object() && node["params"].contains("proxies")) {
      const json& p = node["params"]["proxies"];
      if (p.is_boolean()) proxies = p.get<bool>();
      node["params"].erase("proxies");
    }
    if (instance_inputs.empty()) continue;  // nothing was connected: the loader reports the missing scene
    std::string id = writer + "_instance";
    for (int k = 2; ids.count(id); ++k) id = writer + "_instance_" + std::to_string(k);
    ids.insert(id);
    node["inputs"]["in"] = id + ".out";
    inserted.push_back({{"id", id},
                        {"type", "Instance"},
                        {"inputs", instance_inputs},
                        {"params", {{"missing_mesh", proxies ? "proxy" : "skip"}}}});
    placed.emplace_back(writer, id);
  }
  for (json& node : inserted) nodes.push_back(std::move(node));
  if (!file.contains("editor") || !file["editor"].is_object()) return;
  json& editor = file["editor"];
  if (!editor.contains("positions") || !editor["positions"].is_object()) return;
  json& positions = editor["positions"];
  for (const auto& [writer, id] : placed) {
    if (!positions.contains(writer)) continue;
    const json& at = positions[writer];
    if (!at.is_array() || at.size() != 2 || !at[0].is_number() || !at[1].is_number()) continue;
    // Between the writer and its inputs: the writer moves right to make room.
    positions[id] = at;
    positions[writer] = json::array({at[0].get<double>() + 230.0, at[1].get<double>()});
  }
}

void migrate_graph_v4_to_v5(json& file) { convert_string_tables_v4(file); }

const std::vector<NodeRenamesV1>& format_v5_renames() {
  static const std::vector<NodeRenamesV1> table = {
      {"FlowAccumulation", {{"rainfall", "rainfall_weight"}}, {}, {{"min_slope", "min_gradient"}}, {}},
      {"RiverExtract", {{"rainfall", "rainfall_weight"}}, {{"mask", "river_mask"}}, {}, {}},
      {"PipeErosion",
       {{"rainfall", "rainfall_rate"}, {"temperature", "evaporation_factor"}},
       {{"water", "water_depth"}},
       {{"rain_rate", "rainfall_rate"}},
       {}},
      {"SoilHumidity",
       {{"water", "water_depth"}},
       {},
       {{"water_threshold", "saturation_depth"}, {"intensity", "rainfall_rate"}},
       {}},
      {"FillDepressions", {}, {{"depth", "water_depth"}}, {}, {}},
      {"Lakes", {}, {{"depth", "water_depth"}}, {}, {}},
      {"FloodFill", {}, {{"depth", "water_depth"}, {"mask", "lake_mask"}}, {{"seed", "position"}}, {}},
      {"CarveRivers", {}, {{"mask", "river_mask"}}, {}, {}},
      {"PolygonMapRaster",
       {},
       {{"water", "water_mask"}, {"ocean", "ocean_mask"}, {"lake", "lake_mask"}, {"river", "river_mask"}},
       {},
       {}},
      {"Hillshade", {}, {{"image", "color"}}, {{"azimuth", "sun_azimuth"}, {"altitude", "sun_elevation"}}, {}},
      {"FlowDirection", {}, {{"slope", "gradient"}}, {}, {}},
      {"Normals", {}, {}, {{"height_scale", "z_factor"}}, {}},
      {"SunIllumination", {}, {}, {{"month", "day_of_year"}}, {}},
      {"HydraulicErosion", {}, {}, {{"min_slope", "min_gradient"}}, {}},
      {"RiverNetwork", {}, {}, {{"base_slope", "base_gradient"}, {"slope_weight", "gradient_weight"}}, {}},
      {"ForestLifeCycle",
       {},
       {},
       {{"seed_distance", "dispersal_distance"}, {"seed_probability", "dispersal_probability"}},
       {}},
  };
  return table;
}

const std::vector<ConvertedParam>& format_v5_converted_params() {
  static const std::vector<ConvertedParam> table = {
      {"SunIllumination", "day_of_year", "month 1..12 -> the 15th of that month (calendar::mid_month_day)"},
      {"Turtle3D", "tropism_strength", "radians -> degrees (degrees_for_radians: converts back exactly)"},
  };
  return table;
}

void migrate_graph_v5_to_v6(json& file) {
  apply_renames(file, format_v5_renames());
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  for (json& node : file["nodes"]) {
    if (!node.is_object() || !node.contains("type") || !node.contains("params") || !node["params"].is_object())
      continue;
    json& params = node["params"];
    if (node["type"] == "SunIllumination" && params.contains("day_of_year") && params["day_of_year"].is_number()) {
      // Any number the loader read as a month (6 or 6.0); one out of 1..12 was refused and still is: it becomes
      // day 0, out of the new range 1..366.
      const double month = params["day_of_year"].get<double>();
      const bool valid = month >= 1.0 && month <= 12.0 && month == std::floor(month);
      params["day_of_year"] = valid ? calendar::mid_month_day(static_cast<int>(month)) : 0;
    }
    if (node["type"] == "Turtle3D" && params.contains("tropism_strength") && params["tropism_strength"].is_number() &&
        params["tropism_strength"] != 0)
      params["tropism_strength"] = degrees_for_radians(params["tropism_strength"].get<double>());
  }
}

void migrate_graph_v6_to_v7(json& file) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  for (json& node : file["nodes"]) {
    if (!node.is_object() || node.value("type", json()) != "WriteMesh") continue;
    if (!node.contains("params")) node["params"] = json::object();
    json& params = node["params"];
    if (!params.is_object() || params.contains("up_axis")) continue;
    // The default path was terrain.obj; a path that is not a string is left for the loader to report.
    const json path = params.value("path", json("terrain.obj"));
    if (!path.is_string()) continue;
    std::string extension = std::filesystem::path(path.get<std::string>()).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".obj") params["up_axis"] = "Z";
  }
}

}  // namespace orogen
