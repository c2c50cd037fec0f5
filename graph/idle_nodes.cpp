#include "graph/idle_nodes.h"

#include <algorithm>
#include <map>
#include <set>

#include "graph/output_nodes.h"

namespace orogen {

std::vector<std::string> idle_unwired_nodes(const Graph& graph) {
  std::map<std::string, std::vector<std::string>> readers;  // node -> the nodes reading its outputs
  std::vector<std::string> needed_stack, blocked_stack;
  for (const auto& n : graph.nodes()) {
    for (const auto& [port, link] : n.inputs) readers[link.node].push_back(n.id);
    if (is_output_node(*n.type)) needed_stack.push_back(n.id);
    for (const auto& input : n.type->inputs)
      if (!input.optional && !n.inputs.count(input.name)) {
        blocked_stack.push_back(n.id);
        break;
      }
  }
  if (needed_stack.empty() || blocked_stack.empty()) return {};
  std::set<std::string> needed;  // the outputs and everything upstream of them
  while (!needed_stack.empty()) {
    const std::string id = needed_stack.back();
    needed_stack.pop_back();
    if (!needed.insert(id).second) continue;
    if (const Node* n = graph.find(id))
      for (const auto& [port, link] : n->inputs) needed_stack.push_back(link.node);
  }
  std::set<std::string> blocked;  // an unconnected required input, here or upstream
  while (!blocked_stack.empty()) {
    const std::string id = blocked_stack.back();
    blocked_stack.pop_back();
    if (!blocked.insert(id).second) continue;
    for (const auto& r : readers[id]) blocked_stack.push_back(r);
  }
  std::vector<std::string> idle;
  for (const auto& n : graph.nodes())
    if (blocked.count(n.id) && !needed.count(n.id)) idle.push_back(n.id);
  return idle;
}

}  // namespace orogen
