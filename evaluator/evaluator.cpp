#include "evaluator/evaluator.h"

#include <algorithm>
#include <atomic>
#include <deque>
#include <mutex>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "evaluator/cached_result.h"
#include "evaluator/disk_cache.h"
#include "evaluator/domain_crop.h"
#include "evaluator/memory_cache.h"
#include "evaluator/memory_estimate.h"
#include "evaluator/node_keys.h"
#include "graph/idle_nodes.h"
#include "graph/output_nodes.h"
#include "graph/subgraph.h"
#include "graph/exec_context.h"

namespace orogen {

using Clock = std::chrono::steady_clock;

static double milliseconds_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string_view to_string(NodeStatus s) {
  switch (s) {
    case NodeStatus::Pending:
      return "pending";
    case NodeStatus::Computed:
      return "computed";
    case NodeStatus::Cached:
      return "cached";
    case NodeStatus::Failed:
      return "failed";
    case NodeStatus::Skipped:
      return "skipped";
    case NodeStatus::Cancelled:
      return "cancelled";
  }
  return "unknown";
}

bool EvalResult::ok() const {
  if (cancelled) return false;
  return std::all_of(nodes.begin(), nodes.end(), [](const auto& entry) {
    return entry.second.status == NodeStatus::Computed || entry.second.status == NodeStatus::Cached;
  });
}

PortValue EvalResult::output(const std::string& node, const std::string& port, const Graph& graph) const {
  const auto it = outputs.find(node);
  const Node* n = graph.find(node);
  if (it == outputs.end() || !n) return std::monostate{};
  const int index = n->type->output_index(port);
  if (index < 0 || static_cast<std::size_t>(index) >= it->second.size()) return std::monostate{};
  return it->second[static_cast<std::size_t>(index)];
}

std::map<std::string, CacheKey> compute_cache_keys(const Graph& graph, const Domain& domain,
                                                   const OutputPolicy& output) {
  return compute_cache_keys(graph, domain, output, {});
}

std::map<std::string, CacheKey> compute_cache_keys(const Graph& graph, const Domain& domain, const OutputPolicy& output,
                                                   const std::map<std::string, Domain>& node_domains) {
  if (has_subgraphs(graph)) {
    // The inner nodes' keys ("instance/inner"), and for each instance a key of the inner outputs it presents.
    const ExpandedGraph expanded = expand_subgraphs(graph);
    auto keys = compute_cache_keys(expanded.graph, domain, output, node_domains);
    for (const auto& [id, outputs] : expanded.outputs) {
      KeyHasher h;
      h.add(std::string_view("orogen-subgraph-instance/1"));
      bool complete = true;
      for (const auto& ref : outputs) {
        const auto it = keys.find(ref.node);
        if (it == keys.end()) {
          complete = false;
          break;
        }
        h.add(it->second).add(std::string_view(ref.port));
      }
      if (complete) keys.emplace(id, h.finish());
    }
    return keys;
  }
  NodeKeys keys(graph, domain, output, &node_domains);
  std::map<std::string, CacheKey> result;
  for (const auto& node : graph.nodes())
    if (const auto& info = keys.of(node.id); info.key) result.emplace(node.id, *info.key);
  return result;
}

namespace {

// Whether a cached result has the shape of `type`'s outputs: one value per output, each unset or of the declared
// type. Unset outputs are those nobody requested when it was computed (ExecContext::output_requested).
bool fits(const NodeType& type, const CachedResult& r) {
  if (r.outputs.size() != type.outputs.size()) return false;
  for (std::size_t i = 0; i < r.outputs.size(); ++i)
    if (has_value(r.outputs[i]) && port_type_of(r.outputs[i]) != type.outputs[i].type) return false;
  return true;
}

// Whether a result that fits has every output in `needed` (by output index; empty: every output).
bool covers(const CachedResult& r, const std::vector<bool>& needed) {
  for (std::size_t i = 0; i < r.outputs.size(); ++i)
    if ((needed.empty() || needed[i]) && !has_value(r.outputs[i])) return false;
  return true;
}

// Progress events of one node are at most this frequent, and each advances by at least kProgressStep.
constexpr auto kProgressInterval = std::chrono::milliseconds(20);
constexpr double kProgressStep = 0.01;

// The state that outlives one evaluation: options, caches, statistics.
struct EvaluatorState {
  explicit EvaluatorState(EvaluatorOptions o) : options(std::move(o)), memory(options.cache_bytes) {
    if (!options.cache_dir.empty()) disk = std::make_unique<DiskCache>(options.cache_dir, options.cache_disk_bytes);
  }

  // An arena of options.threads threads (0: all cores), created per evaluation so it follows the process's
  // current parallelism limit: asking for more threads than that limit only oversubscribes the cores (and
  // makes oneTBB print a warning), so the request is capped to it.
  std::unique_ptr<tbb::task_arena> make_arena() const {
    if (options.threads <= 0) return std::make_unique<tbb::task_arena>();
    const auto limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    return std::make_unique<tbb::task_arena>(static_cast<int>(
        std::min<std::size_t>(static_cast<std::size_t>(options.threads), std::max<std::size_t>(limit, 1))));
  }

  EvaluatorOptions options;
  MemoryCache memory;
  std::unique_ptr<DiskCache> disk;
  std::mutex evaluate_mutex;  // one evaluation at a time
  std::atomic<std::size_t> hits{0}, misses{0}, disk_hits{0}, disk_rejected{0}, disk_writes{0}, disk_write_errors{0};

  // The valid cached result of `key` for a node of `type` that has every output in `needed` (empty: all), from
  // memory or disk, or nullptr. A valid result that lacks a needed output is a miss, not damage: it is kept
  // (the new result replaces it) and returned through `partial`, so the caller can compute what it had too.
  std::shared_ptr<const CachedResult> lookup(const CacheKey& key, const NodeType& type,
                                             const std::vector<bool>& needed = {},
                                             std::shared_ptr<const CachedResult>* partial = nullptr) {
    auto keep_partial = [&](const std::shared_ptr<const CachedResult>& r) {
      if (partial && !*partial) *partial = r;
    };
    if (auto r = memory.find(key)) {
      if (!fits(type, *r) || (type.writes_files && !r->files_unchanged())) {
        memory.erase(key);  // a writer whose files changed, or an entry that does not fit
      } else if (covers(*r, needed)) {
        ++hits;
        return r;
      } else {
        keep_partial(r);  // the disk may still hold a more complete result
      }
    }
    if (disk) {
      DiskCache::Loaded loaded;
      try {
        loaded = disk->load(key);
      } catch (const std::exception&) {
        loaded.rejected = true;  // the cache never fails a build: an entry we cannot even inspect is a miss
      }
      if (loaded.rejected) {
        ++disk_rejected;
      } else if (loaded.result && !fits(type, *loaded.result)) {
        disk->remove(key);
        ++disk_rejected;
      } else if (loaded.result && (!type.writes_files || loaded.result->files_unchanged())) {
        if (covers(*loaded.result, needed)) {
          ++hits;
          ++disk_hits;
          memory.insert(key, loaded.result, loaded.result->value_bytes());
          return loaded.result;
        }
        keep_partial(loaded.result);
      }
    }
    ++misses;
    return nullptr;
  }
};

// One unit of work: a distinct cache key (nodes with equal keys share one job), or a node that cannot run.
struct Job {
  enum class Kind { Run, Hit, Fail, Skip };
  Kind kind = Kind::Run;
  std::optional<CacheKey> key;
  const Node* node = nullptr;    // the representative node: the first one planned with this key
  std::vector<std::string> ids;  // every node of the request with this key; ids[0] is the representative
  std::string planned_message;   // Fail: the node's error; Skip: the upstream node that has the error
  bool requested = false;
  std::vector<bool> needed;  // outputs something uses, by output index (Run and Hit jobs)

  struct Input {
    int job = -1;   // producer job, -1 for an unconnected optional input
    int port = -1;  // its output index
  };
  std::vector<Input> inputs;           // by input port
  std::vector<int> producers;          // distinct
  std::vector<int> consumers;          // distinct
  std::atomic<int> waiting{0};         // producers not finished yet
  std::atomic<int> consumers_left{0};  // consumers not finished yet

  // Outcome, written by the one task that runs the job, read after its consumers were scheduled.
  NodeStatus status = NodeStatus::Pending;
  std::string message;
  std::shared_ptr<const CachedResult> result;
  double milliseconds = 0.0;
  std::size_t bytes = 0;
  double unstored_ms = 0.0;  // what recomputing it would cost a later run if it is not on disk (0 if it is)

  std::mutex progress_mutex;
  double last_fraction = -1.0;
  Clock::time_point last_progress;
};

// One call of evaluate(): plans the jobs, runs them, collects the reports.
class Run {
 public:
  Run(EvaluatorState& impl, const Graph& graph, const EvalRequest& request)
      : impl_(impl),
        graph_(graph),
        request_(request),
        policy_(impl.options.output),
        keys_(graph, request.domain, policy_, &request.node_domains) {}

  EvalResult execute() {
    const auto t0 = Clock::now();
    const std::vector<std::string>& requested = requested_ids();
    find_needed_outputs(requested);
    for (const auto& id : requested) jobs_[static_cast<std::size_t>(plan(id))].requested = true;
    for (auto& job : jobs_) job.consumers_left.store(static_cast<int>(job.consumers.size()));

    const bool anything_to_run =
        std::any_of(jobs_.begin(), jobs_.end(), [](const Job& job) { return job.kind == Job::Kind::Run; });
    if (anything_to_run) {
      const auto arena = impl_.make_arena();
      arena->execute([&] {
        for (std::size_t j = 0; j < jobs_.size(); ++j)
          if (jobs_[j].producers.empty()) group_.run([this, j] { launch(static_cast<int>(j)); });
        group_.wait();
      });
    } else {
      // Only hits and planned failures, none of which has producers: no need to wake any thread.
      for (std::size_t j = 0; j < jobs_.size(); ++j) launch(static_cast<int>(j));
    }

    EvalResult result;
    const std::set<std::string> requested_set(requested_.begin(), requested_.end());
    for (const auto& [id, j] : job_of_node_) {
      const Job& job = jobs_[static_cast<std::size_t>(j)];
      NodeReport report;
      report.status = job.status;
      report.milliseconds = job.milliseconds;
      report.output_bytes = job.bytes;
      report.message = job.message;
      if (job.key) report.key = *job.key;
      if (id != job.ids.front() && job.status == NodeStatus::Computed) {
        report.status = NodeStatus::Cached;
        report.milliseconds = 0.0;
        report.message = "same result as node '" + job.ids.front() + "'";
      }
      if (report.status == NodeStatus::Cancelled) result.cancelled = true;
      if (job.requested && job.result && requested_set.count(id)) result.outputs[id] = job.result->outputs;
      result.nodes[id] = std::move(report);
    }
    result.milliseconds = milliseconds_since(t0);
    return result;
  }

 private:
  // The request's nodes, or by default every writer and every node whose outputs nothing reads, but for nodes
  // that cannot run and that no output needs.
  const std::vector<std::string>& requested_ids() {
    if (!request_.nodes.empty()) {
      for (const auto& id : request_.nodes)
        if (!graph_.find(id)) throw GraphError("cannot evaluate node '" + id + "': no such node");
      requested_ = request_.nodes;
      return requested_;
    }
    std::set<std::string> feeding;
    for (const auto& n : graph_.nodes())
      for (const auto& [port, link] : n.inputs) feeding.insert(link.node);
    // Nodes with a Report output are requested too (graph/output_nodes.h).
    // A node added but not wired yet, that no output needs, is left out (graph/idle_nodes.h).
    const std::vector<std::string> idle_ids = idle_unwired_nodes(graph_);
    const std::set<std::string> idle(idle_ids.begin(), idle_ids.end());
    for (const auto& n : graph_.nodes()) {
      if (idle.count(n.id)) continue;
      if (n.type->writes_files || !feeding.count(n.id)) {
        requested_.push_back(n.id);
      } else if (has_report_output(*n.type)) {
        requested_.push_back(n.id);
        for_reports_only_.insert(&n);
      }
    }
    return requested_;
  }

  // The outputs of every node upstream of the request that anything may use: all of a requested node's, and
  // each output a node of the closure is linked from. Nodes with equal keys share one job, so their needs are
  // united by key. (A consumer that turns out to be a cache hit still counts: the producer then computes an
  // output this run does not use, never one too few.)
  void find_needed_outputs(const std::vector<std::string>& requested) {
    auto need = [&](const Node& n) -> std::vector<bool>& {
      auto& v = needed_by_node_[&n];
      v.resize(n.type->outputs.size(), false);
      return v;
    };
    std::vector<const Node*> stack;
    std::unordered_set<const Node*> seen;
    for (const auto& id : requested) {
      const Node& n = graph_.at(id);
      auto& v = need(n);
      // A node requested by default for its figures alone (it feeds other nodes) gives its Report outputs;
      // the links add the others they use.
      const bool reports_only = for_reports_only_.count(&n) > 0;
      for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = v[i] || !reports_only || n.type->outputs[i].type == PortType::Report;
      if (seen.insert(&n).second) stack.push_back(&n);
    }
    while (!stack.empty()) {
      const Node& n = *stack.back();
      stack.pop_back();
      if (request_.given_results.count(n.id)) continue;  // its upstream is not evaluated
      for (const auto& port : n.type->inputs) {
        const ResolvedLink link = resolve_link(graph_, n, port);
        if (!link.source || link.output < 0) continue;
        need(*link.source)[static_cast<std::size_t>(link.output)] = true;
        if (seen.insert(link.source).second) stack.push_back(link.source);
      }
    }
    for (const auto& [node, v] : needed_by_node_) {
      const NodeKeyInfo& info = keys_.of(*node);
      if (!info.key) continue;
      auto& united = needed_by_key_[*info.key];
      united.resize(v.size(), false);
      for (std::size_t i = 0; i < v.size(); ++i) united[i] = united[i] || v[i];
    }
  }

  // The outputs of the node with `key` that anything in this run may use.
  std::vector<bool> needed_outputs(const CacheKey& key, const NodeType& type) const {
    const auto it = needed_by_key_.find(key);
    return it != needed_by_key_.end() ? it->second : std::vector<bool>(type.outputs.size(), true);
  }

  // Walks back from node `id`, stopping at cache hits; returns its job.
  int plan(const std::string& id) {
    if (const auto it = job_of_node_.find(id); it != job_of_node_.end()) return it->second;
    const NodeKeyInfo& info = keys_.of(id);
    if (info.key)
      if (const auto it = job_of_key_.find(*info.key); it != job_of_key_.end()) {
        jobs_[static_cast<std::size_t>(it->second)].ids.push_back(id);
        job_of_node_[id] = it->second;
        return it->second;
      }
    const int j = static_cast<int>(jobs_.size());
    Job& job = jobs_.emplace_back();  // a deque: references stay valid while planning adds jobs
    job.node = &graph_.at(id);
    job.key = info.key;
    job.ids.push_back(id);
    job_of_node_[id] = j;
    if (info.key) job_of_key_[*info.key] = j;

    if (!info.error.empty()) {
      job.kind = Job::Kind::Fail;
      job.planned_message = info.error;
      return j;
    }
    if (!info.blocked_by.empty()) {
      job.kind = Job::Kind::Skip;
      job.planned_message = info.blocked_by;
      plan(info.blocked_by);  // so the node at fault is reported too
      return j;
    }
    const NodeType& type = *job.node->type;
    if (const auto given = request_.given_results.find(id); given != request_.given_results.end()) {
      if (!given->second || !fits(type, *given->second) || !covers(*given->second, needed_outputs(*info.key, type)))
        throw std::invalid_argument("evaluate: the given result of node '" + id + "' does not fit its outputs");
      job.result = given->second;
      job.kind = Job::Kind::Hit;
      forget_unless_kept(*info.key);
      return j;
    }
    job.needed = needed_outputs(*info.key, type);
    std::shared_ptr<const CachedResult> partial;
    if ((job.result = impl_.lookup(*info.key, type, job.needed, &partial))) {
      job.kind = Job::Kind::Hit;
      forget_unless_kept(*info.key);  // the job holds it as long as this run needs it
      return j;
    }
    // Recomputing over a result that lacked a needed output: compute what it had too, so the entry that
    // replaces it never has fewer outputs.
    if (partial)
      for (std::size_t i = 0; i < job.needed.size(); ++i)
        job.needed[i] = job.needed[i] || has_value(partial->outputs[i]);
    job.kind = Job::Kind::Run;
    job.inputs.resize(type.inputs.size());
    for (std::size_t i = 0; i < type.inputs.size(); ++i) {
      const ResolvedLink link = resolve_link(graph_, *job.node, type.inputs[i]);
      if (!link.source) continue;  // an absent optional input (errors were caught by the key analysis)
      const int p = plan(link.source->id);
      job.inputs[i] = {p, link.output};
      if (std::find(job.producers.begin(), job.producers.end(), p) == job.producers.end()) {
        job.producers.push_back(p);
        jobs_[static_cast<std::size_t>(p)].consumers.push_back(j);
      }
    }
    job.waiting.store(static_cast<int>(job.producers.size()));
    return j;
  }

  // The domain node `id` is evaluated on: its own (tiled builds) or the request's.
  const Domain& domain_of(const std::string& id) const {
    const auto it = request_.node_domains.find(id);
    return it != request_.node_domains.end() ? it->second : request_.domain;
  }

  void emit(EvalEvent event) {
    if (!request_.on_event) return;
    std::lock_guard lock(event_mutex_);  // events are delivered one at a time
    try {
      request_.on_event(event);
    } catch (...) {
      // An observer's failure must not break the evaluation.
    }
  }

  void emit_for_all(const Job& job, EvalEvent::Kind kind) {
    for (const auto& id : job.ids) {
      EvalEvent e;
      e.kind = kind;
      e.node = id;
      e.output_bytes = job.bytes;
      e.message = job.message;
      emit(std::move(e));
    }
  }

  bool cancel_requested() const { return request_.cancel && request_.cancel->cancelled(); }

  void launch(int j) {
    Job& job = jobs_[static_cast<std::size_t>(j)];
    switch (job.kind) {
      case Job::Kind::Hit:
        job.status = NodeStatus::Cached;
        job.bytes = job.result->value_bytes();
        emit_for_all(job, EvalEvent::Kind::Cached);
        break;
      case Job::Kind::Fail:
        job.status = NodeStatus::Failed;
        job.message = job.planned_message;
        emit_for_all(job, EvalEvent::Kind::Failed);
        break;
      case Job::Kind::Skip:
        job.status = NodeStatus::Skipped;
        job.message = job.planned_message;
        emit_for_all(job, EvalEvent::Kind::Skipped);
        break;
      case Job::Kind::Run:
        run(job);
        break;
    }
    finish(job);
  }

  void run(Job& job) {
    // Inputs that did not succeed: cancelled wins over failed (cancelling is the user's latest intent).
    std::string failed_upstream;
    bool upstream_cancelled = false;
    for (int p : job.producers) {
      const Job& producer = jobs_[static_cast<std::size_t>(p)];
      if (producer.status == NodeStatus::Cancelled)
        upstream_cancelled = true;
      else if (producer.status == NodeStatus::Failed && failed_upstream.empty())
        failed_upstream = producer.ids.front();
      else if (producer.status == NodeStatus::Skipped && failed_upstream.empty())
        failed_upstream = producer.message;
    }
    if (upstream_cancelled || cancel_requested()) {
      job.status = NodeStatus::Cancelled;
      job.message = "not started: the evaluation was cancelled";
      emit_for_all(job, EvalEvent::Kind::Cancelled);
      return;
    }
    if (!failed_upstream.empty()) {
      job.status = NodeStatus::Skipped;
      job.message = failed_upstream;
      emit_for_all(job, EvalEvent::Kind::Skipped);
      return;
    }
    compute(job);
  }

  void compute(Job& job) {
    const Node& node = *job.node;
    const NodeType& type = *node.type;
    const std::string& id = job.ids.front();
    emit({EvalEvent::Kind::Started, id, 0.0, 0.0, 0, {}});
    const auto t0 = Clock::now();
    std::shared_ptr<CachedResult> result;
    try {
      const Domain& domain = domain_of(id);
      std::vector<PortValue> inputs(type.inputs.size());
      for (std::size_t i = 0; i < job.inputs.size(); ++i)
        if (job.inputs[i].job >= 0) {
          const Job& from = jobs_[static_cast<std::size_t>(job.inputs[i].job)];
          inputs[i] = from.result->outputs[static_cast<std::size_t>(job.inputs[i].port)];
          if (!request_.node_domains.empty()) inputs[i] = crop_input(inputs[i], domain_of(from.ids.front()), domain);
        }
      if (auto why = check_domain(domain); !why.empty()) throw NodeError(why);
      std::vector<ParamValue> params = graph_.effective_params(node);
      if (impl_.options.max_memory > 0) {
        const std::uint64_t need =
            estimate_node_bytes(CostQuery{type, domain, ParamView(type, params), &inputs, graph_.directory, {}});
        if (need > impl_.options.max_memory)
          throw NodeError(memory_refusal(type, domain, need, impl_.options.max_memory));
      }
      ExecContext ctx(type, id, domain, std::move(inputs), std::move(params));
      ctx.set_cancel_token(request_.cancel);
      ctx.set_output_policy(policy_);
      ctx.set_input_dir(graph_.directory);
      if (request_.on_event) ctx.set_progress_callback([this, &job](double f) { progress(job, f); });
      if (std::find(job.needed.begin(), job.needed.end(), false) != job.needed.end())
        ctx.set_requested_outputs(job.needed);
      type.execute(ctx);
      // A node that returns after a cancel may have stopped early without saying so: never keep its result.
      if (cancel_requested()) throw Cancelled{};
      // Outputs nobody requested may stay unset: the cached result then lacks them, and a later run that needs
      // one finds it incomplete (a miss) and computes it.
      for (std::size_t i = 0; i < type.outputs.size(); ++i)
        if ((job.needed.empty() || job.needed[i]) && !has_value(ctx.outputs()[i]))
          throw NodeError("the node did not set its output '" + type.outputs[i].name + "'");
      result = std::make_shared<CachedResult>();
      result->outputs = std::move(ctx.outputs());
      for (const auto& path : ctx.written_files()) {
        try {
          result->files.push_back(WrittenFile::stat(path));
        } catch (const std::exception& e) {
          throw NodeError("the node reported writing '" + path.string() + "', but it cannot be read: " + e.what());
        }
      }
    } catch (const Cancelled&) {
      job.milliseconds = milliseconds_since(t0);
      job.status = NodeStatus::Cancelled;
      job.message = "cancelled";
      emit_for_all(job, EvalEvent::Kind::Cancelled);
      return;
    } catch (const std::exception& e) {
      fail(job, e.what(), t0);
      return;
    } catch (...) {
      // Something that is not a std::exception (a node library's bug, say): still only this node's error.
      fail(job,
           "the node threw an exception that is not a std::exception" +
               (type.library.empty() ? std::string() : " (node type from node library '" + type.library + "')"),
           t0);
      return;
    }
    job.milliseconds = milliseconds_since(t0);
    job.bytes = result->value_bytes();
    job.result = result;
    job.status = NodeStatus::Computed;
    store(job, result);

    emit({EvalEvent::Kind::Finished, id, 1.0, job.milliseconds, job.bytes, {}});
    for (std::size_t k = 1; k < job.ids.size(); ++k)
      emit({EvalEvent::Kind::Cached, job.ids[k], 0.0, 0.0, job.bytes, {}});
  }

  void fail(Job& job, std::string message, Clock::time_point t0) {
    job.milliseconds = milliseconds_since(t0);
    job.status = NodeStatus::Failed;
    job.message = message.empty() ? "failed without a message" : std::move(message);
    emit_for_all(job, EvalEvent::Kind::Failed);
  }

  // Whether the memory cache keeps the result of `key` after this run (EvalRequest::keep_in_memory).
  bool kept_in_memory(const CacheKey& key) const { return !request_.keep_in_memory || request_.keep_in_memory(key); }
  void forget_unless_kept(const CacheKey& key) {
    if (!kept_in_memory(key)) impl_.memory.erase(key);
  }

  // Keeps a complete result: in memory now (if the request keeps it) and, if it is worth an entry, on disk in a
  // separate task so consumers need not wait for it. A later run without the entry recomputes the unstored
  // values it is made from too.
  void store(Job& job, std::shared_ptr<const CachedResult> result) {
    const CacheKey key = *job.key;
    if (kept_in_memory(key))
      impl_.memory.insert(key, result, job.bytes);
    else
      impl_.memory.erase(key);  // a partial entry this result completes
    if (!impl_.disk) return;
    double recompute_ms = job.milliseconds;
    for (int p : job.producers) recompute_ms += jobs_[static_cast<std::size_t>(p)].unstored_ms;
    if (!impl_.disk->worth_storing(recompute_ms, job.bytes)) {
      job.unstored_ms = recompute_ms;
      return;
    }
    group_.run([this, key, result] {
      try {
        impl_.disk->store(key, *result);
        ++impl_.disk_writes;
      } catch (...) {
        ++impl_.disk_write_errors;  // the cache is an optimisation: a full disk must not fail the node
      }
    });
  }

  // Called from the node's own worker threads; the job's lock keeps its progress events in increasing order.
  void progress(Job& job, double fraction) {
    std::lock_guard lock(job.progress_mutex);
    const auto now = Clock::now();
    if (fraction < job.last_fraction + kProgressStep) return;
    if (job.last_fraction >= 0.0 && now - job.last_progress < kProgressInterval) return;
    job.last_fraction = fraction;
    job.last_progress = now;
    emit({EvalEvent::Kind::Progress, job.ids.front(), fraction, 0.0, 0, {}});
  }

  // Releases inputs nobody needs any more, then starts the consumers that have all their inputs.
  void finish(Job& job) {
    for (int p : job.producers) {
      Job& producer = jobs_[static_cast<std::size_t>(p)];
      if (producer.consumers_left.fetch_sub(1) == 1 && !producer.requested) producer.result.reset();
    }
    for (int c : job.consumers)
      if (jobs_[static_cast<std::size_t>(c)].waiting.fetch_sub(1) == 1) group_.run([this, c] { launch(c); });
  }

  EvaluatorState& impl_;
  const Graph& graph_;
  const EvalRequest& request_;
  OutputPolicy policy_;
  NodeKeys keys_;
  std::vector<std::string> requested_;
  std::unordered_set<const Node*> for_reports_only_;  // default request: nodes requested for their reports only
  std::deque<Job> jobs_;
  std::unordered_map<std::string, int> job_of_node_;
  std::unordered_map<CacheKey, int, CacheKeyHash> job_of_key_;
  std::unordered_map<const Node*, std::vector<bool>> needed_by_node_;
  std::unordered_map<CacheKey, std::vector<bool>, CacheKeyHash> needed_by_key_;
  tbb::task_group group_;
  std::mutex event_mutex_;
};

}  // namespace

struct Evaluator::Impl : EvaluatorState {
  using EvaluatorState::EvaluatorState;
};

Evaluator::Evaluator(EvaluatorOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Evaluator::~Evaluator() = default;

namespace {

// How far a status is from success, to report an instance by its worst inner node.
int severity(NodeStatus s) {
  switch (s) {
    case NodeStatus::Computed:
    case NodeStatus::Cached:
      return 0;
    case NodeStatus::Pending:
      return 1;
    case NodeStatus::Skipped:
      return 2;
    case NodeStatus::Cancelled:
      return 3;
    case NodeStatus::Failed:
      return 4;
  }
  return 4;
}

// The request on the expanded graph: an instance stands for the nodes feeding its outputs and its inner nodes
// with a Report output or that write files; a node domain of an instance applies to all its nodes.
EvalRequest expanded_request(const Graph& graph, const ExpandedGraph& expanded, const EvalRequest& request) {
  EvalRequest flat;
  flat.domain = request.domain;
  flat.cancel = request.cancel;
  flat.on_event = request.on_event;
  std::set<std::string> seen;
  auto add = [&](const std::string& id) {
    if (seen.insert(id).second) flat.nodes.push_back(id);
  };
  for (const auto& id : request.nodes) {
    const Node* node = graph.find(id);
    const auto outputs = expanded.outputs.find(id);
    if (!node || !node->type->subgraph || outputs == expanded.outputs.end()) {
      if (!expanded.graph.find(id)) throw GraphError("cannot evaluate node '" + id + "': no such node");
      add(id);
      continue;
    }
    for (const auto& ref : outputs->second) add(ref.node);
    for (const auto& inner : expanded.nodes.at(id)) {
      const NodeType& t = *expanded.graph.at(inner).type;
      if (is_output_node(t)) add(inner);
    }
  }
  for (const auto& [id, domain] : request.node_domains) {
    if (const auto inner = expanded.nodes.find(id); inner != expanded.nodes.end())
      for (const auto& n : inner->second) flat.node_domains.emplace(n, domain);
    else
      flat.node_domains[id] = domain;
  }
  // Given results are of plain nodes (the tiled build's stages run on the expanded graph).
  flat.given_results = request.given_results;
  flat.keep_in_memory = request.keep_in_memory;
  return flat;
}

}  // namespace

EvalResult Evaluator::evaluate(const Graph& graph, const EvalRequest& request) {
  if (!has_subgraphs(graph)) {
    std::lock_guard lock(impl_->evaluate_mutex);
    Run run(*impl_, graph, request);
    return run.execute();
  }
  // Instances are expanded into plain nodes first, so planning, caching and parallelism treat them like any
  // others. The result keeps the inner nodes' reports ("instance/inner") and adds one per instance.
  const ExpandedGraph expanded = expand_subgraphs(graph);
  const EvalRequest flat_request = expanded_request(graph, expanded, request);
  EvalResult result;
  {
    std::lock_guard lock(impl_->evaluate_mutex);
    Run run(*impl_, expanded.graph, flat_request);
    result = run.execute();
  }
  std::set<std::string> requested(request.nodes.begin(), request.nodes.end());
  if (request.nodes.empty()) {  // by default, instances whose outputs nothing reads give their outputs too
    std::set<std::string> feeding;
    for (const auto& n : graph.nodes())
      for (const auto& [port, link] : n.inputs) feeding.insert(link.node);
    for (const auto& n : graph.nodes())
      if (n.type->subgraph && !feeding.count(n.id)) requested.insert(n.id);
  }
  for (const auto& node : graph.nodes()) {
    if (!node.type->subgraph) continue;
    NodeReport report;
    bool touched = false;
    for (const auto& inner : expanded.nodes.at(node.id)) {
      const auto it = result.nodes.find(inner);
      if (it == result.nodes.end()) continue;
      if (!touched || severity(it->second.status) > severity(report.status)) {
        report.status = it->second.status;
        report.message = it->second.message.empty() ? std::string() : inner + ": " + it->second.message;
      }
      if (!touched) report.key = it->second.key;
      touched = true;
      report.milliseconds += it->second.milliseconds;
      report.output_bytes += it->second.output_bytes;
    }
    if (!touched) continue;
    // Computed if any inner node ran, Cached if all were found.
    if (severity(report.status) == 0)
      for (const auto& inner : expanded.nodes.at(node.id))
        if (const auto it = result.nodes.find(inner);
            it != result.nodes.end() && it->second.status == NodeStatus::Computed)
          report.status = NodeStatus::Computed;
    result.nodes[node.id] = report;
    if (!requested.count(node.id)) continue;
    std::vector<PortValue> values;
    bool complete = true;
    for (const auto& ref : expanded.outputs.at(node.id)) {
      const PortValue v = result.output(ref.node, ref.port, expanded.graph);
      complete = complete && has_value(v);
      values.push_back(v);
    }
    if (complete) result.outputs[node.id] = std::move(values);
  }
  // Outputs of inner nodes that were requested only on behalf of an instance are not the caller's.
  std::set<std::string> asked(request.nodes.begin(), request.nodes.end());
  for (auto it = result.outputs.begin(); it != result.outputs.end();)
    it = (!request.nodes.empty() && !asked.count(it->first)) ? result.outputs.erase(it) : std::next(it);
  return result;
}

void Evaluator::store_result(const CacheKey& key, std::shared_ptr<const CachedResult> result, bool in_memory) {
  if (in_memory) impl_->memory.insert(key, result, result->value_bytes());
  if (!impl_->disk) return;
  try {
    impl_->disk->store(key, *result);
    ++impl_->disk_writes;
  } catch (...) {
    ++impl_->disk_write_errors;  // the cache is an optimisation: a full disk must not fail the build
  }
}

std::shared_ptr<const CachedResult> Evaluator::find_result(const CacheKey& key, const NodeType& type,
                                                           const std::vector<bool>& needed) {
  return impl_->lookup(key, type, needed);
}

CacheStats Evaluator::cache_stats() const {
  CacheStats s;
  s.entries = impl_->memory.entries();
  s.bytes = impl_->memory.bytes();
  s.capacity = impl_->memory.capacity();
  s.evictions = impl_->memory.evictions();
  s.hits = impl_->hits.load();
  s.misses = impl_->misses.load();
  s.disk_hits = impl_->disk_hits.load();
  s.disk_rejected = impl_->disk_rejected.load();
  s.disk_writes = impl_->disk_writes.load();
  s.disk_write_errors = impl_->disk_write_errors.load();
  return s;
}

void Evaluator::clear_memory_cache() { impl_->memory.clear(); }

void Evaluator::set_output_policy(OutputPolicy policy) {
  std::lock_guard lock(impl_->evaluate_mutex);
  impl_->options.output = std::move(policy);
}

const EvaluatorOptions& Evaluator::options() const { return impl_->options; }

}  // namespace orogen
