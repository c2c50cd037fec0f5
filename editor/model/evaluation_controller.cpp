#include "editor/model/evaluation_controller.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "graph/idle_nodes.h"

namespace orogen::editor {

namespace {
// The entries of a map keyed by expanded ids that lie under `prefix`, keyed by the rest of the id.
template <class T>
std::map<std::string, T> under_prefix(std::map<std::string, T> in, const std::string& prefix) {
  if (prefix.empty()) return in;
  std::map<std::string, T> out;
  for (auto& [id, v] : in)
    if (id.size() > prefix.size() && id.compare(0, prefix.size(), prefix) == 0)
      out.emplace(id.substr(prefix.size()), std::move(v));
  return out;
}
}  // namespace

std::string_view to_string(NodeRunState::Phase phase) {
  switch (phase) {
    case NodeRunState::Phase::Unknown:
      return "not evaluated";
    case NodeRunState::Phase::Stale:
      return "out of date";
    case NodeRunState::Phase::Computing:
      return "computing";
    case NodeRunState::Phase::Computed:
      return "up to date";
    case NodeRunState::Phase::Cached:
      return "cached";
    case NodeRunState::Phase::Failed:
      return "failed";
    case NodeRunState::Phase::Skipped:
      return "skipped";
  }
  return "?";
}

EvaluatorOptions EvaluationController::preview_defaults() {
  EvaluatorOptions o;
  o.cache_bytes = std::size_t(1) << 30;  // previews are small; many edits' worth of them fit in 1 GiB
  return o;
}

EvaluatorOptions EvaluationController::build_defaults() {
  EvaluatorOptions o;
  o.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
  return o;
}

EvaluationController::EvaluationController(EvaluatorOptions preview_options, EvaluatorOptions build_options)
    : preview_evaluator_(std::move(preview_options)), build_evaluator_(std::move(build_options)) {
  preview_thread_ = std::thread([this] { preview_loop(); });
}

EvaluationController::~EvaluationController() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    preview_cancel_.cancel();
    build_cancel_.cancel();
  }
  wake_.notify_all();
  if (preview_thread_.joinable()) preview_thread_.join();
  if (build_thread_.joinable()) build_thread_.join();
}

void EvaluationController::set_preview_resolution(int samples) {
  std::lock_guard lock(mutex_);
  preview_resolution_ = std::clamp(samples, 16, 8192);
}

int EvaluationController::preview_resolution() const {
  std::lock_guard lock(mutex_);
  return preview_resolution_;
}

Domain EvaluationController::preview_domain(const GraphDomain& domain) const {
  const int n = preview_resolution();
  const double longer = std::max(domain.size.x, domain.size.y);
  // At most the graph's own resolution: a preview never computes more than the build.
  const auto along = [&](double size, int full) {
    const int scaled = std::max(2, static_cast<int>(std::lround(n * size / longer)));
    return std::min(scaled, std::max(full, 2));
  };
  return Domain::from_extent(domain.origin, domain.size,
                             {along(domain.size.x, domain.resolution.x), along(domain.size.y, domain.resolution.y)});
}

void EvaluationController::set_context(std::string prefix) {
  std::lock_guard lock(mutex_);
  if (prefix == context_) return;
  context_ = std::move(prefix);
  states_.clear();
  requested_keys_.clear();
  preview_.reset();
  thumbnails_.reset();
}

void EvaluationController::request_preview(const Graph& graph, std::vector<std::string> nodes, std::uint64_t revision) {
  Job job{graph, std::move(nodes), revision, preview_domain(graph.domain), context_};
  for (auto& id : job.nodes) id = job.prefix + id;
  // Which results the edit made stale: the nodes whose key changed.
  std::map<std::string, CacheKey> keys;
  try {
    keys = under_prefix(compute_cache_keys(job.graph, job.domain), job.prefix);
  } catch (const std::exception&) {
    // An invalid graph (the evaluator reports why when it runs); every state becomes stale.
  }
  {
    std::lock_guard lock(mutex_);
    // Inner nodes of instances ("instance/inner") stay while their instance does.
    auto exists = [&](const std::string& id) {
      return job.prefix.empty() ? job.graph.find(id) != nullptr : keys.count(id) > 0;
    };
    std::erase_if(states_, [&](const auto& kv) { return !exists(kv.first.substr(0, kv.first.find('/'))); });
    std::vector<std::string> ids;
    if (job.prefix.empty())
      for (const auto& node : job.graph.nodes()) ids.push_back(node.id);
    else
      for (const auto& [id, key] : keys)
        if (id.find('/') == std::string::npos) ids.push_back(id);
    for (const auto& [id, state] : states_)
      if (id.find('/') != std::string::npos) ids.push_back(id);
    for (const auto& id : ids) {
      auto& s = states_[id];
      const auto k = keys.find(id);
      bool current = k != keys.end() && s.key && *s.key == k->second &&
                     (s.phase == NodeRunState::Phase::Computed || s.phase == NodeRunState::Phase::Cached);
      if (s.by_build) {
        // A build's state holds until an edit changes the node (its key differs from the last request's).
        const auto before = requested_keys_.find(id);
        current = k != keys.end() && before != requested_keys_.end() && before->second == k->second;
        if (!current) s.by_build = false;
      }
      if (!current && s.phase != NodeRunState::Phase::Unknown) s.phase = NodeRunState::Phase::Stale;
      if (!current) s.progress = 0.0;
    }
    requested_keys_ = std::move(keys);
    pending_ = std::move(job);
    if (running_ || thumbnails_running_) preview_cancel_.cancel();
  }
  wake_.notify_all();
}

std::shared_ptr<const PreviewResult> EvaluationController::preview() const {
  std::lock_guard lock(mutex_);
  return preview_;
}

bool EvaluationController::preview_busy() const {
  std::lock_guard lock(mutex_);
  return running_ || pending_.has_value();
}

std::map<std::string, NodeRunState> EvaluationController::node_states() const {
  std::lock_guard lock(mutex_);
  std::map<std::string, NodeRunState> out = states_;
  // Instances (every prefix "a", "a/b" of an inner id) get the state of their inner nodes.
  std::set<std::string> instances;
  for (const auto& [id, state] : states_)
    for (std::size_t slash = id.find('/'); slash != std::string::npos; slash = id.find('/', slash + 1))
      instances.insert(id.substr(0, slash));
  for (const auto& instance : instances) out[instance] = state_of(instance);
  return out;
}

NodeRunState EvaluationController::node_state(const std::string& id) const {
  std::lock_guard lock(mutex_);
  return state_of(id);
}

NodeRunState EvaluationController::state_of(const std::string& id) const {
  auto it = states_.find(id);
  NodeRunState own = it == states_.end() ? NodeRunState{} : it->second;
  // A subgraph instance runs as its inner nodes ("id/inner", at any depth): its state is the worst of
  // theirs, its time their sum, its message the first inner failure's.
  const std::string prefix = id + "/";
  auto inner = states_.lower_bound(prefix);
  if (inner == states_.end() || inner->first.compare(0, prefix.size(), prefix) != 0) return own;
  auto rank = [](NodeRunState::Phase p) {
    switch (p) {
      case NodeRunState::Phase::Unknown:
        return 0;
      case NodeRunState::Phase::Cached:
        return 1;
      case NodeRunState::Phase::Computed:
        return 2;
      case NodeRunState::Phase::Stale:
        return 3;
      case NodeRunState::Phase::Computing:
        return 4;
      case NodeRunState::Phase::Skipped:
        return 5;
      case NodeRunState::Phase::Failed:
        return 6;
    }
    return 0;
  };
  NodeRunState sum;
  sum.key = own.key;
  double progress = 0.0;
  int known = 0;
  for (; inner != states_.end() && inner->first.compare(0, prefix.size(), prefix) == 0; ++inner) {
    const NodeRunState& s = inner->second;
    if (s.phase == NodeRunState::Phase::Unknown) continue;  // not needed for what was requested
    if (rank(s.phase) > rank(sum.phase)) {
      sum.phase = s.phase;
      if (!s.message.empty()) sum.message = "inner node '" + inner->first.substr(prefix.size()) + "': " + s.message;
    }
    sum.milliseconds += s.milliseconds;
    sum.by_build = sum.by_build || s.by_build;
    progress += s.phase == NodeRunState::Phase::Computing ? s.progress : 1.0;
    ++known;
  }
  if (known == 0) return own;
  sum.progress = progress / known;
  return sum;
}

void EvaluationController::on_preview_event(const EvalEvent& e) {
  std::lock_guard lock(mutex_);
  const std::string& prefix = running_prefix_;
  if (e.node.size() <= prefix.size() || e.node.compare(0, prefix.size(), prefix) != 0) return;  // outside the context
  const std::string id = e.node.substr(prefix.size());
  auto& s = states_[id];
  const auto key = running_keys_.find(id);
  switch (e.kind) {
    case EvalEvent::Kind::Started:
      s.phase = NodeRunState::Phase::Computing;
      s.progress = 0.0;
      s.by_build = false;
      break;
    case EvalEvent::Kind::Progress:
      s.progress = e.fraction;
      break;
    case EvalEvent::Kind::Finished:
      s.phase = NodeRunState::Phase::Computed;
      s.progress = 1.0;
      s.milliseconds = e.milliseconds;
      s.message.clear();
      if (key != running_keys_.end()) s.key = key->second;
      break;
    case EvalEvent::Kind::Cached:
      s.phase = NodeRunState::Phase::Cached;
      s.progress = 1.0;
      s.message.clear();
      if (key != running_keys_.end()) s.key = key->second;
      break;
    case EvalEvent::Kind::Failed:
      s.phase = NodeRunState::Phase::Failed;
      s.message = e.message;
      s.key.reset();
      break;
    case EvalEvent::Kind::Skipped:
      s.phase = NodeRunState::Phase::Skipped;
      s.message = "not evaluated: upstream node '" + e.message + "' failed";
      s.key.reset();
      break;
    case EvalEvent::Kind::Cancelled:
      s.phase = NodeRunState::Phase::Stale;
      s.progress = 0.0;
      break;
  }
}

void EvaluationController::preview_loop() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_.has_value() || pending_thumbnails_.has_value(); });
      if (stop_) return;
      if (!pending_) {
        // Nothing to preview: thumbnails.
        Job t = std::move(*pending_thumbnails_);
        pending_thumbnails_.reset();
        thumbnails_running_ = true;
        preview_cancel_.reset();
        lock.unlock();
        run_thumbnails(std::move(t));
        continue;
      }
      job = std::move(*pending_);
      pending_.reset();
      running_ = true;
      preview_cancel_.reset();
      running_keys_.clear();
    }
    std::map<std::string, CacheKey> keys;
    try {
      keys = under_prefix(compute_cache_keys(job.graph, job.domain), job.prefix);
    } catch (const std::exception&) {}
    {
      std::lock_guard lock(mutex_);
      running_keys_ = std::move(keys);
      running_prefix_ = job.prefix;
    }

    if (job.nodes.empty()) {
      // Everything visible: the nodes nothing reads, except writers (a preview never writes files).
      for (const auto& node : job.graph.nodes())
        if (!node.type->writes_files && job.graph.downstream(node.id).empty()) job.nodes.push_back(node.id);
    }
    auto result = std::make_shared<PreviewResult>();
    result->revision = job.revision;
    result->domain = job.domain;
    result->requested = job.nodes;
    bool cancelled = false;
    try {
      EvalRequest request;
      request.domain = job.domain;
      request.nodes = job.nodes;
      request.cancel = &preview_cancel_;
      request.on_event = [this](const EvalEvent& e) { on_preview_event(e); };
      EvalResult r = preview_evaluator_.evaluate(job.graph, request);
      cancelled = r.cancelled;
      result->outputs = under_prefix(std::move(r.outputs), job.prefix);
      result->reports = under_prefix(std::move(r.nodes), job.prefix);
      result->milliseconds = r.milliseconds;
      if (!job.prefix.empty())
        for (auto& id : result->requested) id = id.substr(job.prefix.size());
    } catch (const std::exception& e) {
      result->error = e.what();
    }

    {
      std::lock_guard lock(mutex_);
      running_ = false;
      // A result of another context (the user left or entered meanwhile) is not this one's.
      if (job.prefix != context_) cancelled = true;
      if (!cancelled) {
        result->serial = ++serial_;
        preview_ = std::move(result);
      }
    }
    idle_.notify_all();
    notify_change();
  }
}

void EvaluationController::request_thumbnails(const Graph& graph, std::uint64_t revision, const Graph* level) {
  Domain domain = preview_domain(graph.domain);
  {
    const double longer = std::max(graph.domain.size.x, graph.domain.size.y);
    const auto along = [&](double size) {
      return std::max(2, static_cast<int>(std::lround(kThumbnailResolution * size / longer)));
    };
    domain = Domain::from_extent(graph.domain.origin, graph.domain.size,
                                 {along(graph.domain.size.x), along(graph.domain.size.y)});
  }
  Job job{graph, {}, revision, domain, context_};
  for (const auto& node : (level && !context_.empty() ? *level : graph).nodes())
    if (!node.type->writes_files && !node.type->outputs.empty()) job.nodes.push_back(job.prefix + node.id);
  {
    std::lock_guard lock(mutex_);
    pending_thumbnails_ = std::move(job);
    if (thumbnails_running_) preview_cancel_.cancel();
  }
  wake_.notify_all();
}

std::shared_ptr<const Thumbnails> EvaluationController::thumbnails() const {
  std::lock_guard lock(mutex_);
  return thumbnails_;
}

void EvaluationController::run_thumbnails(Job job) {  // NOLINT(performance-unnecessary-value-param)
  auto result = std::make_shared<Thumbnails>();
  result->revision = job.revision;
  result->domain = job.domain;
  bool cancelled = false;
  try {
    EvalRequest request;
    request.domain = job.domain;
    request.nodes = job.nodes;
    request.cancel = &preview_cancel_;
    EvalResult r = preview_evaluator_.evaluate(job.graph, request);
    cancelled = r.cancelled;
    result->outputs = under_prefix(std::move(r.outputs), job.prefix);
  } catch (const std::exception&) {
    // An invalid graph: no thumbnails (the preview reports why).
  }
  {
    std::lock_guard lock(mutex_);
    thumbnails_running_ = false;
    if (!cancelled && job.prefix != context_) {
      // Another context's: dropped, not resumed.
    } else if (!cancelled) {
      result->serial = ++serial_;
      thumbnails_ = std::move(result);
    } else if (!pending_thumbnails_ && !stop_ && job.prefix == context_) {
      pending_thumbnails_ = std::move(job);  // cut short by a preview: resumed after it (from the cache)
    }
  }
  idle_.notify_all();
  if (!cancelled) notify_change();
}

void EvaluationController::start_build(const Graph& graph, const OutputPolicy& policy) {
  std::lock_guard lock(mutex_);
  if (build_.running) return;
  if (build_thread_.joinable()) build_thread_.join();  // the previous build has finished
  build_evaluator_.set_output_policy(policy);
  build_cancel_.reset();
  build_ = BuildStatus{};
  build_.running = true;
  build_.domain = graph.domain.to_domain();
  build_node_progress_.clear();
  build_total_ = std::max<std::size_t>(1, graph.nodes().size());
  build_thread_ = std::thread([this, g = graph, d = build_.domain]() mutable { run_build(std::move(g), d); });
}

void EvaluationController::cancel_build() {
  std::lock_guard lock(mutex_);
  if (build_.running) build_cancel_.cancel();
}

BuildStatus EvaluationController::build_status() const {
  std::lock_guard lock(mutex_);
  return build_;
}

void EvaluationController::run_build(Graph graph, Domain domain) {
  EvalRequest request;
  request.domain = domain;
  request.cancel = &build_cancel_;
  request.on_event = [this](const EvalEvent& e) {
    std::lock_guard lock(mutex_);
    switch (e.kind) {
      case EvalEvent::Kind::Started:
        build_node_progress_[e.node] = 0.0;
        build_.current = e.node;
        break;
      case EvalEvent::Kind::Progress:
        build_node_progress_[e.node] = e.fraction;
        build_.current = e.node;
        break;
      default:
        build_node_progress_[e.node] = 1.0;
        break;
    }
    double done = 0.0;
    for (const auto& [id, f] : build_node_progress_) done += f;
    build_.fraction = std::min(1.0, done / static_cast<double>(build_total_));
  };
  BuildStatus status;
  status.domain = domain;
  status.left_out = idle_unwired_nodes(graph);
  std::map<std::string, NodeReport> reports;
  try {
    EvalResult r = build_evaluator_.evaluate(graph, request);
    status.cancelled = r.cancelled;
    status.ok = r.ok();
    status.milliseconds = r.milliseconds;
    for (const auto& [id, report] : r.nodes)
      if (report.status == NodeStatus::Failed) status.failures.push_back(id + ": " + report.message);
    reports = std::move(r.nodes);
  } catch (const std::exception& e) {
    status.ok = false;
    status.failures.push_back(e.what());
  }
  {
    std::lock_guard lock(mutex_);
    status.running = false;
    status.finished = true;
    status.fraction = status.ok ? 1.0 : build_.fraction;
    build_ = std::move(status);
    // What the build did shows on the nodes: its failures, and the nodes only a build evaluates (writers).
    for (const auto& [id, report] : reports) {
      const Node* node = graph.find(id);
      auto& s = states_[id];
      if (report.status == NodeStatus::Failed) {
        s.phase = NodeRunState::Phase::Failed;
        s.message = "build: " + report.message;
        s.key.reset();
        s.by_build = true;
      } else if ((report.status == NodeStatus::Computed || report.status == NodeStatus::Cached) &&
                 ((node && node->type->writes_files) || s.phase == NodeRunState::Phase::Unknown ||
                  s.phase == NodeRunState::Phase::Failed || s.phase == NodeRunState::Phase::Skipped)) {
        s.phase = report.status == NodeStatus::Computed ? NodeRunState::Phase::Computed : NodeRunState::Phase::Cached;
        s.progress = 1.0;
        s.milliseconds = report.milliseconds;
        s.message.clear();
        s.key.reset();
        s.by_build = true;  // until an edit changes it
      }
    }
  }
  idle_.notify_all();
  notify_change();
}

void EvaluationController::wait_idle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] {
    return !running_ && !pending_.has_value() && !thumbnails_running_ && !pending_thumbnails_.has_value() &&
           !build_.running;
  });
}

void EvaluationController::set_on_change(std::function<void()> fn) {
  std::lock_guard lock(notify_mutex_);
  on_change_ = std::move(fn);
}

void EvaluationController::notify_change() {
  std::lock_guard lock(notify_mutex_);  // set_on_change({}) returns only once no call is in flight
  if (on_change_) on_change_();
}

}  // namespace orogen::editor
