// The version-4 string mini-languages, parsed as their nodes parsed them, written out as table rows.
#include "graph/table_migration.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graph/table_value.h"
// Header-only, like nodes/common/hex_color.h in table_value.cpp: the shared core links nothing into graph/.
#include "nodes/common/text.h"

namespace orogen {
namespace {

using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// Version 4's ScatterRules default (Ekman et al. 2016, Table 1, slopes as rise over run).
const char* const kV4DefaultEcosystemTable =
    "highland  | elevation 70 260 2  | relative -1 5 1   | slope 0 1.4 2    | plant 0 0.008 0.8 2.0 | plant 4 0.001 "
    "0.8 1.3\n"
    "marshland | elevation -10 50 2  | relative -5 0 1   | slope -0.4 0.6 2 | plant 1 0.008 1.2 2.0 | plant 5 0.005 "
    "1.5 2.5\n"
    "plains    | elevation -50 350 2 | relative 0.7 3 1  | slope -0.4 1.6 2 | plant 2 0.008 0.6 1.1 | plant 6 0.004 "
    "0.3 0.8\n"
    "slope     | elevation -50 350 2 | relative 0 10 1   | slope 1.4 2.4 2  | plant 4 0.001 0.6 1.8\n"
    "scarp     | elevation -50 350 2 | relative -10 10 1 | slope 2.8 8.4 8  | plant 4 0.001 0.6 1.8 | plant 7 0.001 "
    "0.9 1.0\n";

// "#rrggbb" in lowercase, as the table writes it; throws for anything else.
std::string hex_color(const std::string& text, const std::string& where) {
  const auto c = parse_srgb8(text);
  if (!c) throw std::runtime_error(where + "'" + text + "' is not a #rrggbb color");
  return c->hex();
}

// A range bound as a table cell: an infinite end is null (open) where it may be.
json bound(double v, bool is_min, const std::string& where) {
  if (!std::isinf(v)) return v;
  if ((v < 0) != is_min) throw std::runtime_error(where + "an open end must be -inf for a minimum, inf for a maximum");
  return nullptr;
}

// ScatterRules' and BiomeScatter's lines: split at '\n' and ';', '#' comments removed, blank lines dropped.
std::vector<std::string> rule_lines(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  bool comment = false;
  for (char c : text) {
    if (c == '\n' || c == ';') {
      if (!trim(cur).empty()) out.push_back(trim(cur));
      cur.clear();
      comment = false;
    } else if (c == '#') {
      comment = true;
    } else if (!comment) {
      cur += c;
    }
  }
  if (!trim(cur).empty()) out.push_back(trim(cur));
  return out;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

std::vector<double> numbers(std::istringstream& in, int count, const std::string& where) {
  std::vector<double> v;
  for (int i = 0; i < count; ++i) {
    double x;
    if (!(in >> x) || !std::isfinite(x))
      throw std::runtime_error(where + ": expected " + std::to_string(count) + " numbers");
    v.push_back(x);
  }
  std::string extra;
  if (in >> extra) throw std::runtime_error(where + ": unexpected '" + extra + "'");
  return v;
}

// Biomes.custom_table: "name, t_min, t_max, m_min, m_max, #rrggbb" per line.
json biome_rectangles(const std::string& text) {
  json rows = json::array();
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    std::vector<std::string> f;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) f.push_back(trim(cell));
    const std::string where = "line " + std::to_string(number) + ": ";
    if (f.size() != 6) throw std::runtime_error(where + "expected 'name, t_min, t_max, m_min, m_max, #rrggbb'");
    if (f[0].empty()) throw std::runtime_error(where + "empty name");
    double v[4];
    for (int k = 0; k < 4; ++k) {
      const std::string& t = f[static_cast<std::size_t>(k + 1)];
      char* end = nullptr;
      v[k] = std::strtod(t.c_str(), &end);
      if (t.empty() || *end != '\0' || std::isnan(v[k]))
        throw std::runtime_error(where + "'" + t + "' is not a number");
    }
    rows.push_back({{"name", f[0]},
                    {"temperature", json::array({bound(v[0], true, where), bound(v[1], false, where)})},
                    {"moisture", json::array({bound(v[2], true, where), bound(v[3], false, where)})},
                    {"color", hex_color(f[5], where)}});
  }
  return rows;
}

// BiomeScatter.table: "BIOME DENSITY | CLASS WEIGHT | ..." per line. A biome listed again replaces the
// earlier line (the node used the last), so only the last line of each id is kept.
void biome_densities(const std::string& text, json& biomes, json& species) {
  struct Line {
    std::int64_t biome;
    double density;
    std::vector<std::pair<std::int64_t, double>> species;
  };
  std::vector<Line> lines;
  int line_no = 0;
  for (const auto& line : rule_lines(text)) {
    ++line_no;
    const auto fields = split(line, '|');
    const std::string where = "biome line " + std::to_string(line_no);
    std::istringstream head(fields[0]);
    const auto v = numbers(head, 2, where);
    if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 1e6)
      throw std::runtime_error(where + ": biome id must be an integer");
    Line l{static_cast<std::int64_t>(v[0]), v[1], {}};
    for (std::size_t f = 1; f < fields.size(); ++f) {
      std::istringstream in(fields[f]);
      const auto s = numbers(in, 2, where);
      if (s[0] != std::floor(s[0]) || s[0] < 0 || s[0] > 1e6)
        throw std::runtime_error(where + ": class must be an integer in [0, 1e6]");
      l.species.emplace_back(static_cast<std::int64_t>(s[0]), s[1]);
    }
    std::erase_if(lines, [&](const Line& earlier) { return earlier.biome == l.biome; });
    lines.push_back(std::move(l));
  }
  if (lines.empty()) throw std::runtime_error("the biome table is empty");
  biomes = json::array();
  species = json::array();
  for (const auto& l : lines) {
    biomes.push_back({{"biome", l.biome}, {"density", l.density}});
    for (const auto& [cls, weight] : l.species)
      species.push_back({{"biome", l.biome}, {"class", cls}, {"weight", weight}});
  }
}

// ScatterRules.table: "NAME | elevation MIN MAX SHARPNESS | ... | plant CLASS DENSITY SMIN SMAX" per line.
// Slopes become degrees. Ecosystems that shared a name get " (2)", " (3)", ... so plants still find theirs.
void ecosystem_tables(const std::string& text, json& ecosystems, json& plants) {
  ecosystems = json::array();
  plants = json::array();
  std::set<std::string> names;
  int line_no = 0;
  for (const auto& line : rule_lines(text)) {
    ++line_no;
    const auto fields = split(line, '|');
    std::string name = fields[0];
    const std::string where = "ecosystem " + std::to_string(line_no) + " ('" + name + "')";
    if (name.empty()) throw std::runtime_error(where + ": no name");
    for (int k = 2; names.count(name); ++k) name = fields[0] + " (" + std::to_string(k) + ")";
    names.insert(name);
    json row = {{"name", name}};
    json row_plants = json::array();
    for (std::size_t f = 1; f < fields.size(); ++f) {
      std::istringstream in(fields[f]);
      std::string key;
      in >> key;
      const std::string w = where + ", '" + key + "'";
      if (key == "elevation" || key == "relative" || key == "slope" || key == "skew") {
        auto v = numbers(in, 3, w);
        if (v[1] < v[0]) throw std::runtime_error(w + ": max below min");
        if (v[2] <= 0.0) throw std::runtime_error(w + ": sharpness must be > 0");
        if (key == "slope")
          for (int k = 0; k < 2; ++k)
            v[static_cast<std::size_t>(k)] = std::atan(v[static_cast<std::size_t>(k)]) * (180.0 / kPi);
        row[key] = json::array({v[0], v[1]});
        row[key + "_sharpness"] = v[2];
      } else if (key == "plant") {
        const auto v = numbers(in, 4, w);
        if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e6)
          throw std::runtime_error(w + ": class must be an integer in [0, 1e6]");
        row_plants.push_back({{"ecosystem", name},
                              {"class", static_cast<std::int64_t>(v[0])},
                              {"density", v[1]},
                              {"scale", json::array({v[2], v[3]})}});
      } else {
        throw std::runtime_error(w + ": unknown field (elevation, relative, slope, skew or plant)");
      }
    }
    ecosystems.push_back(std::move(row));
    for (auto& p : row_plants) plants.push_back(std::move(p));
  }
  if (ecosystems.empty()) throw std::runtime_error("the ecosystem table is empty");
}

double splat_number(const std::string& s, const std::string& where) {
  const std::string t = trim(s);
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(v))
    throw std::runtime_error(where + "'" + t + "' is not a finite number");
  return v;
}

// SplatWeights.layers: "name: input < t ~ s, input > t ~ s, weight = w" per line.
void splat_tables(const std::string& text, json& layers, json& rules) {
  layers = json::array();
  rules = json::array();
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const std::string where = "layer line " + std::to_string(line_no) + ": ";
    const auto colon = line.find(':');
    if (colon == std::string::npos) throw std::runtime_error(where + "expected 'name: term, term, ...'");
    const std::string name = trim(line.substr(0, colon));
    if (name.empty()) throw std::runtime_error(where + "empty layer name");
    double weight = 1.0;
    std::stringstream rest(line.substr(colon + 1));
    std::string term;
    while (std::getline(rest, term, ',')) {
      term = trim(term);
      if (term.empty()) continue;
      if (const auto eq = term.find('='); eq != std::string::npos) {
        if (trim(term.substr(0, eq)) != "weight")
          throw std::runtime_error(where + "'" + term + "': only 'weight = w' takes '='");
        weight = splat_number(term.substr(eq + 1), where);
        if (weight < 0.0) throw std::runtime_error(where + "weight must be >= 0");
        continue;
      }
      const auto op = term.find_first_of("<>");
      if (op == std::string::npos)
        throw std::runtime_error(where + "'" + term + "': expected 'input < t' or 'input > t'");
      const std::string input = trim(term.substr(0, op));
      static const std::set<std::string> inputs = {"height", "slope", "curvature", "flow", "wetness", "field"};
      if (!inputs.count(input)) throw std::runtime_error(where + "unknown input '" + input + "'");
      std::string value = term.substr(op + 1);
      double softness = 0.0;
      if (const auto tilde = value.find('~'); tilde != std::string::npos) {
        softness = splat_number(value.substr(tilde + 1), where);
        if (softness < 0.0) throw std::runtime_error(where + "softness must be >= 0");
        value = value.substr(0, tilde);
      }
      rules.push_back({{"layer", name},
                       {"input", input},
                       {"compare", std::string(1, term[op])},
                       {"threshold", splat_number(value, where)},
                       {"softness", softness}});
    }
    layers.push_back({{"name", name}, {"weight", weight}});
  }
  if (layers.empty()) throw std::runtime_error("no layers");
}

// ColorByLayers.colors: "name #rrggbb" separated by newlines or commas.
json layer_colors(const std::string& text) {
  json rows = json::array();
  std::string norm = text;
  for (char& c : norm)
    if (c == ',') c = '\n';
  std::istringstream in(norm);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string name, hex, extra;
    if (!(ls >> name)) continue;
    if (!(ls >> hex) || (ls >> extra)) throw std::runtime_error("expected 'name #rrggbb', got '" + line + "'");
    rows.push_back({{"name", name}, {"color", hex_color(hex, "")}});
  }
  return rows;
}

// Instance.names: "tree, bush, , rock", class ids by position; empty entries name no class.
json class_names(const std::string& text) {
  json rows = json::array();
  std::int64_t cls = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string name = trim(text.substr(start, end - start));
    if (!name.empty()) rows.push_back({{"class", cls}, {"name", name}});
    ++cls;
    start = end + 1;
  }
  return rows;
}

// Replaces string parameter `from` of `params` by what `convert` makes of it.
template <class Convert>
void convert_param(json& params, const char* from, const std::string& node, Convert&& convert) {
  const auto it = params.find(from);
  if (it == params.end() || !it->is_string()) return;
  const std::string text = it->get<std::string>();
  try {
    convert(text);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(node + ": params." + from + ": " + e.what());
  }
}

}  // namespace

void convert_string_tables_v4(json& file) {
  if (!file.is_object() || !file.contains("nodes") || !file["nodes"].is_array()) return;
  for (auto& n : file["nodes"]) {
    if (!n.is_object() || !n.contains("type") || !n["type"].is_string()) continue;
    const std::string type = n["type"].get<std::string>();
    const std::string node =
        "node '" + (n.contains("id") && n["id"].is_string() ? n["id"].get<std::string>() : "") + "' (" + type + ")";
    if (type == "ScatterRules") {
      // The default changed with the unit of slope: a node that relied on it gets the old one converted.
      if (!n.contains("params")) n["params"] = json::object();
      if (n["params"].is_object() && !n["params"].contains("table")) n["params"]["table"] = kV4DefaultEcosystemTable;
    }
    if (!n.contains("params") || !n["params"].is_object()) continue;
    json& params = n["params"];
    if (type == "Biomes") {
      convert_param(params, "custom_table", node,
                    [&](const std::string& text) { params["custom_table"] = biome_rectangles(text); });
    } else if (type == "BiomeScatter") {
      convert_param(params, "table", node, [&](const std::string& text) {
        json biomes, species;
        biome_densities(text, biomes, species);
        params.erase("table");
        params["biomes"] = std::move(biomes);
        params["species"] = std::move(species);
      });
    } else if (type == "ScatterRules") {
      convert_param(params, "table", node, [&](const std::string& text) {
        json ecosystems, plants;
        ecosystem_tables(text, ecosystems, plants);
        params.erase("table");
        params["ecosystems"] = std::move(ecosystems);
        params["plants"] = std::move(plants);
      });
    } else if (type == "SplatWeights") {
      convert_param(params, "layers", node, [&](const std::string& text) {
        json layers, rules;
        splat_tables(text, layers, rules);
        params["layers"] = std::move(layers);
        params["rules"] = std::move(rules);
      });
    } else if (type == "ColorByLayers") {
      convert_param(params, "colors", node, [&](const std::string& text) { params["colors"] = layer_colors(text); });
    } else if (type == "Instance") {
      convert_param(params, "names", node, [&](const std::string& text) { params["names"] = class_names(text); });
    }
  }
}

}  // namespace orogen
