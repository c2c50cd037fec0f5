#pragma once
// "Make unique": an instance of a shared asset (a file or a library asset) becomes an instance of its own copy,
// embedded in the graph file ("subgraphs" section, "#name"), so that editing it changes no other graph
// (docs/subgraphs.md, "Embedded assets").
#include <string>

#include "graph/graph.h"
#include "graph/subgraph.h"

namespace orogen {

struct MadeUnique {
  std::string name;                      // the embedded asset's name: the instance names it "#name"
  const SubgraphAsset* asset = nullptr;  // the copy
};

// Points instance `id` of `graph` at an embedded copy of its asset, named after the asset (made free among the
// graph's embedded assets). Relative input paths and nested asset paths in the copy are rebased from the
// asset's folder to the graph's (graph.directory), so they name the same files; the instance keeps its id,
// parameter values, links and position, and evaluates exactly as before. An instance of an embedded asset
// that other instances share gets a copy too. Throws GraphError, naming the node, for a node that is not an
// instance, an instance that already has an embedded asset of its own, and an asset whose own embedded assets
// cannot come along (one of their names is taken in the graph by a different asset, or they are in another
// folder, where their relative paths would change meaning).
// `holder`: the graph whose "subgraphs" section the copy will be saved in, when `graph` is itself an embedded
// asset of it (being edited): the name is made free there too.
MadeUnique make_instance_unique(Graph& graph, const std::string& id, const Graph* holder = nullptr);

// The document an embedded asset with the nodes and interface of `asset_graph` has in a "subgraphs" section
// (compact, as the loader reads entries: equal content loads as the same asset).
std::string embedded_document_text(const Graph& asset_graph);

// Loads `asset_graph` (an edited embedded asset) as embedded asset `name`, its "#other" instances resolving
// among the embedded assets they use. An instance of "#name" inside it is refused as recursion.
AssetLoad load_embedded_graph(const std::string& name, const Graph& asset_graph);

// Points every instance of embedded asset `asset.embedded` in `graph` at `asset` (an edited version), and
// rebuilds the embedded assets of `graph` that use it, at any depth, so that all agree. Returns whether
// anything changed. Throws GraphError when a rebuilt asset no longer loads.
bool replace_embedded_asset(Graph& graph, const SubgraphAsset& asset);

}  // namespace orogen
