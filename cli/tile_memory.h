#pragma once
// What a tiled build keeps in memory from one tile to the next (`orogen eval --tiles`, cli/tiling.h).
//
// The tiles are evaluated one after another, and a tile's nodes run on the tile and its halos: their cache keys
// hold the tile's domain, so no other tile can use their results. Only results whose key recurs in a later tile
// are worth keeping: nodes evaluated on the whole domain (GlobalNodes::Whole) and nodes that do not depend on the
// domain. Of those, only the ones that later tile reaches: requested there, or feeding a node that runs there
// (a node fed only by results it finds runs nowhere: its inputs are not looked up). Everything else is released
// as soon as the tile's nodes that need it have run (EvalRequest::keep_in_memory), so a tiled build holds one
// tile's working set plus those shared results, not the results of every tile.
#include <map>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "evaluator/cache_key.h"
#include "graph/graph.h"

namespace orogen::cli {

using KeySet = std::unordered_set<CacheKey, CacheKeyHash>;

// For builds evaluated in order, each with the cache keys of `graph`'s nodes (compute_cache_keys with the
// build's node domains) and the nodes whose results it is given (EvalRequest::given_results, looked up
// nowhere): per build, the keys of its nodes that a later build will look up, assuming every key an earlier
// build had is found. The last build's set is empty.
std::vector<KeySet> keys_wanted_later(const Graph& graph, const std::vector<std::map<std::string, CacheKey>>& keys,
                                      const std::vector<std::set<std::string>>& given);

}  // namespace orogen::cli
