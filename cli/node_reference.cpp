#include "cli/node_reference.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/registry.h"
#include "graph/subgraph.h"
#include "graph/tile_graph.h"

namespace orogen::cli {
namespace {

// How a unit reads after a value: its symbol ("m", "°C"), or its name when it has none ("unitless").
std::string unit_text(Unit u) {
  if (u == Unit::None) return "";
  return std::string(unit_symbol(u).empty() ? unit_name(u) : unit_symbol(u));
}

void add_unit(nlohmann::json& j, Unit u) {
  if (u == Unit::None) return;
  j["unit"] = unit_id(u);
  j["unit_symbol"] = unit_symbol(u);
  j["unit_name"] = unit_name(u);
}

std::string range_text(const ParamDecl& p) {
  std::ostringstream s;
  if (p.min && p.max)
    s << "[" << *p.min << ", " << *p.max << "]";
  else if (p.min)
    s << ">= " << *p.min;
  else if (p.max)
    s << "<= " << *p.max;
  return s.str();
}

// A table's default is summarized by its row count; `--json` gives the rows.
std::string default_text(const ParamDecl& p) {
  if (p.type == ParamType::Table) return std::to_string(std::get<TableValue>(p.default_value).rows.size()) + " rows";
  return param_to_json(p.default_value).dump();
}

std::string column_range_text(const TableColumn& c) {
  std::ostringstream s;
  if (c.min && c.max)
    s << "[" << *c.min << ", " << *c.max << "]";
  else if (c.min)
    s << ">= " << *c.min;
  else if (c.max)
    s << "<= " << *c.max;
  return s.str();
}

// "slope : range deg [0, 90], optional"
std::string column_summary(const TableColumn& c) {
  std::string s = c.name + " : " + std::string(to_string(c.type));
  // append, not " " + text: GCC 12 inlines that into a false -Wrestrict warning.
  if (c.unit != Unit::None) s.append(" ").append(unit_text(c.unit));
  if (auto r = column_range_text(c); !r.empty()) s.append(" ").append(r);
  if (!c.choices.empty()) {
    s += " (";
    for (std::size_t k = 0; k < c.choices.size(); ++k) s += (k ? ", " : "") + c.choices[k];
    s += ")";
  }
  if (c.open_ends) s += ", open ends (null)";
  if (!c.required) s += ", optional";
  return s;
}

nlohmann::json column_json(const TableColumn& c) {
  nlohmann::json j = {
      {"name", c.name}, {"type", to_string(c.type)}, {"description", c.description}, {"required", c.required}};
  add_unit(j, c.unit);
  if (c.min) j["min"] = *c.min;
  if (c.max) j["max"] = *c.max;
  if (!c.choices.empty()) j["choices"] = c.choices;
  if (c.open_ends) j["open_ends"] = true;
  return j;
}

nlohmann::json port_json(const PortDecl& p) {
  nlohmann::json j = {
      {"name", p.name}, {"label", p.display_label()}, {"type", to_string(p.type)}, {"description", p.description}};
  add_unit(j, p.unit);
  if (p.optional) j["optional"] = true;
  return j;
}

std::vector<ParamValue> defaults(const NodeType& t) {
  std::vector<ParamValue> v;
  for (const auto& p : t.params) v.push_back(p.default_value);
  return v;
}

// The reach with default parameters: "pointwise", "local" or "global" (see graph/node_type.h).
const char* default_reach_kind(const NodeType& t) { return to_string(t.reach_for(defaults(t)).kind); }

// How the node runs across ranks with default parameters, and what that costs (graph/distribution.h).
std::string distribution_text(const NodeType& t) {
  const Distribution d = t.distribution_for(defaults(t));
  std::string s = std::string(to_string(d)) + ": " + describe(d);
  if (t.distribution_fn)
    s.append("; ").append(t.distribution_summary);
  else if (t.reach_fn && t.distribution != Distribution::Undeclared && t.distribution != d)
    s += std::string("; ") + to_string(t.distribution) + " when the parameters make the reach global";
  if (find_tile_graph(t.name)) {
    const std::string when = tile_graph_conditions(t.name);
    s += " (runs across the tiles" + (when.empty() ? std::string() : " " + when) +
         (when.empty() ? std::string(")") : "; otherwise computed on the whole domain by every rank that needs it)");
  } else if (!runs_across_ranks(d)) {
    s += " (for now: computed on the whole domain by every rank that needs it)";
  }
  return s;
}

// Whether the type runs across the ranks with its default parameters.
bool across_ranks_by_default(const NodeType& t) {
  if (find_tile_graph(t.name)) {
    const std::vector<ParamValue> values = defaults(t);
    return tile_graph_for(t.name, ParamView(t, values), Domain{}) != nullptr;
  }
  return runs_across_ranks(t.distribution_for(defaults(t)));
}

nlohmann::json reach_json(const NodeType& t) {
  const Reach r = t.reach_for(defaults(t));
  nlohmann::json j = {
      {"kind", to_string(r.kind)}, {"summary", t.reach_text()}, {"depends_on_params", bool(t.reach_fn)}};
  if (r.kind == ReachKind::Local) {
    j["metres"] = r.metres;
    j["samples"] = r.samples;
  }
  return j;
}

// The ports and parameters of a type (or of a subgraph asset's instances) as JSON.
void interface_json(const NodeType& t, nlohmann::json& inputs, nlohmann::json& outputs, nlohmann::json& params) {
  inputs = nlohmann::json::array();
  outputs = nlohmann::json::array();
  params = nlohmann::json::array();
  for (const auto& p : t.inputs) inputs.push_back(port_json(p));
  for (const auto& p : t.outputs) outputs.push_back(port_json(p));
  for (const auto& p : t.params) {
    nlohmann::json j = {{"name", p.name},
                        {"label", p.display_label()},
                        {"type", to_string(p.type)},
                        {"default", param_to_json(p.default_value)},
                        {"description", p.description}};
    add_unit(j, p.unit);
    if (p.min) j["min"] = *p.min;
    if (p.max) j["max"] = *p.max;
    if (!p.choices.empty()) j["choices"] = p.choices;
    if (p.output_file) j["output_file"] = true;
    if (!p.extensions.empty()) j["extensions"] = p.extensions;
    if (p.type == ParamType::Table) {
      nlohmann::json columns = nlohmann::json::array();
      for (const auto& c : p.table.columns) columns.push_back(column_json(c));
      j["columns"] = std::move(columns);
      j["min_rows"] = p.table.min_rows;
      j["max_rows"] = p.table.max_rows;
    }
    params.push_back(std::move(j));
  }
}

nlohmann::json type_json(const NodeType& t) {
  nlohmann::json inputs, outputs, params;
  interface_json(t, inputs, outputs, params);
  nlohmann::json j = {{"name", t.name},
                      {"category", t.category},
                      {"version", t.version},
                      {"description", t.description},
                      {"inputs", inputs},
                      {"outputs", outputs},
                      {"params", params},
                      {"reach", reach_json(t)},
                      {"distribution",
                       {{"kind", to_string(t.distribution_for(defaults(t)))},
                        {"declared", to_string(t.distribution)},
                        {"across_ranks", across_ranks_by_default(t)},
                        {"summary", distribution_text(t)}}},
                      {"writes_files", t.writes_files},
                      {"domain_independent", t.domain_independent}};
  if (!t.library.empty()) j["library"] = t.library;  // a type from a node library (graph/node_library.h)
  return j;
}

// A subgraph library asset (graph/subgraph.h), used as {"type": "Subgraph", "asset": NAME}: its name, asset
// version, interface and description; no reach, the instance is expanded into its nodes.
nlohmann::json asset_json(const SubgraphAsset& asset) {
  nlohmann::json inputs, outputs, params;
  interface_json(asset.type, inputs, outputs, params);
  return {{"name", asset.name},
          {"category", "subgraph library"},
          {"type", kSubgraphTypeName},
          {"asset", asset.name},
          {"asset_version", asset.interface().asset_version},
          {"description", asset.interface().description},
          {"file", asset.file.generic_string()},
          {"inputs", inputs},
          {"outputs", outputs},
          {"params", params}};
}

// The library's assets that load, by name (one that does not load is left out of the reference; `orogen nodes`
// lists it with its error).
std::vector<const SubgraphAsset*> library_assets() {
  std::vector<const SubgraphAsset*> out;
  for (const auto& entry : list_subgraph_library())
    if (const AssetLoad load = load_subgraph_asset(entry.name, {}); load.asset) out.push_back(load.asset);
  return out;
}

}  // namespace

std::string node_list_text() {
  std::ostringstream s;
  std::string category;
  for (const auto* t : NodeRegistry::instance().all()) {
    if (t->category != category) {
      category = t->category;
      s << category << ":\n";
    }
    const std::string reach = default_reach_kind(*t), ranks = to_string(t->distribution_for(defaults(*t)));
    s << "  " << t->name << std::string(t->name.size() < 22 ? 22 - t->name.size() : 1, ' ') << reach
      << std::string(reach.size() < 11 ? 11 - reach.size() : 1, ' ') << ranks
      << std::string(ranks.size() < 14 ? 14 - ranks.size() : 1, ' ')
      << (t->library.empty() ? "" : "[" + t->library + "] ") << t->description << "\n";
  }
  return s.str();
}

std::string node_reference_text(const NodeType& t) {
  std::ostringstream s;
  s << t.name << " (" << t.category << ", version " << t.version
    << (t.library.empty() ? "" : ", from node library '" + t.library + "'") << ")\n  " << t.description << "\n";
  s << "\nReach: " << t.reach_text() << "\n";
  s << "Distribution: " << distribution_text(t) << "\n";
  auto ports = [&](const char* title, const std::vector<PortDecl>& list) {
    if (list.empty()) return;
    s << "\n" << title << ":\n";
    for (const auto& p : list)
      s << "  " << p.name << " : " << to_string(p.type) << (p.unit != Unit::None ? ", " + unit_text(p.unit) : "")
        << (p.optional ? " (optional)" : "") << "\n      " << p.display_label() << ": " << p.description << "\n";
  };
  ports("Inputs", t.inputs);
  ports("Outputs", t.outputs);
  if (!t.params.empty()) {
    s << "\nParameters:\n";
    for (const auto& p : t.params) {
      s << "  " << p.name << " : " << to_string(p.type) << " = " << default_text(p);
      if (p.unit != Unit::None) s << " " << unit_text(p.unit);
      if (auto r = range_text(p); !r.empty()) s << "  range " << r;
      s << "\n      " << p.display_label() << ": " << p.description << "\n";
      if (!p.choices.empty()) {
        s << "      choices:";
        for (const auto& c : p.choices) s << " " << c;
        s << "\n";
      }
      if (p.type == ParamType::Table) {
        s << "      columns (rows " << p.table.min_rows << ".." << p.table.max_rows << "):\n";
        for (const auto& c : p.table.columns)
          s << "        " << column_summary(c) << "\n          " << c.description << "\n";
      }
    }
  }
  if (t.writes_files) s << "\nWrites files (paths resolve inside the output directory).\n";
  return s.str();
}

std::string node_reference_json(const NodeType* only) {
  if (only && only->subgraph) return asset_json(*only->subgraph).dump(2) + "\n";
  if (only) return type_json(*only).dump(2) + "\n";
  nlohmann::json all = nlohmann::json::array();
  for (const auto* t : NodeRegistry::instance().all()) all.push_back(type_json(*t));
  // The subgraph library after the node types, marked by "type": "Subgraph".
  for (const auto* asset : library_assets()) all.push_back(asset_json(*asset));
  return all.dump(2) + "\n";
}

// The ports and the parameter table of a type (or of a subgraph asset's instances), in Markdown.
static void markdown_interface(std::ostringstream& s, const NodeType& t) {
  auto ports = [&](const char* title, const std::vector<PortDecl>& list) {
    if (list.empty()) return;
    s << "\n" << title << ":\n\n";
    for (const auto& p : list)
      s << "- `" << p.name << "` " << p.display_label() << " (" << to_string(p.type)
        << (p.unit != Unit::None ? ", " + unit_text(p.unit) : "") << (p.optional ? ", optional" : "")
        << "): " << p.description << "\n";
  };
  ports("Inputs", t.inputs);
  ports("Outputs", t.outputs);
  if (!t.params.empty()) {
    s << "\n| parameter | label | type | default | unit | range | description |\n|---|---|---|---|---|---|---|\n";
    for (const auto& p : t.params) {
      std::string desc = p.description;
      if (!p.choices.empty()) {
        desc += " Choices:";
        for (const auto& c : p.choices) desc += " `" + c + "`";
      }
      s << "| `" << p.name << "` | " << p.display_label() << " | " << to_string(p.type) << " | `" << default_text(p)
        << "` | " << unit_text(p.unit) << " | " << range_text(p) << " | " << desc << " |\n";
    }
    for (const auto& p : t.params) {
      if (p.type != ParamType::Table) continue;
      s << "\nColumns of `" << p.name
        << "` (one JSON object per row):\n\n| column | type | unit | range | required | "
           "description |\n|---|---|---|---|---|---|\n";
      for (const auto& c : p.table.columns) {
        std::string desc = c.description;
        if (!c.choices.empty()) {
          desc += " Choices:";
          for (const auto& choice : c.choices) desc += " `" + choice + "`";
        }
        if (c.open_ends) desc += " `null` for an open end.";
        s << "| `" << c.name << "` | " << to_string(c.type) << " | " << unit_text(c.unit) << " | "
          << column_range_text(c) << " | " << (c.required ? "yes" : "no") << " | " << desc << " |\n";
      }
    }
  }
}

std::string node_reference_markdown() {
  std::ostringstream s;
  s << "# Node reference\n\nGenerated by `orogen nodes --markdown` from the node registry; do not edit by hand.\n"
       "\nReach: how far a node's output at one sample depends on its inputs. point-wise: the same sample only; "
       "local: within the given radius (metres plus samples); global: the whole domain (such nodes cannot be "
       "evaluated tile by tile).\n";
  std::string category;
  for (const auto* t : NodeRegistry::instance().all()) {
    if (t->category != category) {
      category = t->category;
      s << "\n## " << category << "\n";
    }
    s << "\n### " << t->name << "\n\n"
      << t->description << "\n\nReach: " << t->reach_text() << ".\n\nDistribution: " << distribution_text(*t) << ".\n";
    if (!t->library.empty()) s << "\nFrom node library `" << t->library << "`.\n";
    markdown_interface(s, *t);
  }
  // The subgraph library after the node types.
  const auto assets = library_assets();
  if (!assets.empty())
    s << "\n## Subgraph library\n\nAssets of `graphs/library/` (and `OROGEN_LIBRARY_PATH`), used as "
         "`{\"type\": \"Subgraph\", \"asset\": \"NAME\", \"asset_version\": N}`; see docs/subgraphs.md.\n";
  for (const auto* asset : assets) {
    s << "\n### " << asset->name << "\n\n"
      << asset->interface().description << "\n\nAsset version " << asset->interface().asset_version << ".\n";
    markdown_interface(s, asset->type);
  }
  return s.str();
}

}  // namespace orogen::cli
