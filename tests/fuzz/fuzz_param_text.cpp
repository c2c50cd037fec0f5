// libFuzzer target: every parameter text grammar a user types or a graph file carries, through
// param_from_text (the --set and editor syntax) and param_from_json, for every parameter of every node
// type (curves, gradients, vectors, colours, enums, paths, seeds, tables ...). The first byte picks the
// parameter (the first two bytes, little-endian). Values that are accepted are then evaluated where they are functions
// (curves, gradients), and tables must read back from their own JSON unchanged. The text also goes, as the version-4
// string of the chosen node type's mini-language, through the version-5 migration (graph/table_migration.h), whose
// tables must then pass or fail the loader's checks without crashing.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/registry.h"
#include "graph/table_json.h"
#include "graph/table_migration.h"

namespace {

struct Param {
  const orogen::NodeType* type;
  const orogen::ParamDecl* decl;
};

std::vector<Param> all_params() {
  std::vector<Param> params;
  for (const auto* type : orogen::NodeRegistry::instance().all())
    for (const auto& p : type->params) params.push_back({type, &p});
  return params;
}

// The version-4 parameter that held the type's mini-language, if it had one.
const char* v4_string_param(const std::string& type) {
  if (type == "Biomes") return "custom_table";
  if (type == "BiomeScatter" || type == "ScatterRules") return "table";
  if (type == "SplatWeights") return "layers";
  if (type == "ColorByLayers") return "colors";
  if (type == "Instance") return "names";
  return nullptr;
}

void migrate_as_v4(const orogen::NodeType& type, const std::string& text) {
  const char* param = v4_string_param(type.name);
  if (!param) return;
  nlohmann::json file = {{"format", "orogen-graph"},
                         {"version", 4},
                         {"nodes", {{{"id", "n"}, {"type", type.name}, {"params", {{param, text}}}}}}};
  try {
    orogen::convert_string_tables_v4(file);
  } catch (const std::runtime_error&) {
    return;  // the old parser refused the text, naming the line
  }
  std::string error;
  for (const auto& [name, value] : file["nodes"][0]["params"].items())
    if (const auto* decl = type.find_param(name)) (void)orogen::param_from_json(value, *decl, error);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto params = all_params();
  // Two bytes pick the parameter: there are more than 256.
  if (size < 2 || params.empty()) return 0;
  const Param& chosen = params[(data[0] | (std::size_t{data[1]} << 8)) % params.size()];
  const orogen::ParamDecl& decl = *chosen.decl;
  const std::string text(reinterpret_cast<const char*>(data + 2), size - 2);
  migrate_as_v4(*chosen.type, text);
  std::string error;
  std::vector<orogen::ParamValue> values;
  if (auto v = orogen::param_from_text(text, decl, error)) values.push_back(*v);
  const auto json = nlohmann::json::parse(text, nullptr, false);
  if (!json.is_discarded())
    if (auto v = orogen::param_from_json(json, decl, error)) values.push_back(*v);
  const double probes[] = {-1e300,
                           -1.0,
                           0.0,
                           0.25,
                           0.5,
                           1.0,
                           1e300,
                           std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()};
  for (const auto& v : values) {
    if (!decl.check(v).empty()) continue;
    if (const auto* curve = std::get_if<orogen::CurveValue>(&v))
      for (double x : probes) (void)curve->evaluate(x);
    if (const auto* gradient = std::get_if<orogen::GradientValue>(&v))
      for (double x : probes) (void)gradient->evaluate(x);
    if (const auto* table = std::get_if<orogen::TableValue>(&v)) {
      orogen::TableProblem problem;
      const auto again = orogen::table_from_json(orogen::table_to_json(*table), decl.table, problem);
      if (!again || !(*again == *table)) __builtin_trap();  // a valid table must read back as itself
    }
  }
  return 0;
}
