#include "cli/tile_memory.h"

#include <algorithm>

#include "graph/output_nodes.h"

namespace orogen::cli {

namespace {

// Whether a build asks for the node by default (Evaluator: writers, nodes nothing reads, and nodes with a Report
// output). Idle nodes count too: keeping one result too many costs memory, never a wrong result.
bool requested(const Node& node, const std::vector<std::string>& consumers) {
  return is_output_node(*node.type) || consumers.empty();
}

}  // namespace

std::vector<KeySet> keys_wanted_later(const Graph& graph, const std::vector<std::map<std::string, CacheKey>>& keys,
                                      const std::vector<std::set<std::string>>& given) {
  const std::vector<std::string> order = graph.topological_order();
  std::map<std::string, std::vector<std::string>> consumers;
  for (const auto& node : graph.nodes())
    for (const auto& [port, link] : node.inputs) consumers[link.node].push_back(node.id);

  // wanted[j]: the keys build j finds from earlier builds. A node runs (or is looked up) there when it is requested
  // or feeds a node that runs; a node whose key an earlier build had is found, and what feeds it is not looked at.
  std::vector<KeySet> wanted(keys.size());
  KeySet earlier;
  for (std::size_t j = 0; j < keys.size(); ++j) {
    const auto key_of = [&](const std::string& id) -> const CacheKey* {
      const auto it = keys[j].find(id);
      return it == keys[j].end() ? nullptr : &it->second;
    };
    std::set<std::string> runs;
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      const std::string& id = *it;
      const auto& users = consumers[id];
      const bool is_reached =
          requested(graph.at(id), users) ||
          std::any_of(users.begin(), users.end(), [&](const std::string& c) { return runs.count(c); });
      if (!is_reached) continue;
      const CacheKey* key = key_of(id);
      if (key && earlier.count(*key))
        wanted[j].insert(*key);
      else if (key && (j >= given.size() || !given[j].count(id)))
        runs.insert(id);
    }
    for (const auto& [id, key] : keys[j]) earlier.insert(key);
  }

  // Build i keeps the keys of its own that some later build wants.
  std::vector<KeySet> kept(keys.size());
  KeySet later;
  for (std::size_t i = keys.size(); i-- > 0;) {
    for (const auto& [id, key] : keys[i])
      if (later.count(key)) kept[i].insert(key);
    later.insert(wanted[i].begin(), wanted[i].end());
  }
  return kept;
}

}  // namespace orogen::cli
