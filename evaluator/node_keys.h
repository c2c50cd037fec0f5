#pragma once
// Cache keys of graph nodes, computed on demand with their upstream, plus the problems that keep a node from
// running (invalid links, missing required inputs, invalid parameter values). Used by compute_cache_keys
// and by the evaluator's planner.
//
// A node's key hashes, in this order: a key-schema tag, the type name and version, every parameter's name
// and effective value in declaration order, for every input port in declaration order either the upstream
// node's key and output port name or a fixed "absent" marker, the domain (unless the type is
// domain_independent), and for writers the resolved absolute output paths. Nothing else enters it: not
// node ids, not editor positions, not the order of nodes in the file.
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "evaluator/cache_key.h"
#include "graph/graph.h"
#include "graph/output_path.h"

namespace orogen {

struct NodeKeyInfo {
  std::optional<CacheKey> key;  // absent when a link is invalid or an upstream node has no key
  std::string error;            // the node's own problem; it fails with this message without running
  std::string blocked_by;       // keyless because of this upstream node (which has an error)
};

class NodeKeys {
 public:
  // `node_domains` (optional): nodes evaluated on a domain of their own (tiled builds, see
  // EvalRequest::node_domains); the others use `domain`.
  NodeKeys(const Graph& graph, const Domain& domain, const OutputPolicy& output,
           const std::map<std::string, Domain>* node_domains = nullptr)
      : graph_(graph), domain_(domain), output_(output), node_domains_(node_domains) {}

  // The analysis of node `id` (which must exist), computing its upstream first.
  const NodeKeyInfo& of(const std::string& id) { return of(graph_.at(id)); }
  const NodeKeyInfo& of(const Node& node);

 private:
  const Graph& graph_;
  const Domain& domain_;
  const OutputPolicy& output_;
  const std::map<std::string, Domain>* node_domains_;
  std::unordered_map<const Node*, NodeKeyInfo> done_;
  std::unordered_set<const Node*> visiting_;  // cycle detection
};

// The node feeding input `port` of `node`, with the index of its output port, or an error message.
struct ResolvedLink {
  const Node* source = nullptr;
  int output = -1;
  std::string error;
};
ResolvedLink resolve_link(const Graph& graph, const Node& node, const PortDecl& port);

// Key-schema tag: bump when the key's byte stream changes so old persistent entries are not reused.
inline constexpr const char* kNodeKeySchema = "orogen-node-key/1";

}  // namespace orogen
