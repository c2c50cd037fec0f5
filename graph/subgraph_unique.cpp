// Making an instance unique: its asset copied into the graph as an embedded asset.
#include "graph/subgraph_unique.h"

#include <algorithm>
#include <map>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/subgraph.h"
#include "graph/subgraph_extract.h"

namespace orogen {

namespace fs = std::filesystem;

namespace {

fs::path folder(const fs::path& dir) {
  std::error_code ec;
  const fs::path base = dir.empty() ? fs::current_path(ec) : fs::absolute(dir, ec);
  const fs::path canonical = fs::weakly_canonical(base, ec);
  return ec ? base.lexically_normal() : canonical;
}

}  // namespace

MadeUnique make_instance_unique(Graph& graph, const std::string& id, const Graph* holder) {
  Node* node = graph.find(id);
  if (!node) {
    std::vector<std::string> ids;
    for (const auto& n : graph.nodes()) ids.push_back(n.id);
    throw GraphError("no node '" + id + "' in the graph" + json_util::suggestion(id, ids));
  }
  const SubgraphAsset* asset = node->type->subgraph;
  if (!asset) throw GraphError("node '" + id + "' is a " + node->type->name + ", not a subgraph instance");
  if (!asset->embedded.empty()) {
    const bool shared = std::any_of(graph.nodes().begin(), graph.nodes().end(), [&](const Node& n) {
      return n.id != id && n.type->subgraph && n.type->subgraph->embedded == asset->embedded;
    });
    if (!shared)
      throw GraphError("instance '" + id + "' is unique already: its asset '#" + asset->embedded +
                       "' is embedded in the graph and no other instance uses it");
  }
  const fs::path from = asset->graph.directory;  // the asset file's folder, or the graph's for an embedded one
  const fs::path to = graph.directory;

  // The copy: the asset's nodes with their paths rebased, so that they name the same files from the graph.
  Graph copy = asset->graph;
  std::vector<std::string> ids;
  for (const auto& n : copy.nodes()) ids.push_back(n.id);
  for (const auto& inner : ids) rebase_node_paths(*copy.find(inner), from, to);

  // Its own embedded assets ("#x" inside an asset file) come along into the graph's section.
  auto siblings = embedded_assets_of(graph);
  for (const auto& [name, nested] : embedded_assets_of(copy)) {
    const auto it = siblings.find(name);
    if (it != siblings.end() && it->second != nested &&
        serialize_graph(it->second->graph) != serialize_graph(nested->graph))
      throw GraphError("cannot make instance '" + id + "' unique: its asset '" + asset->name +
                       "' uses its own embedded asset '#" + name +
                       "', and the graph has a different embedded asset of that name");
    if (it == siblings.end() && folder(nested->graph.directory) != folder(to))
      throw GraphError("cannot make instance '" + id + "' unique: its asset '" + asset->name +
                       "' uses its own embedded asset '#" + name + "', whose relative paths resolve in " +
                       nested->graph.directory.string() + ", not in the graph's folder");
    siblings.emplace(name, nested);
  }

  const std::string name = free_embedded_name(graph, asset->name, holder);
  const AssetLoad load = load_embedded_asset(name, embedded_document_text(copy), to, siblings);
  if (!load.asset)
    throw GraphError("cannot make instance '" + id + "' unique: the copy of asset '" + asset->name +
                     "' does not load: " + load.error);
  node->type = &load.asset->type;
  node->asset = std::string(1, kEmbeddedReferencePrefix) + name;
  return {name, load.asset};
}

std::string embedded_document_text(const Graph& asset_graph) {
  // As the graph file's "subgraphs" section will hold it, so that saving and loading again gives the same asset.
  nlohmann::json document = nlohmann::json::parse(serialize_graph(asset_graph));
  document.erase("subgraphs");
  return document.dump();
}

AssetLoad load_embedded_graph(const std::string& name, const Graph& asset_graph) {
  std::map<std::string, const SubgraphAsset*> siblings;
  try {
    siblings = embedded_assets_of(asset_graph);
  } catch (const GraphError& e) {
    return {nullptr, e.what()};
  }
  // "#name" inside itself: the loader sees the same name again and names the cycle.
  if (siblings.count(name))
    return {nullptr, "subgraph asset '#" + name + "' contains itself: #" + name + " -> #" + name};
  return load_embedded_asset(name, embedded_document_text(asset_graph), asset_graph.directory, siblings);
}

namespace {

bool uses_embedded(const Graph& graph, const std::string& name) {
  for (const auto& node : graph.nodes()) {
    const SubgraphAsset* inner = node.type->subgraph;
    if (!inner || inner->embedded.empty()) continue;
    if (inner->embedded == name || uses_embedded(inner->graph, name)) return true;
  }
  return false;
}

}  // namespace

bool replace_embedded_asset(Graph& graph, const SubgraphAsset& asset) {
  bool changed = false;
  std::map<const SubgraphAsset*, const SubgraphAsset*> rebuilt;  // each embedded asset using it, once
  std::vector<std::string> ids;
  for (const auto& n : graph.nodes()) ids.push_back(n.id);
  for (const auto& id : ids) {
    Node& node = *graph.find(id);
    const SubgraphAsset* current = node.type->subgraph;
    if (!current || current->embedded.empty() || current == &asset) continue;
    const SubgraphAsset* replacement = nullptr;
    if (current->embedded == asset.embedded) {
      replacement = &asset;
    } else if (const auto it = rebuilt.find(current); it != rebuilt.end()) {
      replacement = it->second;
    } else if (uses_embedded(current->graph, asset.embedded)) {
      Graph copy = current->graph;
      replace_embedded_asset(copy, asset);
      const AssetLoad load = load_embedded_graph(current->embedded, copy);
      if (!load.asset)
        throw GraphError("embedded asset '#" + current->embedded + "' uses '#" + asset.embedded +
                         "', and no longer loads with its new version: " + load.error);
      replacement = rebuilt[current] = load.asset;
    }
    if (!replacement || replacement == current) continue;
    node.type = &replacement->type;
    changed = true;
  }
  return changed;
}

}  // namespace orogen
