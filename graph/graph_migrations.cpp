#include "graph/graph_migrations.h"
#include "graph/table_migration.h"

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

const NodeRenamesV1* renames_for(const json& node) {
  if (!node.is_object() || !node.contains("type") || !node["type"].is_string()) return nullptr;
  const auto type = node["type"].get<std::string>();
  for (const auto& r : format_v1_renames())
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

}  // namespace

void migrate_graph_v1_to_v2(json& file) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  json& nodes = file["nodes"];

  // Output renames by node id, for the links that read them.
  std::map<std::string, const NodeRenamesV1*> by_id;
  for (const json& node : nodes)
    if (const auto* r = renames_for(node); r && node.contains("id") && node["id"].is_string())
      by_id[node["id"].get<std::string>()] = r;

  for (json& node : nodes) {
    if (!node.is_object()) continue;
    if (const auto* r = renames_for(node)) {
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

}  // namespace orogen
