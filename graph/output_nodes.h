#pragma once
// A graph's outputs: the nodes that write files and the nodes with a Report output (their figures are results in
// their own right). A build asks for them by default (evaluator), keeps what they need (graph/idle_nodes.h), and a
// tiled build plans its memory from them (cli/tile_memory.h).
#include <algorithm>

#include "graph/node_type.h"

namespace orogen {

inline bool has_report_output(const NodeType& t) {
  return std::any_of(t.outputs.begin(), t.outputs.end(), [](const PortDecl& p) { return p.type == PortType::Report; });
}

inline bool is_output_node(const NodeType& t) { return t.writes_files || has_report_output(t); }

}  // namespace orogen
