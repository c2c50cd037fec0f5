#pragma once
// Work in progress in a graph: a node added but not wired yet. Like Gaea and World Machine, a node that no
// output needs does not stop a build: it is reported as a warning and left out of the evaluation.
#include <string>
#include <vector>

#include "graph/graph.h"

namespace orogen {

// The graph's outputs are its writers and the nodes with a Report output; a graph with neither has none (then
// every node nothing reads is wanted, and this returns nothing). Returns, in graph order, the nodes that cannot
// run (a required input unconnected, on the node or upstream of it) and that no output needs.
std::vector<std::string> idle_unwired_nodes(const Graph& graph);

}  // namespace orogen
