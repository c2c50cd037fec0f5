// Writing graph files: stable, pretty, diff-friendly JSON whose numbers read back exactly.
//
// Layout: objects one member per line with a 2-space indent; an array that holds a number or string is
// written on one line ([x, y], colours, gradient stops), an array made only of arrays has one element per
// line (curve points, gradient stops), so a change to one point is a one-line diff. A table has one row per
// line, each row an object on one line with its cells in column order.
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graph/atomic_file.h"
#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/subgraph.h"
#include "graph/table_json.h"

namespace orogen {
namespace {

using nlohmann::json;

class JsonWriter {
 public:
  std::string& text() { return out_; }

  void newline(int level) {
    out_ += '\n';
    out_.append(static_cast<std::size_t>(2 * level), ' ');
  }

  void string(const std::string& s) { out_ += json(s).dump(-1, ' ', false, json::error_handler_t::replace); }

  void key(const std::string& k, int level, bool first) {
    if (!first) out_ += ',';
    newline(level);
    string(k);
    out_ += ": ";
  }

  void value(const json& j, int level) {
    switch (j.type()) {
      case json::value_t::number_float:
        out_ += json_util::format_double(j.get<double>());
        return;
      case json::value_t::string:
        string(j.get_ref<const std::string&>());
        return;
      case json::value_t::object: {
        if (j.empty()) {
          out_ += "{}";
          return;
        }
        out_ += '{';
        bool first = true;
        for (const auto& [k, v] : j.items()) {
          key(k, level + 1, first);
          value(v, level + 1);
          first = false;
        }
        newline(level);
        out_ += '}';
        return;
      }
      case json::value_t::array: {
        if (j.empty()) {
          out_ += "[]";
          return;
        }
        const bool one_line = fits_one_line(j);
        out_ += '[';
        for (std::size_t i = 0; i < j.size(); ++i) {
          if (i > 0) out_ += one_line ? ", " : ",";
          if (!one_line) newline(level + 1);
          value(j[i], level + 1);
        }
        if (!one_line) newline(level);
        out_ += ']';
        return;
      }
      default:
        out_ += j.dump();
        return;  // null, bool, integers
    }
  }

  void table(const TableValue& t, int level) {
    if (t.rows.empty()) {
      out_ += "[]";
      return;
    }
    out_ += '[';
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      if (r > 0) out_ += ',';
      newline(level + 1);
      out_ += '{';
      bool first = true;
      for (std::size_t c = 0; c < t.rows[r].size() && c < t.columns.size(); ++c) {
        if (std::holds_alternative<std::monostate>(t.rows[r][c])) continue;
        if (!first) out_ += ", ";
        first = false;
        string(t.columns[c]);
        out_ += ": ";
        value(table_cell_to_json(t.rows[r][c]), level + 1);
      }
      out_ += '}';
    }
    newline(level);
    out_ += ']';
  }

 private:
  // One line for arrays holding at least one scalar and no objects, whose nested arrays also fit one line.
  static bool fits_one_line(const json& a) {
    bool has_scalar = false;
    for (const auto& e : a) {
      if (e.is_object()) return false;
      if (e.is_array()) {
        if (!e.empty() && !fits_one_line(e)) return false;
      } else {
        has_scalar = true;
      }
    }
    return has_scalar;
  }

  std::string out_;
};

json pair_json(const glm::dvec2& v) { return json::array({v.x, v.y}); }

// Whether `values` has an entry for one of `decls` (only declared entries are written).
template <class Map, class Decls>
bool has_declared(const Map& values, const Decls& decls) {
  for (const auto& d : decls)
    if (values.count(d.name)) return true;
  return false;
}

// `with_embedded`: write the "subgraphs" section of the embedded assets the instances use. An embedded asset's
// own document has none (it shares the file's).
std::string serialize(const Graph& graph, bool with_embedded);

}  // namespace

std::string serialize_graph(const Graph& graph) { return serialize(graph, true); }

namespace {

std::string serialize(const Graph& graph, bool with_embedded) {
  JsonWriter w;
  std::string& out = w.text();
  out += '{';
  w.key("format", 1, true);
  w.string(kGraphFormatName);
  w.key("version", 1, false);
  out += std::to_string(kGraphFormatVersion);

  w.key("domain", 1, false);
  out += '{';
  w.key("size", 2, true);
  w.value(pair_json(graph.domain.size), 2);
  w.key("resolution", 2, false);
  w.value(json::array({graph.domain.resolution.x, graph.domain.resolution.y}), 2);
  if (graph.domain.origin != glm::dvec2(0.0)) {
    w.key("origin", 2, false);
    w.value(pair_json(graph.domain.origin), 2);
  }
  w.newline(1);
  out += '}';

  if (graph.interface) {  // a subgraph asset: its interface as read
    w.key("interface", 1, false);
    w.value(json::parse(graph.interface->json_text), 1);
  }

  w.key("nodes", 1, false);
  out += '[';
  bool first_node = true;
  for (const auto& node : graph.nodes()) {
    if (!first_node) out += ',';
    first_node = false;
    w.newline(2);
    out += '{';
    w.key("id", 3, true);
    w.string(node.id);
    w.key("type", 3, false);
    w.string(node.type->name);
    if (const SubgraphAsset* asset = node.type->subgraph) {
      // The asset, and the version and interface this instance was made with (saved: the one it loaded with).
      w.key("asset", 3, false);
      w.string(node.asset);
      w.key("asset_version", 3, false);
      out += std::to_string(asset->interface().asset_version);
      w.key("interface", 3, false);
      w.value(interface_signature(asset->interface()), 3);
    }
    // Parameters and inputs in declaration order, so files diff the same way the inspector reads.
    if (has_declared(node.params, node.type->params)) {
      w.key("params", 3, false);
      out += '{';
      bool first = true;
      for (const auto& decl : node.type->params) {
        const auto it = node.params.find(decl.name);
        if (it == node.params.end()) continue;
        w.key(decl.name, 4, first);
        if (const auto* t = std::get_if<TableValue>(&it->second))
          w.table(*t, 4);
        else
          w.value(param_to_json(it->second), 4);
        first = false;
      }
      w.newline(3);
      out += '}';
    }
    if (has_declared(node.inputs, node.type->inputs)) {
      w.key("inputs", 3, false);
      out += '{';
      bool first = true;
      for (const auto& decl : node.type->inputs) {
        const auto it = node.inputs.find(decl.name);
        if (it == node.inputs.end()) continue;
        w.key(decl.name, 4, first);
        w.string(it->second.str());
        first = false;
      }
      w.newline(3);
      out += '}';
    }
    w.newline(2);
    out += '}';
  }
  if (!graph.nodes().empty()) w.newline(1);
  out += ']';

  // The node libraries the nodes come from, each with the types used (optional: absent without plugin nodes).
  std::map<std::string, std::set<std::string>> libraries;
  for (const auto& node : graph.nodes())
    if (!node.type->library.empty()) libraries[node.type->library].insert(node.type->name);
  if (!libraries.empty()) {
    w.key("node_libraries", 1, false);
    out += '{';
    bool first = true;
    for (const auto& [library, types] : libraries) {
      w.key(library, 2, first);
      w.value(json(std::vector<std::string>(types.begin(), types.end())), 2);
      first = false;
    }
    w.newline(1);
    out += '}';
  }

  // Embedded assets: those the instances use, at any depth (an unused one has no instance to keep it).
  if (with_embedded) {
    const auto embedded = embedded_assets_of(graph);
    if (!embedded.empty()) {
      w.key("subgraphs", 1, false);
      out += '{';
      bool first = true;
      for (const auto& [name, asset] : embedded) {
        w.key(name, 2, first);
        // The asset's document as its own file would have it, indented to its place.
        std::string text = serialize(asset->graph, false);
        while (!text.empty() && text.back() == '\n') text.pop_back();
        for (const char c : text) {
          out += c;
          if (c == '\n') out.append(4, ' ');
        }
        first = false;
      }
      w.newline(1);
      out += '}';
    }
  }

  // Positions in node order; positions of nodes no longer in the graph are not worth keeping.
  bool any_position = false;
  for (const auto& node : graph.nodes()) {
    const auto it = graph.editor.positions.find(node.id);
    if (it == graph.editor.positions.end()) continue;
    if (!any_position) {
      w.key("editor", 1, false);
      out += '{';
      w.key("positions", 2, true);
      out += '{';
    }
    w.key(node.id, 3, !any_position);
    w.value(pair_json(it->second), 3);
    any_position = true;
  }
  if (any_position) {
    w.newline(2);
    out += '}';
    w.newline(1);
    out += '}';
  }
  out += "\n}\n";
  return out;
}

}  // namespace

void save_graph_file(const Graph& graph, const std::filesystem::path& path) {
  write_text_atomically(path, serialize_graph(graph));
}

}  // namespace orogen
