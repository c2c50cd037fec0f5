#include "editor/model/grouping.h"

#include <algorithm>
#include <limits>
#include <set>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "graph/asset_reference.h"
#include "graph/graph_file.h"

namespace orogen::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path or_current(const fs::path& dir) {
  if (!dir.empty()) return dir;
  std::error_code ec;
  return fs::current_path(ec);
}

// `relative`, written against `from`, rewritten against `to` (absolute when no relative path exists).
std::string rebase_path(const std::string& relative, const fs::path& from, const fs::path& to) {
  const fs::path absolute = (or_current(from) / relative).lexically_normal();
  const fs::path rebased = absolute.lexically_relative(or_current(to));
  return rebased.empty() ? absolute.generic_string() : rebased.generic_string();
}

// A node moved from a graph in `from` to one in `to`: its relative asset reference and input file paths
// must still name the same files.
void rebase_node(Node& node, const fs::path& from, const fs::path& to) {
  if (or_current(from).lexically_normal() == or_current(to).lexically_normal()) return;
  if (node.type->subgraph && is_path_reference(node.asset) && fs::path(node.asset).is_relative())
    node.asset = rebase_path(node.asset, from, to);
  for (const auto& decl : node.type->params) {
    if (decl.type != ParamType::Path || decl.output_file) continue;
    const auto it = node.params.find(decl.name);
    if (it == node.params.end()) continue;
    if (const auto* text = std::get_if<std::string>(&it->second);
        text && !text->empty() && fs::path(*text).is_relative())
      it->second = rebase_path(*text, from, to);
  }
}

// `base` made into an interface name: an identifier, unique among `taken`.
std::string unique_name(std::string base, std::set<std::string>& taken) {
  for (char& c : base)
    if (c == '-') c = '_';
  std::string name = base;
  for (int k = 2; taken.count(name); ++k) name = base + std::to_string(k);
  taken.insert(name);
  return name;
}

glm::dvec2 top_left(const Graph& graph, const std::vector<std::string>& ids) {
  glm::dvec2 corner(std::numeric_limits<double>::max());
  bool any = false;
  for (const auto& id : ids)
    if (const auto it = graph.editor.positions.find(id); it != graph.editor.positions.end()) {
      corner = glm::min(corner, it->second);
      any = true;
    }
  return any ? corner : glm::dvec2(0.0);
}

json targets_json(const std::vector<SubgraphTarget>& targets) {
  if (targets.size() == 1) return targets.front().str();
  json list = json::array();
  for (const auto& t : targets) list.push_back(t.str());
  return list;
}

}  // namespace

GroupPlan plan_group(const Graph& graph, const std::vector<std::string>& ids) {
  if (ids.empty()) throw DocumentError("nothing to group: select the nodes to put in a subgraph");
  std::set<std::string> inside;
  for (const auto& id : ids) {
    if (!graph.find(id)) throw DocumentError("cannot group: there is no node '" + id + "'");
    inside.insert(id);
  }
  GroupPlan plan;
  for (const auto& node : graph.nodes())
    if (inside.count(node.id)) plan.nodes.push_back(node.id);

  // A path that leaves the selection and comes back would become a cycle through the instance.
  std::set<std::string> below, above;
  for (const auto& id : plan.nodes) {
    for (const auto& d : graph.downstream(id))
      if (!inside.count(d)) below.insert(d);
    for (const auto& u : graph.upstream(id))
      if (!inside.count(u)) above.insert(u);
  }
  for (const auto& id : below)
    if (above.count(id))
      throw DocumentError("cannot group: node '" + id +
                          "' is fed by the selection and feeds it, so the group would feed itself; add '" + id +
                          "' to the selection or leave out the nodes around it");

  std::set<std::string> input_names, output_names;
  // Inputs in the order the selected nodes declare them; one per outside output, however many it feeds.
  for (const auto& id : plan.nodes) {
    const Node& node = graph.at(id);
    for (const auto& decl : node.type->inputs) {
      const auto link = node.inputs.find(decl.name);
      if (link == node.inputs.end() || inside.count(link->second.node)) continue;
      auto same = std::find_if(plan.inputs.begin(), plan.inputs.end(),
                               [&](const GroupPlan::Input& in) { return in.source == link->second; });
      if (same == plan.inputs.end()) {
        plan.inputs.push_back({unique_name(decl.name, input_names), decl.type, link->second, {}});
        same = std::prev(plan.inputs.end());
      }
      same->targets.push_back({id, decl.name});
    }
  }
  // Outputs in the order the selected nodes declare them; the outside consumers in graph order.
  for (const auto& id : plan.nodes) {
    const Node& node = graph.at(id);
    for (const auto& decl : node.type->outputs) {
      const PortRef source{id, decl.name};
      GroupPlan::Output output{{}, decl.type, source, {}};
      for (const auto& consumer : graph.nodes()) {
        if (inside.count(consumer.id)) continue;
        for (const auto& in : consumer.type->inputs)
          if (const auto link = consumer.inputs.find(in.name); link != consumer.inputs.end() && link->second == source)
            output.consumers.push_back({consumer.id, in.name});
      }
      if (output.consumers.empty()) continue;
      output.name = unique_name(decl.name, output_names);
      plan.outputs.push_back(std::move(output));
    }
  }
  return plan;
}

Graph make_group_asset(const Graph& graph, const GroupPlan& plan, const fs::path& graph_dir, const fs::path& asset_dir,
                       const std::string& description) {
  Graph asset;
  asset.domain = graph.domain;
  asset.directory = asset_dir;
  const glm::dvec2 corner = top_left(graph, plan.nodes);
  const std::set<std::string> inside(plan.nodes.begin(), plan.nodes.end());
  for (const auto& id : plan.nodes) {
    const Node& node = graph.at(id);
    Node& copy = asset.add_node(*node.type, id);
    copy.asset = node.asset;
    copy.params = node.params;
    rebase_node(copy, graph_dir, asset_dir);
    if (const auto it = graph.editor.positions.find(id); it != graph.editor.positions.end())
      asset.editor.positions[id] = it->second - corner;
  }
  // Links inside the selection (every node is in the asset already).
  for (const auto& id : plan.nodes)
    for (const auto& [port, from] : graph.at(id).inputs)
      if (inside.count(from.node)) asset.connect(from, id, port);

  json in = {{"asset_version", 1},
             {"description", description},
             {"inputs", json::array()},
             {"outputs", json::array()},
             {"params", json::array()}};
  for (const auto& input : plan.inputs)
    in["inputs"].push_back({{"name", input.name},
                            {"type", std::string(to_string(input.type))},
                            {"description", "Grouped from " + input.source.str()},
                            {"to", targets_json(input.targets)}});
  for (const auto& output : plan.outputs)
    in["outputs"].push_back({{"name", output.name},
                             {"type", std::string(to_string(output.type))},
                             {"description", "The output of " + output.source.str()},
                             {"from", output.source.str()}});
  // The reader builds the interface (its types, the inner ports it maps to) from this text.
  auto interface = std::make_shared<SubgraphInterface>();
  interface->json_text = in.dump();
  asset.interface = std::move(interface);
  return asset;
}

fs::path free_asset_path(const fs::path& dir, const std::string& base) {
  for (int k = 1;; ++k) {
    const fs::path candidate = dir / (base + (k == 1 ? "" : std::to_string(k)) + kSubgraphFileSuffix);
    std::error_code ec;
    if (!fs::exists(candidate, ec)) return candidate;
  }
}

fs::path document_directory(const Document& document) {
  if (document.has_path()) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(document.path(), ec);
    return (ec ? document.path() : absolute).lexically_normal().parent_path();
  }
  return document.graph().directory;
}

GroupResult group_nodes(Document& document, const std::vector<std::string>& ids, fs::path asset_file) {
  const Graph& graph = document.graph();
  const GroupPlan plan = plan_group(graph, ids);
  const fs::path graph_dir = document_directory(document);
  if (asset_file.empty()) {
    if (graph_dir.empty())
      throw DocumentError("cannot group: save the graph first, so that the asset has a folder to go in");
    asset_file = free_asset_path(graph_dir);
  }
  std::error_code ec;
  asset_file = fs::absolute(asset_file, ec).lexically_normal();
  const fs::path asset_dir = asset_file.parent_path();

  std::string listed;
  for (const auto& id : plan.nodes) listed += (listed.empty() ? "" : ", ") + id;
  const Graph asset_graph =
      make_group_asset(graph, plan, graph_dir, asset_dir, "Grouped from " + document.display_name() + ": " + listed);
  // Checked as the loader will check it before anything is written: a selection with a required input left
  // unconnected inside (not fed from outside either) makes no valid asset.
  // The folder first: references out of it ("../x.json") only resolve once it exists.
  fs::create_directories(asset_dir, ec);
  LoadOptions options;
  options.directory = asset_dir;
  AssetLoadContext context;  // a selection holding an instance of the file it would overwrite is recursion
  context.chain.push_back(asset_file.stem().stem().string());
  context.files.push_back(fs::weakly_canonical(asset_file, ec));
  options.asset_context = &context;
  const std::string text = serialize_graph(asset_graph);
  if (const LoadResult check = parse_graph(text, options); !check.ok())
    throw DocumentError("cannot group " + listed + ": the asset would be invalid:\n" + check.error_text());
  try {
    save_graph_file(asset_graph, asset_file);
  } catch (const std::exception& e) {
    throw DocumentError("cannot write the asset " + asset_file.string() + ": " + e.what());
  }
  const AssetLoad load = load_subgraph_asset(asset_file.string(), asset_dir);
  if (!load.asset) throw DocumentError(load.error);

  std::string reference = asset_file.generic_string();
  if (!graph_dir.empty())
    if (const fs::path rel = asset_file.lexically_relative(graph_dir); !rel.empty()) reference = rel.generic_string();

  GroupResult result;
  result.asset_file = asset_file;
  result.asset = load.asset;
  const glm::dvec2 corner = top_left(graph, plan.nodes);
  document.edit("Group " + std::to_string(plan.nodes.size()) + " nodes into " + load.asset->name, [&](Graph& g) {
    for (const auto& id : plan.nodes) g.remove_node(id);
    Node& instance = add_subgraph_instance(g, *load.asset, reference);
    result.instance = instance.id;
    g.editor.positions[instance.id] = corner;
    for (const auto& input : plan.inputs) g.connect(input.source, result.instance, input.name);
    for (const auto& output : plan.outputs)
      for (const auto& consumer : output.consumers)
        g.connect({result.instance, output.name}, consumer.node, consumer.name);
  });
  return result;
}

std::vector<std::string> inline_instance(Graph& graph, const std::string& id, const fs::path& graph_dir) {
  const Node instance = graph.at(id);
  const SubgraphAsset* asset = instance.type->subgraph;
  if (!asset) throw GraphError("node '" + id + "' is not a subgraph instance: there is nothing to ungroup");
  const SubgraphInterface& in = asset->interface();
  const fs::path asset_dir = asset->file.parent_path();

  // The asset's nodes with the instance's exposed values, as the expansion writes them (graph/subgraph.cpp):
  // defaults are the asset's values (relative paths in them are the asset's), values set on the instance are
  // the graph's.
  Graph inner = asset->graph;
  auto write_exposed = [&](bool set_here) {
    for (const auto& p : in.params) {
      if ((instance.params.count(p.decl.name) > 0) != set_here) continue;
      const ParamValue& value = graph.param(id, p.decl.name);
      for (const auto& t : p.targets) inner.set_param(t.node, t.name, value);
    }
  };
  write_exposed(false);
  std::vector<Node*> inner_nodes;
  for (const auto& node : inner.nodes()) inner_nodes.push_back(inner.find(node.id));
  for (Node* node : inner_nodes) rebase_node(*node, asset_dir, graph_dir);
  write_exposed(true);

  // Who reads the instance's outputs, before it goes.
  struct Consumer {
    std::string node, port;
    int output;
  };
  std::vector<Consumer> consumers;
  for (const auto& node : graph.nodes())
    for (const auto& [port, from] : node.inputs)
      if (from.node == id) consumers.push_back({node.id, port, instance.type->output_index(from.port)});
  const glm::dvec2 at = graph.editor.positions.count(id) ? graph.editor.positions.at(id) : glm::dvec2(0.0);
  graph.remove_node(id);

  std::map<std::string, std::string> renamed;  // inner id -> id in the graph
  std::vector<std::string> added;
  for (const auto& node : inner.nodes()) {
    // The instance's own id is free again: an inner node may take it.
    const std::string new_id = graph.find(node.id) ? graph.unique_id(node.id) : node.id;
    Node& copy = graph.add_node(*node.type, new_id);
    copy.asset = node.asset;
    copy.params = node.params;
    renamed[node.id] = new_id;
    added.push_back(new_id);
    if (const auto it = inner.editor.positions.find(node.id); it != inner.editor.positions.end())
      graph.editor.positions[new_id] = at + it->second;
  }
  for (const auto& node : inner.nodes())
    for (const auto& [port, from] : node.inputs)
      graph.connect({renamed.at(from.node), from.port}, renamed.at(node.id), port);
  for (const auto& input : in.inputs) {
    const auto link = instance.inputs.find(input.port.name);
    if (link == instance.inputs.end()) continue;
    for (const auto& t : input.targets) graph.connect(link->second, renamed.at(t.node), t.name);
  }
  for (const auto& c : consumers) {
    const PortRef& source = in.outputs.at(static_cast<std::size_t>(c.output)).source;
    graph.connect({renamed.at(source.node), source.port}, c.node, c.port);
  }
  return added;
}

std::vector<std::string> ungroup_node(Document& document, const std::string& id) {
  const Node* node = document.graph().find(id);
  if (!node || !node->type->subgraph) throw DocumentError("cannot ungroup '" + id + "': it is not a subgraph instance");
  const std::string name = node->type->subgraph->name;
  const fs::path dir = document_directory(document);
  std::vector<std::string> added;
  document.edit("Ungroup " + id + " (" + name + ")", [&](Graph& g) { added = inline_instance(g, id, dir); });
  return added;
}

}  // namespace orogen::editor
