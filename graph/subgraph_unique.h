#pragma once
// "Make unique": an instance of a shared asset (a file or a library asset) becomes an instance of its own copy,
// embedded in the graph file ("subgraphs" section, "#name"), so that editing it changes no other graph
// (docs/subgraphs.md, "Embedded assets").
#include <string>

#include "graph/graph.h"

namespace orogen {

struct SubgraphAsset;

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
MadeUnique make_instance_unique(Graph& graph, const std::string& id);

}  // namespace orogen
