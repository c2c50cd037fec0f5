#pragma once
// Runs evaluations off the UI thread and keeps what the UI shows about them.
//
// Preview: every request_preview() (after an edit, or when another node is selected) evaluates the graph at
// preview resolution on a background thread, cancelling the run it supersedes through its CancelToken;
// only the newest request runs. Thanks to resolution independence the preview shows the same terrain as
// the full build, at less detail. Per-node state (stale, computing with progress, computed, cached, failed)
// and last compute times come from the evaluator's events.
//
// Build: start_build() evaluates at the graph's full resolution with a separate evaluator on its own
// thread, writing the outputs, with progress and cancel; previews keep running meanwhile. When it ends the
// node states show what it did: nodes it failed on are Failed ("build: ..."), writers and nodes no preview
// has evaluated are Computed with the build's time (until the next edit makes them Stale).
//
// No method blocks on an evaluation except wait_idle() (for tests and tools).
#include <condition_variable>
#include <functional>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "evaluator/evaluator.h"

namespace orogen::editor {

struct NodeRunState {
  enum class Phase {
    Unknown,    // never evaluated in this session
    Stale,      // its result is out of date (an edit upstream or in it); will be recomputed when needed
    Computing,  // running now; see progress
    Computed,   // up to date, computed by the last run
    Cached,     // up to date, found in the cache by the last run
    Failed,     // see message
    Skipped,    // an upstream node failed (message names it)
  };
  Phase phase = Phase::Unknown;
  double progress = 0.0;        // Computing: fraction done
  double milliseconds = 0.0;    // the last time it was computed (kept while cached or stale)
  std::string message;          // Failed, Skipped
  std::optional<CacheKey> key;  // the key of the result it is up to date with
  bool by_build = false;        // the state comes from the last build (a full-resolution result)
};

std::string_view to_string(NodeRunState::Phase phase);

struct PreviewResult {
  std::uint64_t revision = 0;  // the request's tag (document content revision)
  std::uint64_t serial = 0;    // increases with every published result
  Domain domain;
  std::vector<std::string> requested;                     // the nodes asked for
  std::map<std::string, std::vector<PortValue>> outputs;  // outputs of the requested nodes that succeeded
  std::map<std::string, NodeReport> reports;              // every node the run touched
  double milliseconds = 0.0;
  std::string error;  // an evaluation that threw (e.g. a cycle)
};

// Small pictures of every node's outputs for the canvas, evaluated after the preview at a low resolution.
struct Thumbnails {
  std::uint64_t revision = 0;  // the request's tag
  std::uint64_t serial = 0;
  std::map<std::string, std::vector<PortValue>> outputs;  // nodes that succeeded
  Domain domain;                                          // the world rectangle (points and curves are drawn in it)
};

struct BuildStatus {
  bool running = false;
  bool finished = false;  // a build ran to its end (successfully or not) since start_build
  bool ok = false;
  bool cancelled = false;
  double fraction = 0.0;  // overall progress
  std::string current;    // a node being computed
  double milliseconds = 0.0;
  std::vector<std::string> failures;  // "node: message"
  std::vector<std::string> left_out;  // nodes not wired yet that no output needs (graph/idle_nodes.h)
  Domain domain;
};

class EvaluationController {
 public:
  static constexpr int kDefaultPreviewResolution = 512;

  explicit EvaluationController(EvaluatorOptions preview_options = preview_defaults(),
                                EvaluatorOptions build_options = build_defaults());
  ~EvaluationController();  // cancels and joins
  EvaluationController(const EvaluationController&) = delete;
  EvaluationController& operator=(const EvaluationController&) = delete;

  static EvaluatorOptions preview_defaults();
  // Builds leave one core to the UI thread and the previews (the CLI is there for batch builds).
  static EvaluatorOptions build_defaults();

  // Samples along the longer side of the previewed rectangle (the other side keeps the aspect ratio).
  void set_preview_resolution(int samples);
  int preview_resolution() const;
  Domain preview_domain(const GraphDomain& domain) const;

  // Evaluates `nodes` of a copy of `graph` at preview resolution in the background, cancelling the run in
  // flight. An empty list previews every node without downstream that does not write files. `revision` is
  // returned with the result so the UI can tell which edit it shows.
  void request_preview(const Graph& graph, std::vector<std::string> nodes, std::uint64_t revision);
  // Samples along the longer side of thumbnails.
  static constexpr int kThumbnailResolution = 64;
  // Evaluates every node that does not write files at thumbnail resolution, in the background, when no
  // preview is waiting (a preview request cancels it); replaces the thumbnail request in flight. Node states
  // are not touched.
  // With a context (set_context), `graph` is the root and `level` the entered asset whose nodes get thumbnails.
  void request_thumbnails(const Graph& graph, std::uint64_t revision, const Graph* level = nullptr);
  // Previews inside an entered subgraph instance (editor/model/subgraph_navigation.h), in the context of that
  // instance's inputs: the graph given to request_preview and request_thumbnails is then the root graph, and
  // node ids (requested, results, reports, states, thumbnails) are the entered asset's, evaluated as
  // `prefix` + id in the expanded root ("a/b/" + "relief"). Empty: ids are the graph's own. Changing it
  // forgets the node states and results of the other context.
  void set_context(std::string prefix);
  const std::string& context() const { return context_; }
  std::shared_ptr<const Thumbnails> thumbnails() const;

  // The newest finished (not cancelled) preview, or null.
  std::shared_ptr<const PreviewResult> preview() const;
  // Whether a preview is queued or running.
  bool preview_busy() const;

  std::map<std::string, NodeRunState> node_states() const;
  NodeRunState node_state(const std::string& id) const;

  // Evaluates every output of the graph at full resolution and writes the files (under `policy`). Ignored
  // while a build runs.
  void start_build(const Graph& graph, const OutputPolicy& policy);
  void cancel_build();
  BuildStatus build_status() const;

  // Blocks until no preview is queued or running and no build runs (tests, tools, shutdown).
  void wait_idle();

  // Called from the worker threads when a preview result is published or a build ends (the UI wakes from
  // waiting for events with it). Set before the first request.
  void set_on_change(std::function<void()> fn);

  CacheStats preview_cache_stats() const { return preview_evaluator_.cache_stats(); }

 private:
  struct Job {
    Graph graph;
    std::vector<std::string> nodes;
    std::uint64_t revision = 0;
    Domain domain;
    std::string prefix;  // the context the job was requested in
  };
  std::string context_;         // set_context (UI thread)
  std::string running_prefix_;  // the running preview's context (events arrive with expanded ids)
  void preview_loop();
  void run_thumbnails(Job job);
  void on_preview_event(const EvalEvent& e);
  void run_build(Graph graph, Domain domain);

  Evaluator preview_evaluator_;
  Evaluator build_evaluator_;

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<Job> pending_;
  std::optional<Job> pending_thumbnails_;
  bool thumbnails_running_ = false;
  std::shared_ptr<const Thumbnails> thumbnails_;
  bool running_ = false;
  bool stop_ = false;
  CancelToken preview_cancel_;
  int preview_resolution_ = kDefaultPreviewResolution;
  std::map<std::string, NodeRunState> states_;
  NodeRunState state_of(const std::string& id) const;  // node_state() with the mutex held
  std::map<std::string, CacheKey> running_keys_;       // keys of the graph being evaluated
  std::map<std::string, CacheKey> requested_keys_;     // keys of the last preview request
  std::shared_ptr<const PreviewResult> preview_;
  std::uint64_t serial_ = 0;

  CancelToken build_cancel_;
  BuildStatus build_;
  std::map<std::string, double> build_node_progress_;
  std::size_t build_total_ = 1;
  std::thread build_thread_;

  void notify_change();
  std::mutex notify_mutex_;
  std::function<void()> on_change_;
  std::thread preview_thread_;  // last: starts after everything it uses exists
};

}  // namespace orogen::editor
