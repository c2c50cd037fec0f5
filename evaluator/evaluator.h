#pragma once
// The evaluator: pull-based, lazy, content-addressed, parallel.
//
// evaluate() computes the cache key of every node upstream of the request (from type, version, canonical
// parameters, input keys and domain, without computing anything), then walks back from the requested nodes
// and stops at every key found in the memory or disk cache. Only the remaining nodes run, on a oneTBB
// arena: independent branches concurrently, each node as soon as its inputs are ready. A failure skips the
// failed node's downstream only; cancellation stops at the next check and caches no partial result.
//
// Details of the contract:
// - Nodes with equal keys in one request (identical subgraphs) run once; the others report Cached.
// - A node computes only the outputs something uses (ExecContext::output_requested): those linked to a node
//   that may run, and all outputs of a requested node (but see EvalRequest::nodes); nodes with equal keys get
//   the union. Keys do not depend
//   on it: a cached result that lacks an output needed now is a miss, and the node runs again for the union of
//   what is needed and what the entry had. Such partial results are cached (in memory and on disk) with their
//   unset outputs marked, and never returned where a complete result is expected (find_result without
//   `needed`).
// - Every computed result goes to the memory LRU (unless it alone exceeds the bound, or the request keeps only
//   some: EvalRequest::keep_in_memory) and, with a cache_dir, to disk if it is worth an entry (small, or slower
//   to recompute than to read: evaluator/disk_cache.h); a damaged disk entry is deleted and recomputed. Failed and
//   cancelled nodes are never cached. Nodes that completed before a cancel keep their cached results: they are complete
//   and content-addressed, so the next run reuses them. A node that returns normally after the cancel is treated as
//   cancelled.
// - A writer's result records the files it wrote (size, modification time); it is a hit only while all of
//   them are unchanged, otherwise the writer runs again (with its inputs from the cache).
// - Values between nodes are released as soon as every consumer in the run is done, unless requested.
// - Throws GraphError if a requested node does not exist; every other problem is reported per node.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "evaluator/cache_key.h"
#include "evaluator/cached_result.h"
#include "graph/cancel.h"
#include "graph/graph.h"
#include "graph/output_path.h"
#include "graph/port_value.h"

namespace orogen {

struct EvaluatorOptions {
  int threads = 0;                                 // 0: all cores; capped at the process's oneTBB parallelism limit
  std::size_t cache_bytes = std::size_t(2) << 30;  // in-memory LRU bound (2 GiB)
  std::filesystem::path cache_dir;                 // empty: no persistent cache
  std::uint64_t max_memory = 0;                    // bytes a node's outputs may need (estimate_node_bytes); 0: no limit
  std::uint64_t cache_disk_bytes = std::uint64_t(4) << 30;  // bound of cache_dir; LRU eviction beyond it
  OutputPolicy output;                                      // where writer nodes may write
};

enum class NodeStatus { Pending, Computed, Cached, Failed, Skipped, Cancelled };
std::string_view to_string(NodeStatus s);

struct NodeReport {
  NodeStatus status = NodeStatus::Pending;
  double milliseconds = 0.0;  // compute time (0 for cached)
  std::size_t output_bytes = 0;
  std::string message;  // failure reason, or the upstream node that failed for Skipped
  CacheKey key;
};

struct EvalEvent {
  enum class Kind { Started, Progress, Finished, Cached, Failed, Skipped, Cancelled };
  Kind kind = Kind::Started;
  std::string node;
  double fraction = 0.0;         // Progress
  double milliseconds = 0.0;     // Finished
  std::size_t output_bytes = 0;  // Finished, Cached
  std::string message;           // Failed, Skipped
};
// Called from worker threads, one event at a time (never concurrently). Per node the order is Started,
// Progress..., then Finished, Failed or Cancelled; or a single Cached, Skipped or Cancelled (not started).
using EventCallback = std::function<void(const EvalEvent&)>;

struct EvalRequest {
  Domain domain;
  // Tiled builds: nodes evaluated on a domain of their own instead of `domain` (a tile expanded by the halo
  // its consumers need; see cli/tiling.h). A node's Heightfield and Image inputs that lie on a larger domain
  // of the same lattice are cropped to its domain before it runs. The domain enters the node's cache key.
  std::map<std::string, Domain> node_domains;
  // Nodes whose outputs are wanted. Empty: every node that writes files, has no downstream or has a Report
  // output; of a node requested only for its Report outputs (it has a downstream), the result holds those and
  // the outputs its links use, the others unset.
  std::vector<std::string> nodes;
  // Results computed outside this evaluation, by node id (a tiled build's tile-graph stages,
  // cli/tile_graph_stages.h): used as they are, reported Cached, and the nodes upstream of them not evaluated. Each
  // must hold every output this evaluation uses (the others may be unset); throws std::invalid_argument otherwise.
  std::map<std::string, std::shared_ptr<const CachedResult>> given_results;
  // Which results the memory cache keeps after this evaluation, by key; empty: all (up to its bound). A tiled
  // build keeps only what a later tile looks up (cli/tile_memory.h): other results this evaluation computes or
  // is given stay out of memory, and entries of them it finds there are dropped once taken, so each value
  // lives only while a node of this evaluation needs it. The disk cache stores as before.
  std::function<bool(const CacheKey&)> keep_in_memory;
  const CancelToken* cancel = nullptr;
  EventCallback on_event;
};

struct EvalResult {
  std::map<std::string, NodeReport> nodes;                // every node the request touched
  std::map<std::string, std::vector<PortValue>> outputs;  // outputs of the requested nodes that succeeded
  bool cancelled = false;
  double milliseconds = 0.0;
  bool ok() const;  // nothing failed and not cancelled
  // The value of output `port` of `node`, or monostate.
  PortValue output(const std::string& node, const std::string& port, const Graph& graph) const;
};

// Counters accumulate over the Evaluator's life. hits counts results found in memory or on disk (disk_hits
// is the part found on disk), misses the lookups that found nothing valid (the node then runs),
// disk_rejected the damaged or mismatched disk entries deleted, evictions the LRU evictions.
struct CacheStats {
  std::size_t entries = 0, bytes = 0, capacity = 0;
  std::size_t hits = 0, misses = 0, disk_hits = 0, disk_rejected = 0, evictions = 0;
  std::size_t disk_writes = 0, disk_write_errors = 0;  // entries written to the cache directory, and failures
};

// Cache keys of every node in the graph for `domain`; nodes with an invalid input link get no key. Subgraph
// instances are expanded: the keys of their inner nodes are listed as "instance/inner", and an instance's
// own key combines the keys of the inner outputs it presents.
std::map<std::string, CacheKey> compute_cache_keys(const Graph& graph, const Domain& domain,
                                                   const OutputPolicy& output = {});
// The same for nodes evaluated on domains of their own (EvalRequest::node_domains).
std::map<std::string, CacheKey> compute_cache_keys(const Graph& graph, const Domain& domain, const OutputPolicy& output,
                                                   const std::map<std::string, Domain>& node_domains);

class Evaluator {
 public:
  explicit Evaluator(EvaluatorOptions options = {});
  ~Evaluator();
  Evaluator(const Evaluator&) = delete;
  Evaluator& operator=(const Evaluator&) = delete;

  // One evaluation at a time per Evaluator; cancel through request.cancel from any thread.
  EvalResult evaluate(const Graph& graph, const EvalRequest& request);

  // A result computed outside evaluate() (a tiled build's tile-graph stages), kept like a computed one: in memory
  // (unless `in_memory` is false: the caller keeps it elsewhere) and, with a cache_dir, on disk (synchronously).
  void store_result(const CacheKey& key, std::shared_ptr<const CachedResult> result, bool in_memory = true);
  // The valid cached result of `key` for a node of `type` (memory, then disk) that has every output in `needed` (by
  // output index; empty: every output), or nullptr. Counts as a hit or miss.
  std::shared_ptr<const CachedResult> find_result(const CacheKey& key, const NodeType& type,
                                                  const std::vector<bool>& needed = {});

  CacheStats cache_stats() const;
  void clear_memory_cache();
  void set_output_policy(OutputPolicy policy);
  const EvaluatorOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace orogen
