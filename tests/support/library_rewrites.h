#pragma once
// Example graphs rewritten to use library assets (graphs/library) after their fixtures (tests/fixtures/v1..v5)
// were taken, with outputs byte-identical (tests/test_library_rewrites.cpp). Each instance's asset keeps the ids
// of the nodes it replaced, so the graph with its instances expanded and their nodes renamed back
// ("range/base" -> "base") is the graph a fixture migrates to: the migration tests compare that, in id order.
#include <algorithm>
#include <set>
#include <string>

#include "graph/graph_file.h"
#include "graph/subgraph.h"

namespace orogen::test {

inline const std::set<std::string> kLibraryRewrites = {"eroded_mountains.json", "forest.json", "river_network.json",
                                                       "voronoi_island.json"};

// The graph as text with every instance expanded, the expanded nodes named as before the rewrite (the
// instance's prefix dropped when that id is free) and the nodes in id order.
inline std::string canonical_graph_text(const Graph& graph) {
  const Graph expanded = expand_subgraphs(graph).graph;
  std::set<std::string> plain;
  for (const auto& n : expanded.nodes())
    if (n.id.find('/') == std::string::npos) plain.insert(n.id);
  auto rename = [&](const std::string& id) {
    const auto slash = id.find('/');
    if (slash == std::string::npos || plain.count(id.substr(slash + 1))) return id;
    return id.substr(slash + 1);
  };
  std::vector<const Node*> nodes;
  for (const auto& n : expanded.nodes()) nodes.push_back(&n);
  std::sort(nodes.begin(), nodes.end(), [&](const Node* a, const Node* b) { return rename(a->id) < rename(b->id); });
  Graph out;
  out.domain = graph.domain;
  for (const Node* n : nodes) out.add_expanded_node(*n->type, rename(n->id)).params = n->params;
  for (const Node* n : nodes)
    for (const auto& [port, from] : n->inputs) out.connect({rename(from.node), from.port}, rename(n->id), port);
  return serialize_graph(out);
}

}  // namespace orogen::test
