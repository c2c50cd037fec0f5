// Extracting a selection of nodes into a subgraph asset, and rewriting the graph to use an instance of it.
#include "graph/subgraph_extract.h"

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <tuple>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "graph/asset_reference.h"
#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/subgraph.h"

namespace orogen {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "'" : ", '") + s + "'";
  return out;
}

// A folder as expansion will see it: absolute and without symbolic links, so lexical relative paths agree.
fs::path resolved_dir(const fs::path& dir) {
  std::error_code ec;
  const fs::path base = dir.empty() ? fs::current_path(ec) : fs::absolute(dir, ec);
  const fs::path canonical = fs::weakly_canonical(base, ec);
  return ec ? base.lexically_normal() : canonical;
}

// `value`, a path relative to `from`, made relative to `to` (absolute values stay).
std::string rebase(const std::string& value, const fs::path& from, const fs::path& to) {
  if (value.empty() || fs::path(value).is_absolute()) return value;
  const fs::path target = (from / value).lexically_normal();
  const fs::path relative = target.lexically_relative(to);
  return relative.empty() ? target.string() : relative.generic_string();
}

// An interface name from `base` (a port or parameter name, or "node_port"): letters, digits, '_' and '-'.
std::string identifier(std::string base) {
  for (char& c : base)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  if (base.empty() || (!std::isalpha(static_cast<unsigned char>(base[0])) && base[0] != '_')) base = "_" + base;
  return base;
}

// `preferred` if free, else `fallback` ("node_port"), else fallback2, fallback3, ...
std::string unique_name(std::set<std::string>& used, const std::string& preferred, const std::string& fallback) {
  std::string name = identifier(preferred);
  if (used.count(name)) name = identifier(fallback);
  const std::string base = name;
  for (int k = 2; used.count(name); ++k) name = base + std::to_string(k);
  used.insert(name);
  return name;
}

// The top-left corner of the positions of `ids` (0,0 when none has one).
glm::dvec2 top_left(const Graph& graph, const std::set<std::string>& ids) {
  glm::dvec2 corner(std::numeric_limits<double>::max());
  bool any = false;
  for (const auto& id : ids)
    if (const auto it = graph.editor.positions.find(id); it != graph.editor.positions.end()) {
      corner = glm::min(corner, it->second);
      any = true;
    }
  return any ? corner : glm::dvec2(0.0);
}

bool writes_files(const Node& node) {
  return std::any_of(node.type->params.begin(), node.type->params.end(),
                     [](const ParamDecl& d) { return d.type == ParamType::Path && d.output_file; });
}

}  // namespace

void rebase_node_paths(Node& node, const fs::path& from, const fs::path& to) {
  const fs::path a = resolved_dir(from), b = resolved_dir(to);
  if (a == b) return;
  for (const auto& decl : node.type->params) {
    if (decl.type != ParamType::Path || decl.output_file) continue;
    const auto it = node.params.find(decl.name);
    const auto* text = std::get_if<std::string>(it != node.params.end() ? &it->second : &decl.default_value);
    if (!text) continue;
    const std::string moved = rebase(*text, a, b);
    if (moved != *text) node.params[decl.name] = moved;
  }
  if (node.type->subgraph && is_path_reference(node.asset)) node.asset = rebase(node.asset, a, b);
}

Extraction make_subgraph_asset(const Graph& graph, const ExtractRequest& request) {
  // The selection: known, distinct ids, no writers.
  if (request.nodes.empty()) throw GraphError("the selection is empty: name the nodes to extract (--nodes a,b,c)");
  std::set<std::string> selected;
  std::vector<std::string> unknown, repeated, writers;
  for (const auto& id : request.nodes) {
    if (!graph.find(id))
      unknown.push_back(id);
    else if (!selected.insert(id).second)
      repeated.push_back(id);
  }
  if (!unknown.empty()) {
    std::vector<std::string> ids;
    for (const auto& n : graph.nodes()) ids.push_back(n.id);
    std::string text;
    for (const auto& id : unknown)
      text += (text.empty() ? "" : "; ") + ("no node '" + id + "' in the graph" + json_util::suggestion(id, ids));
    throw GraphError(text);
  }
  if (!repeated.empty()) throw GraphError("node " + join(repeated) + " is selected twice");
  if (!request.allow_writers)
    for (const auto& n : graph.nodes())
      if (selected.count(n.id) && writes_files(n)) writers.push_back(n.id + "' (" + n.type->name + ")");
  if (!writers.empty()) {
    std::string list;
    for (const auto& w : writers) list += (list.empty() ? "'" : ", '") + w;
    throw GraphError("the selection has writers: " + list +
                     "; every instance of the asset would write the same file, so leave writers out of the "
                     "selection (they are linked to the instance's outputs)");
  }

  // Convexity: an unselected node fed by the selection and feeding it would be both upstream and downstream
  // of the instance.
  for (const auto& n : graph.nodes()) {
    if (selected.count(n.id)) continue;
    const auto up = graph.upstream(n.id);
    const auto down = graph.downstream(n.id);
    const auto from = std::find_if(up.begin(), up.end(), [&](const std::string& id) { return selected.count(id); });
    const auto to = std::find_if(down.begin(), down.end(), [&](const std::string& id) { return selected.count(id); });
    if (from != up.end() && to != down.end())
      throw GraphError("the selection is not convex: node '" + n.id + "' (not selected) is fed by selected node '" +
                       *from + "' and feeds selected node '" + *to +
                       "', so the instance would feed itself (a cycle); select '" + n.id +
                       "' too, or leave out the nodes on one side of it");
  }

  if (!request.instance_id.empty()) {
    if (!Graph::valid_id(request.instance_id))
      throw GraphError("invalid instance id '" + request.instance_id +
                       "': letters, digits, '_' and '-', starting with a letter or '_'");
    if (graph.find(request.instance_id) && !selected.count(request.instance_id))
      throw GraphError("the instance id '" + request.instance_id + "' is taken by a node that stays in the graph");
  }

  Extraction ex;
  ex.asset_name = asset_name_of(request.asset_file);
  const fs::path graph_dir = resolved_dir(graph.directory);
  const fs::path asset_dir = resolved_dir(request.asset_file.parent_path());
  const fs::path instance_dir = resolved_dir(request.graph_file.parent_path());
  std::string reference = (asset_dir / request.asset_file.filename()).lexically_relative(instance_dir).generic_string();
  if (reference.empty()) reference = (asset_dir / request.asset_file.filename()).generic_string();
  if (!is_path_reference(reference)) reference = "./" + reference;
  ex.reference = reference;

  // The inner graph: the selected nodes, in graph order, with the links among them, placed from 0,0.
  const glm::dvec2 corner = top_left(graph, selected);
  Graph inner;
  inner.domain = graph.domain;
  for (const auto& n : graph.nodes()) {
    if (!selected.count(n.id)) continue;
    Node& copy = inner.add_node(*n.type, n.id);
    copy.asset = n.asset;
    copy.params = n.params;
    // Relative paths inside an asset resolve against the asset's folder.
    rebase_node_paths(copy, graph_dir, asset_dir);
    if (const auto it = graph.editor.positions.find(n.id); it != graph.editor.positions.end())
      inner.editor.positions[n.id] = it->second - corner;
  }
  for (const auto& n : graph.nodes()) {
    if (!selected.count(n.id)) continue;
    for (const auto& [port, from] : n.inputs)
      if (selected.count(from.node)) inner.connect(from, n.id, port);
  }

  // Inputs: one per outside output feeding the selection, in the order of the selected inputs it feeds.
  std::set<std::string> used;
  json inputs = json::array();
  for (const auto& n : graph.nodes()) {
    if (!selected.count(n.id)) continue;
    for (const auto& decl : n.type->inputs) {
      const auto it = n.inputs.find(decl.name);
      if (it == n.inputs.end() || selected.count(it->second.node)) continue;
      auto same = std::find_if(ex.inputs.begin(), ex.inputs.end(),
                               [&](const Extraction::Input& i) { return i.source == it->second; });
      if (same != ex.inputs.end()) {
        same->targets.push_back({n.id, decl.name});
        continue;
      }
      Extraction::Input input;
      input.name = unique_name(used, decl.name, n.id + "_" + decl.name);
      input.source = it->second;
      input.targets.push_back({n.id, decl.name});
      ex.inputs.push_back(input);
      json entry = {
          {"name", input.name},
          {"type", std::string(to_string(decl.type))},
          {"description", decl.description.empty() ? "Input " + decl.name + " of " + n.id : decl.description}};
      inputs.push_back(entry);
    }
  }
  for (std::size_t k = 0; k < ex.inputs.size(); ++k) {
    json to = json::array();
    for (const auto& t : ex.inputs[k].targets) to.push_back(t.str());
    inputs[k]["to"] = to.size() == 1 ? to[0] : to;
  }

  // Outputs: one per selected output linked from outside, in graph and port order.
  used.clear();
  json outputs = json::array();
  for (const auto& n : graph.nodes()) {
    if (!selected.count(n.id)) continue;
    for (const auto& decl : n.type->outputs) {
      Extraction::Output output;
      output.source = {n.id, decl.name};
      for (const auto& m : graph.nodes()) {
        if (selected.count(m.id)) continue;
        for (const auto& [port, from] : m.inputs)
          if (from == output.source) output.sinks.emplace_back(m.id, port);
      }
      if (output.sinks.empty()) continue;
      output.name = unique_name(used, decl.name, n.id + "_" + decl.name);
      outputs.push_back(
          {{"name", output.name},
           {"type", std::string(to_string(decl.type))},
           {"description", decl.description.empty() ? "Output " + decl.name + " of " + n.id : decl.description},
           {"from", output.source.str()}});
      ex.outputs.push_back(std::move(output));
    }
  }

  // Exposed parameters.
  used.clear();
  json params = json::array();
  for (const auto& spec : request.expose) {
    const auto dot = spec.rfind('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == spec.size())
      throw GraphError("--expose '" + spec + "': expected NODE.PARAM");
    const std::string node = spec.substr(0, dot), name = spec.substr(dot + 1);
    if (!selected.count(node))
      throw GraphError("--expose '" + spec + "': node '" + node + "' is not in the selection (" + join(request.nodes) +
                       ")");
    const Node& n = graph.at(node);
    const ParamDecl* decl = n.type->find_param(name);
    if (!decl) {
      std::vector<std::string> names;
      for (const auto& d : n.type->params) names.push_back(d.name);
      throw GraphError("--expose '" + spec + "': node '" + node + "' (" + n.type->name + ") has no parameter '" + name +
                       "' (its parameters: " + join(names) + ")");
    }
    if (std::any_of(ex.params.begin(), ex.params.end(), [&](const Extraction::Param& p) {
          return p.target == PortRef{node, name};
        }))
      throw GraphError("--expose '" + spec + "' is given twice");
    Extraction::Param param{unique_name(used, name, node + "_" + name), {node, name}};
    params.push_back({{"name", param.name},
                      {"type", std::string(to_string(decl->type))},
                      {"description", decl->description.empty() ? spec : decl->description},
                      {"to", spec}});
    ex.params.push_back(std::move(param));
  }

  std::vector<std::string> ids;
  for (const auto& n : inner.nodes()) ids.push_back(n.id);
  const std::string source = request.source.empty() ? std::string("a graph") : request.source;
  json interface = {
      {"asset_version", 1},
      {"description",
       request.description.empty() ? "Extracted from " + source + ": nodes " + join(ids) + "." : request.description},
      {"inputs", inputs},
      {"outputs", outputs},
      {"params", params}};
  auto in = std::make_shared<SubgraphInterface>();
  in->json_text = interface.dump();
  inner.interface = std::move(in);
  ex.asset_text = serialize_graph(inner);
  return ex;
}

Graph rewrite_with_instance(const Graph& graph, const ExtractRequest& request, const Extraction& ex,
                            const SubgraphAsset& asset) {
  const std::set<std::string> selected(request.nodes.begin(), request.nodes.end());
  std::string id = request.instance_id;
  if (id.empty()) {
    // Free once the selection is gone: the asset's name, or a selected node's id.
    Graph rest;
    for (const auto& n : graph.nodes())
      if (!selected.count(n.id)) rest.add_node(*n.type, n.id);
    id = rest.unique_id(Graph::valid_id(ex.asset_name) ? ex.asset_name : "subgraph");
  }
  // The nodes in their order, the instance where the first selected node was, so the file's diff stays local.
  Graph out;
  out.domain = graph.domain;
  out.directory = graph.directory;
  out.interface = graph.interface;  // grouping inside an asset keeps it an asset
  bool placed = false;
  for (const auto& n : graph.nodes()) {
    if (selected.count(n.id)) {
      if (!placed) add_subgraph_instance(out, asset, ex.reference, id);
      placed = true;
      continue;
    }
    Node& copy = out.add_node(*n.type, n.id);
    copy.asset = n.asset;
    copy.params = n.params;
  }
  std::map<PortRef, std::string, bool (*)(const PortRef&, const PortRef&)> output_name(
      [](const PortRef& a, const PortRef& b) { return std::tie(a.node, a.port) < std::tie(b.node, b.port); });
  for (const auto& output : ex.outputs) output_name[output.source] = output.name;
  for (const auto& n : graph.nodes()) {
    if (selected.count(n.id)) continue;
    for (const auto& [port, from] : n.inputs)
      out.connect(selected.count(from.node) ? PortRef{id, output_name.at(from)} : from, n.id, port);
  }
  for (const auto& input : ex.inputs) out.connect(input.source, id, input.name);

  bool positioned = false;
  for (const auto& n : graph.nodes()) {
    const auto it = graph.editor.positions.find(n.id);
    if (it == graph.editor.positions.end()) continue;
    if (selected.count(n.id))
      positioned = true;
    else
      out.editor.positions[n.id] = it->second;
  }
  if (positioned) out.editor.positions[id] = top_left(graph, selected);
  return out;
}

}  // namespace orogen
