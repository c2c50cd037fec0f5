// Reading graph files: strict JSON, format-version migration, and validation that reports every problem
// with its JSON path and node id. Writing is in graph_file_writer.cpp, parameter values in param_json.cpp.
#include "graph/graph_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

#include "graph/graph_migrations.h"
#include "graph/idle_nodes.h"
#include "graph/table_json.h"
#include "graph/json_util.h"
#include "graph/registry.h"
#include "graph/subgraph.h"
#include "graph/units.h"

namespace orogen {

std::string Diagnostic::str() const {
  std::string where = path;
  if (!node.empty()) where += (where.empty() ? "" : " ") + std::string("[node '") + node + "']";
  return where.empty() ? message : where + ": " + message;
}

std::string LoadResult::error_text() const {
  std::string text;
  for (const auto& d : diagnostics) text += d.str() + "\n";
  return text;
}

namespace {

using json_util::describe;
using json_util::pointer_token;
using json_util::suggestion;
using nlohmann::json;

struct MigrationTable {
  std::mutex mutex;
  // The format's own history (graph_migrations.h); tests may register more.
  std::map<int, GraphMigration> by_version{{1, migrate_graph_v1_to_v2}, {2, migrate_graph_v2_to_v3},
                                           {3, migrate_graph_v3_to_v4}, {4, migrate_graph_v4_to_v5},
                                           {5, migrate_graph_v5_to_v6}, {6, migrate_graph_v6_to_v7}};
};

MigrationTable& migrations() {
  static MigrationTable table;
  return table;
}

std::optional<GraphMigration> find_migration(int from_version) {
  auto& table = migrations();
  std::lock_guard lock(table.mutex);
  const auto it = table.by_version.find(from_version);
  if (it == table.by_version.end()) return std::nullopt;
  return it->second;
}

template <class Decls>
std::vector<std::string> names_of(const Decls& decls) {
  std::vector<std::string> names;
  for (const auto& d : decls) names.push_back(d.name);
  return names;
}

// " (did you mean 'x'?)", " (expected one of: ...)", or `if_none` when there is nothing to choose from.
std::string hint_or(std::string_view name, const std::vector<std::string>& candidates, std::string if_none) {
  return candidates.empty() ? std::move(if_none) : suggestion(name, candidates);
}

// Placeholder types live for the whole program (graphs point at their types); identical ones are shared.
const NodeType& placeholder_type(NodeType t) {
  static std::mutex mutex;
  static std::deque<NodeType> types;
  std::lock_guard lock(mutex);
  auto same_ports = [](const std::vector<PortDecl>& a, const std::vector<PortDecl>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
      if (a[k].name != b[k].name || a[k].type != b[k].type) return false;
    return true;
  };
  for (const auto& existing : types)
    if (existing.name == t.name && same_ports(existing.inputs, t.inputs) && same_ports(existing.outputs, t.outputs))
      return existing;
  types.push_back(std::move(t));
  return types.back();
}

// One "inputs" entry of a node, kept until every node is known.
struct PendingLink {
  std::string path;           // /nodes/i/inputs/port
  std::string node;           // id of the node the link feeds
  std::size_t node_index;     // its index in "nodes"
  std::string port;           // input port name
  const PortDecl* input;      // its declaration, or null if the port or the node type is unknown
  const NodeType* node_type;  // null if unknown
  PortRef from;
};

class GraphReader {
 public:
  GraphReader(const LoadOptions& options, std::vector<Diagnostic>& diagnostics)
      : options_(options), diagnostics_(diagnostics) {}

  std::optional<Graph> read(json doc) {
    if (!doc.is_object()) {
      report("", "", "a graph file must be a JSON object {\"format\": \"orogen-graph\", ...}, found " + describe(doc));
      return std::nullopt;
    }
    // An embedded asset's document shares the "subgraphs" section of the file it is in; any other document
    // (the graph, an asset file) has its own, which its "#name" instances look in.
    AssetLoadContext& assets = context();
    const bool embedded = std::exchange(assets.embedded_document, false);
    const std::string scope_key = std::exchange(assets.next_scope_key, std::string());
    check_format(doc);
    if (!check_version_and_migrate(doc)) return std::nullopt;
    check_fields(doc, "", "",
                 {"format", "version", "domain", "interface", "subgraphs", "nodes", "node_libraries", "editor"},
                 "in the file");
    struct PopScope {
      AssetLoadContext* context = nullptr;
      ~PopScope() {
        if (context) context->scopes.pop_back();
      }
    } pop;
    if (embedded) {
      if (doc.contains("subgraphs"))
        report("/subgraphs", "",
               "an embedded asset cannot have a \"subgraphs\" section of its own: every embedded asset of a file is "
               "in the file's top-level section, where \"#name\" finds it");
    } else {
      EmbeddedScope scope;
      scope.key = scope_key.empty() ? "graph:" + options_.directory.string() : scope_key;
      scope.directory = options_.directory;
      if (doc.contains("subgraphs") && check_embedded_section(doc["subgraphs"])) scope.section = &doc["subgraphs"];
      assets.scopes.push_back(std::move(scope));
      pop.context = &assets;
    }

    if (doc.contains("node_libraries")) read_node_libraries(doc["node_libraries"]);
    if (doc.contains("domain")) read_domain(doc["domain"]);
    if (doc.contains("interface")) note_interface_inputs(doc["interface"]);
    if (!doc.contains("nodes"))
      report("/nodes", "", "missing \"nodes\": the list of nodes (may be empty: [])");
    else
      read_nodes(doc["nodes"]);
    if (doc.contains("interface") && nodes_read_) read_interface(doc["interface"]);
    if (doc.contains("editor")) read_editor(doc["editor"]);
    if (pop.context) check_unused_embedded();

    if (!diagnostics_.empty() && !options_.keep_partial) return std::nullopt;
    return std::move(graph_);
  }

  std::vector<DroppedLink> take_dropped_links() { return std::move(dropped_); }
  AssetLoadContext& context() { return options_.asset_context ? *options_.asset_context : own_context_; }
  std::vector<Diagnostic> take_warnings() { return std::move(warnings_); }

 private:
  void report(std::string path, std::string node, std::string message) {
    diagnostics_.push_back({std::move(path), std::move(node), std::move(message)});
  }
  void drop(const PendingLink& link, const std::string& reason) {
    if (options_.keep_partial) dropped_.push_back({link.from, link.node, link.port, reason});
  }

  // Reports every key of `object` that is not in `known`.
  void check_fields(const json& object, const std::string& path, const std::string& node,
                    const std::vector<std::string>& known, const std::string& where) {
    for (const auto& [key, value] : object.items())
      if (std::find(known.begin(), known.end(), key) == known.end())
        report(path + "/" + pointer_token(key), node, "unknown field '" + key + "' " + where + suggestion(key, known));
  }

  void check_format(const json& doc) {
    if (!doc.contains("format")) {
      report("/format", "", "missing \"format\": \"orogen-graph\" (is this an Orogen graph file?)");
      return;
    }
    const json& f = doc["format"];
    if (!f.is_string() || f.get<std::string>() != kGraphFormatName)
      report("/format", "", "\"format\" must be \"orogen-graph\", found " + describe(f));
  }

  // False when the rest of the file cannot be read (newer version, impossible migration).
  bool check_version_and_migrate(json& doc) {
    if (!doc.contains("version")) {
      report("/version", "",
             "missing \"version\": the format version (this build writes " + std::to_string(kGraphFormatVersion) + ")");
      return true;  // read the rest as the current version, to report its problems too
    }
    const json& v = doc["version"];
    if (!v.is_number_integer()) {
      report("/version", "", "\"version\" must be an integer, found " + describe(v));
      return true;
    }
    if (v.is_number_unsigned() ? v.get<std::uint64_t>() > static_cast<std::uint64_t>(kGraphFormatVersion)
                               : v.get<std::int64_t>() > kGraphFormatVersion) {
      report("/version", "",
             "this file was written by a newer Orogen (version " + v.dump() + ", this build reads up to " +
                 std::to_string(kGraphFormatVersion) + "); update Orogen to open it");
      return false;
    }
    const std::int64_t from = v.get<std::int64_t>();
    for (std::int64_t k = from; k < kGraphFormatVersion; ++k) {
      const auto migration = k < INT32_MIN ? std::nullopt : find_migration(static_cast<int>(k));
      if (!migration) {
        report("/version", "",
               "cannot read format version " + std::to_string(from) + ": no migration from version " +
                   std::to_string(k) + " to " + std::to_string(k + 1) + " is known");
        return false;
      }
      try {
        (*migration)(doc);
      } catch (const std::exception& e) {
        report("/version", "",
               "migrating the file from format version " + std::to_string(k) + " to " + std::to_string(k + 1) +
                   " failed: " + e.what());
        return false;
      }
      if (!doc.is_object()) {
        report("", "",
               "migrating the file from format version " + std::to_string(k) + " to " + std::to_string(k + 1) +
                   " did not leave a JSON object");
        return false;
      }
      doc["version"] = k + 1;
    }
    return true;
  }

  // [x, y] of finite numbers; reports and returns nullopt otherwise.
  std::optional<glm::dvec2> read_pair(const json& j, const std::string& path, const std::string& node,
                                      const std::string& shape) {
    if (!j.is_array() || j.size() != 2) {
      report(path, node, "expected " + shape + ", found " + describe(j));
      return std::nullopt;
    }
    glm::dvec2 out{};
    bool ok = true;
    for (std::size_t k = 0; k < 2; ++k) {
      if (!j[k].is_number()) {
        report(path + "/" + std::to_string(k), node, "expected a number, found " + describe(j[k]));
        ok = false;
      } else {
        out[static_cast<int>(k)] = j[k].get<double>();
      }
    }
    return ok ? std::optional(out) : std::nullopt;
  }

  void read_domain(const json& d) {
    if (!d.is_object()) {
      report("/domain", "",
             "\"domain\" must be an object {\"size\": [w, h], \"resolution\": [nx, ny]}, found " + describe(d));
      return;
    }
    check_fields(d, "/domain", "", {"size", "resolution", "origin"}, "in \"domain\"");
    if (!d.contains("size")) {
      report("/domain/size", "", "missing \"size\": the world size [width, height] in metres");
    } else if (auto size = read_pair(d["size"], "/domain/size", "", "[width, height] in metres")) {
      for (int k = 0; k < 2; ++k)
        if (!((*size)[k] > 0.0))
          report("/domain/size/" + std::to_string(k), "",
                 std::string(k == 0 ? "width" : "height") + " must be greater than 0 m, found " +
                     json_util::format_double((*size)[k]));
      graph_.domain.size = *size;
    }
    if (!d.contains("resolution")) {
      report("/domain/resolution", "", "missing \"resolution\": the sample counts [nx, ny]");
    } else {
      const json& r = d["resolution"];
      if (!r.is_array() || r.size() != 2) {
        report("/domain/resolution", "", "expected [nx, ny] (2 integers), found " + describe(r));
      } else {
        for (std::size_t k = 0; k < 2; ++k) {
          const json& n = r[k];
          const bool in_range = n.is_number_integer() && !(n.is_number_unsigned() && n.get<std::uint64_t>() > 65536) &&
                                n.get<std::int64_t>() >= 2 && n.get<std::int64_t>() <= 65536;
          if (!in_range)
            report("/domain/resolution/" + std::to_string(k), "",
                   "the resolution must be an integer from 2 to 65536, found " + describe(n));
          else
            graph_.domain.resolution[static_cast<int>(k)] = static_cast<int>(n.get<std::int64_t>());
        }
      }
    }
    if (d.contains("origin"))
      if (auto origin = read_pair(d["origin"], "/domain/origin", "", "[x, y] in metres"))
        graph_.domain.origin = *origin;
    if (graph_.domain.size.x > 0.0 && graph_.domain.size.y > 0.0)
      if (auto why = check_domain(graph_.domain.to_domain()); !why.empty()) report("/domain", "", why);
  }

  void read_nodes(const json& nodes) {
    if (!nodes.is_array()) {
      report("/nodes", "", "\"nodes\" must be an array of nodes, found " + describe(nodes));
      return;
    }
    nodes_read_ = true;
    std::map<std::string, std::size_t> first_use;  // valid id -> index of the node that has it
    for (std::size_t i = 0; i < nodes.size(); ++i) read_node(nodes[i], i, first_use);
    for (const auto& [id, index] : first_use) index_of_id_[id] = index;
    add_placeholders();
    resolve_links();
    check_required_inputs();
    check_cycles();
  }

  void read_node(const json& n, std::size_t i, std::map<std::string, std::size_t>& first_use) {
    const std::string path = "/nodes/" + std::to_string(i);
    if (!n.is_object()) {
      report(path, "", "a node must be an object {\"id\": ..., \"type\": ...}, found " + describe(n));
      return;
    }
    std::string id;
    bool id_ok = false;
    if (n.contains("id") && n["id"].is_string()) {
      id = n["id"].get<std::string>();
      mentioned_ids_.insert(id);
    }
    const bool instance = n.contains("type") && n["type"] == kSubgraphTypeName;
    if (instance)
      check_fields(n, path, id, {"id", "type", "asset", "asset_version", "interface", "params", "inputs"},
                   "in a subgraph instance");
    else
      check_fields(n, path, id, {"id", "type", "params", "inputs"}, "in a node");
    if (!n.contains("id")) {
      report(path + "/id", "", "missing \"id\": every node needs a unique id");
    } else if (!n["id"].is_string()) {
      report(path + "/id", "", "\"id\" must be a string, found " + describe(n["id"]));
    } else if (!Graph::valid_id(id)) {
      report(path + "/id", id,
             "invalid node id '" + id + "': use up to 128 letters, digits, '_' and '-', starting with a letter or '_'");
    } else if (auto it = first_use.find(id); it != first_use.end()) {
      report(path + "/id", id,
             "duplicate node id '" + id + "' (already used by /nodes/" + std::to_string(it->second) + ")");
    } else {
      first_use[id] = i;
      id_ok = true;
    }

    const NodeType* type = nullptr;
    if (instance) {
      type = read_instance(n, path, id);
    } else if (!n.contains("type")) {
      report(path + "/type", id, "missing \"type\": the name of the node type");
    } else if (!n["type"].is_string()) {
      report(path + "/type", id, "\"type\" must be a string, found " + describe(n["type"]));
    } else {
      const auto name = n["type"].get<std::string>();
      type = NodeRegistry::instance().find(name);
      if (!type) {
        const auto hint = NodeRegistry::instance().closest(name);
        if (const auto lib = library_of_.find(name); lib != library_of_.end())
          report(path + "/type", id,
                 "unknown node type '" + name + "': it comes from node library '" + lib->second +
                     "', which is not loaded (load it with --plugin, OROGEN_PLUGIN_PATH or the editor's "
                     "preferences)");
        else
          report(path + "/type", id,
                 "unknown node type '" + name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
      }
    }

    Node* node = nullptr;
    if (id_ok && type) node = &graph_.add_node(*type, id);
    if (node && instance) node->asset = n["asset"].get<std::string>();
    if (id_ok && !type && options_.keep_partial && n.contains("type") && n["type"].is_string())
      unknown_[id] = {i, n["type"].get<std::string>()};
    if (n.contains("params")) read_params(n["params"], path + "/params", id, type, node);
    if (n.contains("inputs")) read_inputs(n["inputs"], path + "/inputs", id, i, type);
  }

  void read_params(const json& params, const std::string& path, const std::string& id, const NodeType* type,
                   Node* node) {
    if (!params.is_object()) {
      report(path, id, "\"params\" must be an object {\"name\": value, ...}, found " + describe(params));
      return;
    }
    if (!type) return;  // unknown type: already reported, its parameters cannot be checked
    for (const auto& [name, value] : params.items()) {
      const std::string p = path + "/" + pointer_token(name);
      const ParamDecl* decl = type->find_param(name);
      if (!decl) {
        report(p, id,
               "unknown parameter '" + name + "' for node type " + type->name +
                   hint_or(name, names_of(type->params), " (it has no parameters)"));
        continue;
      }
      if (decl->type == ParamType::Table) {
        // A table's problem points at its row and column: /nodes/3/params/layers/2/color.
        TableProblem problem;
        auto table = table_from_json(value, decl->table, problem);
        if (!table)
          report(p + problem.pointer(), id, "params." + problem.str(name));
        else if (node)
          node->params[name] = std::move(*table);
        continue;
      }
      std::string error;
      auto v = param_from_json(value, *decl, error);
      if (!v) {
        report(p, id, "parameter '" + name + "' (" + std::string(to_string(decl->type)) + "): " + error);
        continue;
      }
      if (node) node->params[name] = std::move(*v);
    }
  }

  void read_inputs(const json& inputs, const std::string& path, const std::string& id, std::size_t index,
                   const NodeType* type) {
    if (!inputs.is_object()) {
      report(path, id, "\"inputs\" must be an object {\"port\": \"node.port\", ...}, found " + describe(inputs));
      return;
    }
    for (const auto& [port, value] : inputs.items()) {
      const std::string p = path + "/" + pointer_token(port);
      const PortDecl* input = type ? type->find_input(port) : nullptr;
      if (type && !input)
        report(p, id,
               "unknown input '" + port + "' for node type " + type->name +
                   hint_or(port, names_of(type->inputs), " (it has no inputs)"));
      links_attempted_.insert({index, port});
      if (!value.is_string()) {
        report(p, id, "a link must be a string \"node.port\", found " + describe(value));
        continue;
      }
      const auto text = value.get<std::string>();
      const auto dot = text.find('.');
      if (dot == std::string::npos || dot == 0 || dot + 1 == text.size() ||
          text.find('.', dot + 1) != std::string::npos) {
        report(p, id,
               "malformed link \"" + text + "\": expected \"node.port\", the id of a node and one of its outputs");
        continue;
      }
      pending_.push_back({p, id, index, port, input, type, PortRef{text.substr(0, dot), text.substr(dot + 1)}});
    }
  }

  void resolve_links() {
    const std::vector<std::string> all_ids(mentioned_ids_.begin(), mentioned_ids_.end());
    for (const auto& link : pending_) {
      const std::string& src_id = link.from.node;
      if (!mentioned_ids_.count(src_id)) {
        if (options_.drop_dangling_links) continue;
        const auto hint = json_util::closest_name(src_id, all_ids);
        report(link.path, link.node,
               "link to missing node '" + src_id + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
        drop(link, diagnostics_.back().message);
        continue;
      }
      const Node* src = graph_.find(src_id);
      if (!src) {  // that node has an invalid id or an unknown type, reported already
        drop(link, "link from node '" + src_id + "', which could not be loaded");
        continue;
      }
      const PortDecl* output = src->type->find_output(link.from.port);
      if (!output) {
        report(link.path, link.node,
               "link to missing output '" + link.from.port + "' of node '" + src_id + "' (" + src->type->name + ")" +
                   hint_or(link.from.port, names_of(src->type->outputs), " (it has no outputs)"));
        drop(link, diagnostics_.back().message);
        continue;
      }
      if (!link.input) {  // unknown port or node type, reported already
        drop(link, "link to unknown input '" + link.port + "'");
        continue;
      }
      if (output->type != link.input->type) {
        report(link.path, link.node,
               "type mismatch: " + link.from.str() + " is " + std::string(to_string(output->type)) + " but input '" +
                   link.port + "' of " + link.node_type->name + " takes " + std::string(to_string(link.input->type)));
        drop(link, diagnostics_.back().message);
        continue;
      }
      if (Node* dst = graph_.find(link.node);
          dst && index_of_id_.count(link.node) && index_of_id_.at(link.node) == link.node_index)
        dst->inputs[link.port] = link.from;
    }
  }

  // keep_partial: nodes of unknown types as placeholders with the ports their links use. An input takes the
  // type of the output feeding it, an output the type of the inputs it feeds (a heightfield if unknown).
  void add_placeholders() {
    for (const auto& [id, info] : unknown_) {
      NodeType t;
      t.name = info.second;
      t.category = "missing";
      // Kept, so that saving the graph still records the library its node comes from.
      if (const auto lib = library_of_.find(t.name); lib != library_of_.end()) t.library = lib->second;
      t.description = "Placeholder for a node of unknown type '" + info.second +
                      "' (not registered in this build): it cannot be evaluated; its parameters were not kept.";
      for (const auto& link : pending_) {
        if (link.node_index == info.first && !t.find_input(link.port)) {
          PortDecl in{link.port, PortType::Heightfield, "", true, OutputKind::Auto};
          if (const Node* src = graph_.find(link.from.node))
            if (const PortDecl* out = src->type->find_output(link.from.port)) in.type = out->type;
          t.inputs.push_back(in);
        }
        if (link.from.node == id && !t.find_output(link.from.port)) {
          PortDecl out{link.from.port, link.input ? link.input->type : PortType::Heightfield, "", false,
                       OutputKind::Auto};
          t.outputs.push_back(out);
        }
      }
      const std::string name = info.second;
      t.execute = [name](ExecContext&) {
        throw std::runtime_error("unknown node type '" + name + "': this build has no such node");
      };
      const NodeType& placeholder = placeholder_type(std::move(t));
      graph_.add_node(placeholder, id);
      for (auto& link : pending_)
        if (link.node_index == info.first) {
          link.node_type = &placeholder;
          link.input = placeholder.find_input(link.port);
        }
    }
  }

  void check_required_inputs() {
    if (options_.allow_unconnected_inputs) return;
    const std::vector<std::string> idle_ids = idle_unwired_nodes(graph_);
    const std::set<std::string> idle(idle_ids.begin(), idle_ids.end());
    for (const auto& node : graph_.nodes()) {
      const std::size_t index = index_of_id_.at(node.id);
      for (const auto& input : node.type->inputs) {
        if (input.optional || node.inputs.count(input.name)) continue;
        if (interface_fed_.count({node.id, input.name})) continue;  // an input of the asset's interface
        // A link that was written but is broken is reported as such; a dropped dangling link is expected.
        if (links_attempted_.count({index, input.name})) continue;
        const std::string path = "/nodes/" + std::to_string(index) + "/inputs/" + pointer_token(input.name);
        const std::string message = "missing required input '" + input.name + "' (" +
                                    std::string(to_string(input.type)) + ") of node type " + node.type->name;
        if (idle.count(node.id))  // work in progress: no output needs the node, so it is not evaluated
          warnings_.push_back({path, node.id, message + "; no output needs this node, so it is left out"});
        else
          report(path, node.id, message);
      }
    }
  }

  // Reports each cycle found by a depth-first search against the links (every cycle has at least one edge
  // that closes it), naming its nodes in the direction data flows.
  void check_cycles() {
    enum class State { New, Active, Done };
    std::map<std::string, State> state;
    struct Frame {
      const Node* node;
      std::vector<std::pair<std::string, PortRef>> inputs;
      std::size_t next = 0;
    };
    for (const auto& root : graph_.nodes()) {
      if (state[root.id] != State::New) continue;
      std::vector<Frame> stack;
      auto push = [&](const Node& n) {
        state[n.id] = State::Active;
        stack.push_back({&n, {n.inputs.begin(), n.inputs.end()}, 0});
      };
      push(root);
      while (!stack.empty()) {
        Frame& f = stack.back();
        if (f.next == f.inputs.size()) {
          state[f.node->id] = State::Done;
          stack.pop_back();
          continue;
        }
        const auto [port, from] = f.inputs[f.next++];  // a copy: push() below may move the frame
        const Node* up = graph_.find(from.node);
        if (!up) continue;
        const State s = state[up->id];
        if (s == State::New) {
          push(*up);
        } else if (s == State::Active) {
          // The stack holds nodes each fed by the next; `up` feeds the top. Data flows up -> top -> ... -> up.
          std::string cycle = up->id;
          for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
            cycle += " -> " + it->node->id;
            if (it->node == up) break;
          }
          const Node* node = stack.back().node;
          report("/nodes/" + std::to_string(index_of_id_.at(node->id)) + "/inputs/" + pointer_token(port), node->id,
                 "the links form a cycle: " + cycle);
          if (options_.keep_partial) {
            // Leave the closing link out so the rest of the graph can be evaluated.
            dropped_.push_back({from, node->id, port, diagnostics_.back().message});
            graph_.disconnect(node->id, port);
          }
        }
      }
    }
  }

  // "node_libraries": {"<library>": ["<type>", ...]}, the node libraries the graph's nodes come from (written
  // by serialize_graph), so that a missing type can name the library to load.
  void read_node_libraries(const json& libs) {
    if (!libs.is_object()) {
      report("/node_libraries", "",
             "\"node_libraries\" must be an object {\"library\": [\"Type\", ...]}, found " + describe(libs));
      return;
    }
    for (const auto& [name, types] : libs.items()) {
      const std::string path = "/node_libraries/" + pointer_token(name);
      if (!types.is_array()) {
        report(path, "", "the types of node library '" + name + "' must be a list of names, found " + describe(types));
        continue;
      }
      for (std::size_t i = 0; i < types.size(); ++i) {
        if (!types[i].is_string())
          report(path + "/" + std::to_string(i), "", "a node type name must be a string, found " + describe(types[i]));
        else
          library_of_[types[i].get<std::string>()] = name;
      }
    }
  }

  void read_editor(const json& e) {
    if (!e.is_object()) {
      report("/editor", "", "\"editor\" must be an object {\"positions\": {...}}, found " + describe(e));
      return;
    }
    check_fields(e, "/editor", "", {"positions"}, "in \"editor\"");
    if (!e.contains("positions")) return;
    const json& positions = e["positions"];
    if (!positions.is_object()) {
      report("/editor/positions", "",
             "\"positions\" must be an object {\"node id\": [x, y], ...}, found " + describe(positions));
      return;
    }
    for (const auto& [id, value] : positions.items()) {
      const std::string p = "/editor/positions/" + pointer_token(id);
      if (nodes_read_ && !mentioned_ids_.count(id)) {
        report(p, id, "editor position for unknown node '" + id + "'");
        continue;
      }
      auto xy = read_pair(value, p, id, "a canvas position [x, y]");
      if (xy && graph_.find(id)) graph_.editor.positions[id] = *xy;
    }
  }

  // "subgraphs": {"name": {asset document}, ...}, the file's embedded assets (docs/subgraphs.md). Their documents
  // are read when an instance names them ("#name"), or at the end if none does.
  bool check_embedded_section(const json& section) {
    if (!section.is_object()) {
      report("/subgraphs", "",
             "\"subgraphs\" must be an object of embedded assets {\"name\": {asset document}}, found " +
                 describe(section));
      return false;
    }
    // A bad entry is reported and left unread; the others stay usable.
    for (const auto& [name, entry] : section.items()) {
      const std::string p = "/subgraphs/" + pointer_token(name);
      if (!Graph::valid_id(name)) {
        report(p, "",
               "invalid embedded asset name '" + name +
                   "': use up to 128 letters, digits, '_' and '-', starting with a letter or '_'");
      } else if (!entry.is_object()) {
        report(p, "",
               "an embedded asset must be an asset document {\"format\": \"orogen-graph\", \"version\": ..., "
               "\"interface\": ..., \"nodes\": [...]}, found " +
                   describe(entry));
      }
    }
    return true;
  }

  // Embedded assets no instance named are read now, so that their problems are reported too; saving drops them.
  void check_unused_embedded() {
    AssetLoadContext& assets = context();
    const EmbeddedScope& scope = assets.scopes.back();
    if (!scope.section) return;
    std::vector<std::string> unused;
    for (const auto& [name, entry] : scope.section->items())
      if (!scope.attempted.count(name) && Graph::valid_id(name) && entry.is_object()) unused.push_back(name);
    for (const auto& name : unused) {
      const AssetLoad load = load_subgraph_asset(std::string(1, kEmbeddedReferencePrefix) + name, {}, &assets);
      const std::string p = "/subgraphs/" + pointer_token(name);
      if (!load.asset)
        report(p, "", load.error);
      else
        warnings_.push_back({p, "",
                             "embedded asset '#" + name +
                                 "' is used by no instance: saving the graph drops it (add an instance with "
                                 "\"asset\": \"#" +
                                 name + "\" to keep it)"});
    }
  }

  // The asset of a "Subgraph" node, after checking its reference, version and recorded interface; reports and
  // returns null when it cannot be used.
  const NodeType* read_instance(const json& n, const std::string& path, const std::string& id) {
    if (!n.contains("asset") || !n["asset"].is_string()) {
      report(path + "/asset", id,
             n.contains("asset")
                 ? "\"asset\" must be a string (a library name, a path or \"#name\" of an embedded asset), found " +
                       describe(n["asset"])
                 : "missing \"asset\": the subgraph asset this instance uses (a library name, a path or \"#name\")");
      return nullptr;
    }
    const std::string reference = n["asset"].get<std::string>();
    AssetLoad load = load_subgraph_asset(reference, options_.directory, &context());
    if (!load.asset) {
      report(path + "/asset", id, load.error);
      return nullptr;
    }
    const SubgraphInterface& current = load.asset->interface();
    if (!n.contains("asset_version") || !n["asset_version"].is_number_integer()) {
      report(path + "/asset_version", id,
             "\"asset_version\" must be the integer version of asset '" + load.asset->name +
                 "' the instance was made with (the asset is at version " + std::to_string(current.asset_version) +
                 ")" + (n.contains("asset_version") ? ", found " + describe(n["asset_version"]) : ""));
      return nullptr;
    }
    const std::int64_t made_with = n["asset_version"].get<std::int64_t>();
    const std::string versions = "made with version " + std::to_string(made_with) + ", the asset (" +
                                 load.asset->location() + ") is at version " + std::to_string(current.asset_version);
    if (made_with > current.asset_version) {
      report(path + "/asset_version", id,
             "subgraph asset '" + load.asset->name + "' is older than this instance: " + versions);
      return nullptr;
    }
    if (n.contains("interface")) {
      const json& recorded = n["interface"];
      if (!recorded.is_object()) {
        report(path + "/interface", id,
               "\"interface\" must be an object {\"inputs\": {...}, \"outputs\": {...}, \"params\": {...}}, found " +
                   describe(recorded));
        return nullptr;
      }
      const std::string change = describe_interface_change(recorded, interface_signature(current));
      if (!change.empty()) {
        report(path + "/interface", id,
               "the interface of subgraph asset '" + load.asset->name + "' changed (" + versions + "): " + change +
                   (made_with == current.asset_version ? " (without a version bump)" : "") +
                   "; update the instance or use the asset version it was made with");
        return nullptr;
      }
    }
    return &load.asset->type;
  }

  // "node.name" inside an interface entry; reports and returns nullopt when malformed.
  std::optional<SubgraphTarget> read_target(const json& j, const std::string& path) {
    if (!j.is_string()) {
      report(path, "",
             "expected \"node.name\" (an inner node and one of its ports or parameters), found " + describe(j));
      return std::nullopt;
    }
    const std::string text = j.get<std::string>();
    const auto dot = text.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == text.size() ||
        text.find('.', dot + 1) != std::string::npos) {
      report(path, "", "malformed \"" + text + "\": expected \"node.name\"");
      return std::nullopt;
    }
    return SubgraphTarget{text.substr(0, dot), text.substr(dot + 1)};
  }

  // The targets of an interface entry: one "node.name" or a list of them.
  std::vector<SubgraphTarget> read_targets(const json& entry, const std::string& path, const std::string& field) {
    std::vector<SubgraphTarget> out;
    if (!entry.contains(field)) {
      report(path + "/" + field, "",
             "missing \"" + field + "\": the inner \"node.name\" (or a list of them) it maps to");
      return out;
    }
    const json& j = entry[field];
    if (j.is_array()) {
      for (std::size_t k = 0; k < j.size(); ++k)
        if (auto t = read_target(j[k], path + "/" + field + "/" + std::to_string(k))) out.push_back(*t);
      if (j.empty()) report(path + "/" + field, "", "the list of inner targets is empty");
    } else if (auto t = read_target(j, path + "/" + field)) {
      out.push_back(*t);
    }
    return out;
  }

  // Before the nodes are read: the inner inputs the interface feeds, which may stay unconnected inside.
  void note_interface_inputs(const json& in) {
    if (!in.is_object() || !in.contains("inputs") || !in["inputs"].is_array()) return;
    for (const auto& entry : in["inputs"]) {
      if (!entry.is_object() || !entry.contains("to")) continue;
      const json& to = entry["to"];
      for (const auto& t : to.is_array() ? to : json::array({to}))
        if (t.is_string())
          if (const auto dot = t.get<std::string>().find('.'); dot != std::string::npos)
            interface_fed_.insert({t.get<std::string>().substr(0, dot), t.get<std::string>().substr(dot + 1)});
    }
  }

  const Node* interface_node(const SubgraphTarget& t, const std::string& path) {
    const Node* node = graph_.find(t.node);
    if (!node) {
      std::vector<std::string> ids;
      for (const auto& n : graph_.nodes()) ids.push_back(n.id);
      report(path, "", "no inner node '" + t.node + "'" + suggestion(t.node, ids));
    }
    return node;
  }

  std::string read_name(const json& entry, const std::string& path, std::set<std::string>& seen) {
    if (!entry.contains("name") || !entry["name"].is_string() || !Graph::valid_id(entry["name"].get<std::string>())) {
      report(path + "/name", "",
             "\"name\" must be an identifier (letters, digits, '_' and '-', starting with a letter or '_')" +
                 (entry.contains("name") ? ", found " + describe(entry["name"]) : std::string()));
      return {};
    }
    const std::string name = entry["name"].get<std::string>();
    if (!seen.insert(name).second) {
      report(path + "/name", "", "duplicate name '" + name + "'");
      return {};
    }
    return name;
  }

  std::string read_text(const json& entry, const std::string& path, const char* field) {
    if (!entry.contains(field)) return {};
    if (!entry[field].is_string()) {
      report(path + "/" + field, "",
             std::string("\"") + field + "\" must be a string, found " + describe(entry[field]));
      return {};
    }
    return entry[field].get<std::string>();
  }

  // A port type named in the interface must match the inner port's.
  void check_declared_type(const json& entry, const std::string& path, const std::string& actual) {
    if (!entry.contains("type")) {
      report(path + "/type", "", "missing \"type\" (" + actual + ", the type of the inner port or parameter)");
    } else if (!entry["type"].is_string() || entry["type"].get<std::string>() != actual) {
      report(path + "/type", "", "\"type\" is " + describe(entry["type"]) + " but the inner target is " + actual);
    }
  }

  std::optional<double> read_bound(const json& entry, const std::string& path, const char* field) {
    if (!entry.contains(field)) return std::nullopt;
    if (!entry[field].is_number()) {
      report(path + "/" + field, "",
             std::string("\"") + field + "\" must be a number, found " + describe(entry[field]));
      return std::nullopt;
    }
    return entry[field].get<double>();
  }

  // "interface": what makes the file a subgraph asset (graph/subgraph.h, docs/subgraphs.md).
  void read_interface(const json& in) {
    const std::string base = "/interface";
    if (!in.is_object()) {
      report(base, "",
             "\"interface\" must be an object {\"asset_version\": 1, \"inputs\": [...], ...}, found " + describe(in));
      return;
    }
    check_fields(in, base, "", {"asset_version", "description", "inputs", "outputs", "params"}, "in \"interface\"");
    auto result = std::make_shared<SubgraphInterface>();
    result->json_text = in.dump();
    if (!in.contains("asset_version") || !in["asset_version"].is_number_integer() ||
        in["asset_version"].get<std::int64_t>() < 1 || in["asset_version"].get<std::int64_t>() > INT32_MAX)
      report(base + "/asset_version", "",
             "\"asset_version\" must be a positive integer (raise it when the interface changes)" +
                 (in.contains("asset_version") ? ", found " + describe(in["asset_version"]) : std::string()));
    else
      result->asset_version = static_cast<int>(in["asset_version"].get<std::int64_t>());
    result->description = read_text(in, base, "description");
    auto list = [&](const char* field) -> const json* {
      if (!in.contains(field)) return nullptr;
      if (!in[field].is_array()) {
        report(base + "/" + field, "", std::string("\"") + field + "\" must be an array, found " + describe(in[field]));
        return nullptr;
      }
      return &in[field];
    };
    std::set<std::string> port_names, output_names, param_names;
    if (const json* inputs = list("inputs"))
      for (std::size_t i = 0; i < inputs->size(); ++i) {
        const json& e = (*inputs)[i];
        const std::string p = base + "/inputs/" + std::to_string(i);
        if (!e.is_object()) {
          report(p, "", "an input must be an object {\"name\", \"type\", \"to\"}, found " + describe(e));
          continue;
        }
        check_fields(e, p, "", {"name", "type", "description", "label", "to"}, "in an interface input");
        SubgraphInput input;
        input.port.name = read_name(e, p, port_names);
        input.port.description = read_text(e, p, "description");
        input.port.label = read_text(e, p, "label");
        input.port.optional = true;
        bool typed = false;
        for (const auto& t : read_targets(e, p, "to")) {
          const Node* node = interface_node(t, p + "/to");
          if (!node) continue;
          const PortDecl* decl = node->type->find_input(t.name);
          if (!decl) {
            report(p + "/to", "",
                   "node '" + t.node + "' (" + node->type->name + ") has no input '" + t.name + "'" +
                       suggestion(t.name, names_of(node->type->inputs)));
            continue;
          }
          if (node->inputs.count(t.name)) {
            report(p + "/to", "", "input " + t.str() + " is linked inside the asset already");
            continue;
          }
          if (typed && decl->type != input.port.type) {
            report(p + "/to", "",
                   "input " + t.str() + " takes " + std::string(to_string(decl->type)) + ", not " +
                       std::string(to_string(input.port.type)) + " as the other targets");
            continue;
          }
          if (!typed) check_declared_type(e, p, std::string(to_string(decl->type)));
          input.port.type = decl->type;
          input.port.optional = input.port.optional && decl->optional;  // required if any target is
          input.port.unit = decl->unit;
          typed = true;
          input.targets.push_back(t);
        }
        if (!input.port.name.empty() && typed) result->inputs.push_back(std::move(input));
      }
    if (const json* outputs = list("outputs"))
      for (std::size_t i = 0; i < outputs->size(); ++i) {
        const json& e = (*outputs)[i];
        const std::string p = base + "/outputs/" + std::to_string(i);
        if (!e.is_object()) {
          report(p, "", "an output must be an object {\"name\", \"type\", \"from\"}, found " + describe(e));
          continue;
        }
        check_fields(e, p, "", {"name", "type", "description", "label", "from"}, "in an interface output");
        SubgraphOutput output;
        output.port.name = read_name(e, p, output_names);
        output.port.description = read_text(e, p, "description");
        output.port.label = read_text(e, p, "label");
        if (!e.contains("from")) {
          report(p + "/from", "", "missing \"from\": the inner \"node.port\" output it presents");
          continue;
        }
        const auto t = read_target(e["from"], p + "/from");
        if (!t) continue;
        const Node* node = interface_node(*t, p + "/from");
        if (!node) continue;
        const PortDecl* decl = node->type->find_output(t->name);
        if (!decl) {
          report(p + "/from", "",
                 "node '" + t->node + "' (" + node->type->name + ") has no output '" + t->name + "'" +
                     suggestion(t->name, names_of(node->type->outputs)));
          continue;
        }
        check_declared_type(e, p, std::string(to_string(decl->type)));
        output.port.type = decl->type;
        output.port.kind = decl->kind;
        output.port.unit = decl->unit;
        output.source = PortRef{t->node, t->name};
        if (!output.port.name.empty()) result->outputs.push_back(std::move(output));
      }
    if (const json* params = list("params"))
      for (std::size_t i = 0; i < params->size(); ++i)
        if (auto param = read_exposed_param((*params)[i], base + "/params/" + std::to_string(i), param_names))
          result->params.push_back(std::move(*param));
    graph_.interface = std::move(result);
  }

  // An exposed parameter: its declaration starts as a copy of its first target's (type, range, unit, choices,
  // table schema), which the entry may narrow and document; every target must take the same type.
  std::optional<SubgraphParam> read_exposed_param(const json& e, const std::string& p, std::set<std::string>& seen) {
    if (!e.is_object()) {
      report(p, "", "a parameter must be an object {\"name\", \"type\", \"to\", ...}, found " + describe(e));
      return std::nullopt;
    }
    check_fields(
        e, p, "",
        {"name", "type", "default", "min", "max", "soft_min", "soft_max", "unit", "description", "label", "to"},
        "in an exposed parameter");
    SubgraphParam param;
    const std::string name = read_name(e, p, seen);
    const auto targets = read_targets(e, p, "to");
    const ParamDecl* first = nullptr;
    std::vector<const ParamDecl*> target_decls;
    ParamValue first_value;
    bool ok = !name.empty() && !targets.empty();
    for (const auto& t : targets) {
      const Node* node = interface_node(t, p + "/to");
      if (!node) {
        ok = false;
        continue;
      }
      const ParamDecl* decl = node->type->find_param(t.name);
      if (!decl) {
        report(p + "/to", "",
               "node '" + t.node + "' (" + node->type->name + ") has no parameter '" + t.name + "'" +
                   suggestion(t.name, names_of(node->type->params)));
        ok = false;
        continue;
      }
      if (!first) {
        first = decl;
        first_value = graph_.param(t.node, t.name);
      } else if (decl->type != first->type) {
        report(p + "/to", "",
               "parameter " + t.str() + " is " + std::string(to_string(decl->type)) + ", not " +
                   std::string(to_string(first->type)) + " as the first target");
        ok = false;
      } else if (decl->choices != first->choices || decl->table.columns.size() != first->table.columns.size()) {
        report(p + "/to", "", "parameter " + t.str() + " takes other values than the first target");
        ok = false;
      }
      param.targets.push_back(t);
      target_decls.push_back(decl);
    }
    if (!ok || !first) return std::nullopt;
    check_declared_type(e, p, std::string(to_string(first->type)));
    ParamDecl decl = *first;
    // The range every target accepts: the narrowest bounds among them.
    for (const ParamDecl* t : target_decls) {
      if (t->min) decl.min = decl.min ? std::max(*decl.min, *t->min) : *t->min;
      if (t->max) decl.max = decl.max ? std::min(*decl.max, *t->max) : *t->max;
    }
    decl.name = name;
    decl.label = read_text(e, p, "label");
    if (e.contains("description")) decl.description = read_text(e, p, "description");
    // Bounds may only narrow the targets' own, so every value the exposed parameter accepts is valid inside.
    auto narrow = [&](const char* field, std::optional<double>& bound, bool lower) {
      const auto v = read_bound(e, p, field);
      if (!v) return;
      if (bound && (lower ? *v < *bound : *v > *bound)) {
        report(p + "/" + field, "",
               std::string("\"") + field + "\" " + json_util::format_double(*v) +
                   " is outside the inner parameter's range (" + (lower ? "min " : "max ") +
                   json_util::format_double(*bound) + ")");
        return;
      }
      bound = v;
    };
    narrow("min", decl.min, true);
    narrow("max", decl.max, false);
    if (auto v = read_bound(e, p, "soft_min")) decl.soft_min = v;
    if (auto v = read_bound(e, p, "soft_max")) decl.soft_max = v;
    if (e.contains("unit")) {
      const auto unit = e["unit"].is_string() ? unit_from_id(e["unit"].get<std::string>()) : std::nullopt;
      if (!unit)
        report(p + "/unit", "", "unknown unit " + describe(e["unit"]) + " (use the ids `orogen nodes --json` writes)");
      else
        decl.unit = *unit;
    }
    decl.default_value = first_value;
    if (e.contains("default")) {
      if (decl.type == ParamType::Table) {
        TableProblem problem;
        auto table = table_from_json(e["default"], decl.table, problem);
        if (!table) {
          report(p + "/default" + problem.pointer(), "", "default." + problem.str(name));
          return std::nullopt;
        }
        decl.default_value = std::move(*table);
      } else {
        std::string error;
        auto v = param_from_json(e["default"], decl, error);
        if (!v) {
          report(p + "/default", "", "default of '" + name + "': " + error);
          return std::nullopt;
        }
        decl.default_value = std::move(*v);
      }
    }
    if (const std::string why = decl.check(decl.default_value); !why.empty()) {
      report(p + (e.contains("default") ? "/default" : ""), "", "default of '" + name + "': " + why);
      return std::nullopt;
    }
    for (std::size_t k = 0; k < target_decls.size(); ++k)
      if (const std::string why = target_decls[k]->check(decl.default_value); !why.empty()) {
        report(p + (e.contains("default") ? "/default" : ""), "",
               "default of '" + name + "' does not suit " + param.targets[k].str() + ": " + why);
        return std::nullopt;
      }
    param.decl = std::move(decl);
    return param;
  }

  const LoadOptions& options_;
  std::vector<Diagnostic>& diagnostics_;
  std::set<std::pair<std::string, std::string>> interface_fed_;  // (inner node, input) fed by the interface
  std::vector<Diagnostic> warnings_;
  AssetLoadContext own_context_;  // when the caller gives none: the assets this file's instances load
  Graph graph_;
  std::set<std::string> mentioned_ids_;             // every string id in the file, valid or not
  std::map<std::string, std::size_t> index_of_id_;  // node id -> index in "nodes", for nodes in the graph
  std::vector<PendingLink> pending_;
  std::map<std::string, std::pair<std::size_t, std::string>> unknown_;  // id -> (index, type name)
  std::map<std::string, std::string> library_of_;                       // node type -> the node library it comes from
  std::vector<DroppedLink> dropped_;
  std::set<std::pair<std::size_t, std::string>> links_attempted_;  // (node index, input) written in the file
  bool nodes_read_ = false;                                        // "nodes" was an array, so the set of ids is known
};

// The index of the node a path such as /nodes/3/params/x points into.
std::optional<std::size_t> node_index_of(const std::string& path) {
  static const std::string prefix = "/nodes/";
  if (path.rfind(prefix, 0) != 0) return std::nullopt;
  std::size_t index = 0, k = prefix.size();
  if (k >= path.size() || !std::isdigit(static_cast<unsigned char>(path[k]))) return std::nullopt;
  for (; k < path.size() && std::isdigit(static_cast<unsigned char>(path[k])); ++k) {
    if (index > 1'000'000'000) return std::nullopt;
    index = index * 10 + static_cast<std::size_t>(path[k] - '0');
  }
  return index;
}

// The id of the node a path such as /nodes/3/params/x points into, if the document has one there.
std::string node_id_at(const json& doc, const std::string& path) {
  const auto at = node_index_of(path);
  if (!at || !doc.is_object() || !doc.contains("nodes") || !doc["nodes"].is_array()) return {};
  const std::size_t index = *at;
  const json& nodes = doc["nodes"];
  if (index >= nodes.size() || !nodes[index].is_object() || !nodes[index].contains("id") ||
      !nodes[index]["id"].is_string())
    return {};
  return nodes[index]["id"].get<std::string>();
}

}  // namespace

void register_graph_migration(int from_version, GraphMigration migration) {
  auto& table = migrations();
  std::lock_guard lock(table.mutex);
  table.by_version[from_version] = std::move(migration);
}

int migrate_graph_document(nlohmann::json& doc) {
  if (!doc.is_object() || !doc.contains("version") || !doc["version"].is_number_integer())
    throw std::runtime_error("not a graph file: no integer \"version\"");
  const std::int64_t from = doc["version"].get<std::int64_t>();
  if (from > kGraphFormatVersion)
    throw std::runtime_error("written by a newer Orogen (version " + std::to_string(from) +
                             ", this build reads up to " + std::to_string(kGraphFormatVersion) + ")");
  for (std::int64_t k = from; k < kGraphFormatVersion; ++k) {
    const auto migration = k < 1 ? std::nullopt : find_migration(static_cast<int>(k));
    if (!migration) throw std::runtime_error("no migration from format version " + std::to_string(k) + " is known");
    (*migration)(doc);
    if (!doc.is_object()) throw std::runtime_error("the migration from version " + std::to_string(k) + " failed");
    doc["version"] = k + 1;
  }
  return static_cast<int>(from);
}

LoadResult parse_graph(std::string_view json_text, const LoadOptions& options) {
  LoadResult result;
  std::vector<json_util::ParseProblem> problems;
  auto doc = json_util::parse_strict(json_text, problems);
  for (auto& p : problems)
    result.diagnostics.push_back({p.path, doc ? node_id_at(*doc, p.path) : std::string(), std::move(p.message)});
  if (!doc) return result;
  GraphReader reader(options, result.diagnostics);
  auto graph = reader.read(std::move(*doc));
  if (graph && (result.diagnostics.empty() || options.keep_partial)) result.graph = std::move(graph);
  result.dropped_links = reader.take_dropped_links();
  result.warnings = reader.take_warnings();
  // Checks run in passes (links need every node); list the problems in file order instead: file-level and
  // domain first, then node by node, then the editor section.
  auto rank = [](const Diagnostic& d) {
    if (d.path.rfind("/editor", 0) == 0) return std::pair<int, std::size_t>(2, 0);
    if (auto index = node_index_of(d.path)) return std::pair<int, std::size_t>(1, *index);
    return std::pair<int, std::size_t>(0, 0);
  };
  std::stable_sort(result.diagnostics.begin(), result.diagnostics.end(),
                   [&](const Diagnostic& a, const Diagnostic& b) { return rank(a) < rank(b); });
  return result;
}

LoadResult load_graph_file(const std::filesystem::path& path, const LoadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    LoadResult result;
    result.diagnostics.push_back({"", "", "cannot open " + path.string() + ": " + std::strerror(errno)});
    return result;
  }
  // Read at most kMaxGraphFileBytes + 1 bytes: a graph file is text of a few kilobytes, and a device or a
  // huge file must not be read without end.
  std::string text;
  char chunk[1 << 16];
  while (in && text.size() <= kMaxGraphFileBytes) {
    in.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) {
    LoadResult result;
    result.diagnostics.push_back({"", "", "cannot read " + path.string()});
    return result;
  }
  if (text.size() > kMaxGraphFileBytes) {
    LoadResult result;
    result.diagnostics.push_back({"", "",
                                  path.string() + " is larger than " + std::to_string(kMaxGraphFileBytes >> 20) +
                                      " MiB, the limit of a graph file"});
    return result;
  }
  LoadOptions with_directory = options;
  if (with_directory.directory.empty()) {
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(path, ec);
    with_directory.directory = (ec ? path : absolute).lexically_normal().parent_path();
  }
  auto result = parse_graph(text, with_directory);
  if (result.graph) {
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(path, ec);
    result.graph->directory = (ec ? path : absolute).lexically_normal().parent_path();
  }
  return result;
}

}  // namespace orogen
