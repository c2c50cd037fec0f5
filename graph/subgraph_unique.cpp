// Making an instance unique: its asset copied into the graph as an embedded asset.
#include "graph/subgraph_unique.h"

#include <algorithm>

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

MadeUnique make_instance_unique(Graph& graph, const std::string& id) {
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

  // The document as the graph file's "subgraphs" section will hold it (compact, as the loader reads entries),
  // so that saving and loading again gives the same asset.
  nlohmann::json document = nlohmann::json::parse(serialize_graph(copy));
  document.erase("subgraphs");
  const std::string name = free_embedded_name(graph, asset->name);
  const AssetLoad load = load_embedded_asset(name, document.dump(), to, siblings);
  if (!load.asset)
    throw GraphError("cannot make instance '" + id + "' unique: the copy of asset '" + asset->name +
                     "' does not load: " + load.error);
  node->type = &load.asset->type;
  node->asset = std::string(1, kEmbeddedReferencePrefix) + name;
  return {name, load.asset};
}

}  // namespace orogen
