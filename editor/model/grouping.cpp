#include "editor/model/grouping.h"

#include <algorithm>
#include <set>

#include "graph/atomic_file.h"
#include "graph/graph_file.h"
#include "graph/subgraph_extract.h"
#include "graph/subgraph_unique.h"

namespace orogen::editor {

namespace fs = std::filesystem;

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
  if (ids.empty()) throw DocumentError("nothing to group: select the nodes to put in a subgraph");
  const fs::path graph_dir = document_directory(document);
  if (asset_file.empty()) {
    if (graph_dir.empty())
      throw DocumentError("cannot group: save the graph first, so that the asset has a folder to go in");
    asset_file = free_asset_path(graph_dir);
  }
  std::error_code ec;
  asset_file = fs::absolute(asset_file, ec).lexically_normal();
  const fs::path asset_dir = asset_file.parent_path();

  ExtractRequest request;
  request.nodes = ids;
  request.asset_file = asset_file;
  // Only its folder matters: the instance names the asset relative to it.
  request.graph_file = document.has_path() ? fs::absolute(document.path(), ec) : graph_dir / "untitled.json";
  request.allow_writers = true;
  Extraction extraction;
  std::string listed;
  try {
    Graph located = graph;
    located.directory = graph_dir;  // relative paths in the selection are the document's
    for (const auto& n : graph.nodes())
      if (std::find(ids.begin(), ids.end(), n.id) != ids.end()) listed += (listed.empty() ? "" : ", ") + n.id;
    request.description = "Grouped from " + document.display_name() + ": " + listed;
    extraction = make_subgraph_asset(located, request);
  } catch (const GraphError& e) {
    throw DocumentError(std::string("cannot group: ") + e.what());
  }
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
  if (const LoadResult check = parse_graph(extraction.asset_text, options); !check.ok())
    throw DocumentError("cannot group " + listed + ": the asset would be invalid:\n" + check.error_text());
  try {
    write_text_atomically(asset_file, extraction.asset_text);
  } catch (const std::exception& e) {
    throw DocumentError("cannot write the asset " + asset_file.string() + ": " + e.what());
  }
  const AssetLoad load = load_subgraph_asset(asset_file.string(), asset_dir);
  if (!load.asset) throw DocumentError(load.error);

  GroupResult result;
  result.asset_file = asset_file;
  result.asset = load.asset;
  std::set<std::string> staying;
  for (const auto& n : graph.nodes())
    if (std::find(ids.begin(), ids.end(), n.id) == ids.end()) staying.insert(n.id);
  document.edit("Group " + std::to_string(request.nodes.size()) + " nodes into " + load.asset->name, [&](Graph& g) {
    g = rewrite_with_instance(g, request, extraction, *load.asset);
    for (const auto& n : g.nodes())
      if (n.type == &load.asset->type && !staying.count(n.id)) result.instance = n.id;
  });
  return result;
}

std::vector<std::string> inline_instance(Graph& graph, const std::string& id, const fs::path& graph_dir) {
  const Node instance = graph.at(id);
  const SubgraphAsset* asset = instance.type->subgraph;
  if (!asset) throw GraphError("node '" + id + "' is not a subgraph instance: there is nothing to ungroup");
  const SubgraphInterface& in = asset->interface();
  const fs::path asset_dir = asset->graph.directory;  // its file's folder; for an embedded one, the graph's

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
  for (Node* node : inner_nodes) rebase_node_paths(*node, asset_dir, graph_dir);
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

std::string make_unique_node(Document& document, const std::string& id, const Graph* holder) {
  std::string name;
  try {
    Graph check = document.graph();
    check.directory = document_directory(document);  // the copy's paths are rebased to the document's folder
    name = make_instance_unique(check, id, holder).name;
  } catch (const GraphError& e) {
    throw DocumentError("cannot make '" + id + "' unique: " + e.what());
  }
  const fs::path dir = document_directory(document);
  document.edit("Make " + id + " unique (#" + name + ")", [&](Graph& g) {
    const fs::path directory = g.directory;
    g.directory = dir;
    make_instance_unique(g, id, holder);
    g.directory = directory;
  });
  return name;
}

}  // namespace orogen::editor
