// libFuzzer target: whole graphs of the newer node families (island, plants, rocks, scatter, climate, texture,
// erosion) built from the input bytes and evaluated under a time and a memory budget, so hangs and blow-ups
// are found as crashes are:
// - every numeric parameter at its declared minimum or maximum, just inside them, at its default or anywhere
//   in its range; enums from their choices; links only between compatible ports (an FBM terrain first, so
//   every heightfield input has a producer);
// - evaluated on a small domain with --max-memory's refusal (EvaluatorOptions::max_memory, from the cost
//   model) at kMemoryBudget, and cancelled after kTimeBudget; a run that has not returned kCancelBound after
//   the cancel aborts (a hang: a loop that does not poll), and one that allocates beyond libFuzzer's
//   -malloc_limit_mb / -rss_limit_mb fails (a blow-up the estimate did not refuse).
// Writers are left out (the writer tests cover them); results and clear errors are both fine.
// Seeds: tests/fuzz/graph_eval_seeds (any bytes work: every byte string decodes to a graph).
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "evaluator/evaluator.h"
#include "graph/graph.h"
#include "graph/graph_file.h"
#include "graph/registry.h"

namespace {

using namespace orogen;

constexpr auto kTimeBudget = std::chrono::milliseconds(300);
constexpr auto kCancelBound = std::chrono::seconds(5);  // under ASan + UBSan
constexpr std::uint64_t kMemoryBudget = 256ull << 20;
constexpr int kMaxNodes = 6;

const std::vector<const NodeType*>& family_types() {
  static const std::vector<const NodeType*> types = [] {
    const std::set<std::string> families = {"island", "plants", "rocks", "scatter", "climate", "texture", "erosion"};
    std::vector<const NodeType*> out;
    for (const NodeType* t : NodeRegistry::instance().all())
      if (families.count(t->category) && !t->writes_files) out.push_back(t);
    return out;
  }();
  return types;
}

// A value of `p` at or near the ends of its range, its default, or anywhere inside.
ParamValue fuzzed_value(const ParamDecl& p, FuzzedDataProvider& in) {
  if (p.type == ParamType::Enum && !p.choices.empty())
    return p.choices[in.ConsumeIntegralInRange<std::size_t>(0, p.choices.size() - 1)];
  if (p.type == ParamType::Bool) return in.ConsumeBool();
  if ((p.type != ParamType::Float && p.type != ParamType::Int) || !p.min || !p.max) return p.default_value;
  const double lo = *p.min, hi = *p.max;
  double v = 0.0;
  switch (in.ConsumeIntegralInRange(0, 5)) {
    case 0:
      v = lo;
      break;
    case 1:
      v = hi;
      break;
    case 2:
      v = lo + (hi - lo) * 1e-6;
      break;
    case 3:
      v = hi - (hi - lo) * 1e-6;
      break;
    case 4:
      return p.default_value;
    default:
      v = lo + (hi - lo) * in.ConsumeProbability<double>();
      break;
  }
  if (p.type == ParamType::Int) return static_cast<std::int64_t>(v);
  return v;
}

Graph build(FuzzedDataProvider& in) {
  Graph g;
  Node& terrain = g.add_node("FBM", "terrain");
  terrain.params["amplitude"] = in.ConsumeFloatingPointInRange(0.0, 3000.0);
  std::vector<std::string> ids = {"terrain"};
  const int count = in.ConsumeIntegralInRange(1, kMaxNodes);
  for (int k = 0; k < count && in.remaining_bytes() > 0; ++k) {
    const auto& types = family_types();
    const NodeType* type = types[in.ConsumeIntegralInRange<std::size_t>(0, types.size() - 1)];
    const std::string id = "n" + std::to_string(k);
    Node& n = g.add_node(*type, id);
    for (const auto& p : type->params) {
      if (p.type == ParamType::Path || p.output_file || !in.ConsumeBool()) continue;
      ParamValue v = fuzzed_value(p, in);
      if (p.check(v).empty()) n.params[p.name] = std::move(v);
    }
    // Each input from an earlier node's output of its type, when there is one (optional inputs maybe).
    for (const auto& port : type->inputs) {
      if (port.optional && in.ConsumeBool()) continue;
      std::vector<PortRef> candidates;
      for (const std::string& from : ids)
        for (const auto& out : g.at(from).type->outputs)
          if (out.type == port.type) candidates.push_back({from, out.name});
      if (candidates.empty()) continue;
      const PortRef& from = candidates[in.ConsumeIntegralInRange<std::size_t>(0, candidates.size() - 1)];
      if (g.check_link(from, id, port.name).empty()) g.connect(from, id, port.name);
    }
    ids.push_back(id);
  }
  return g;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const int side = in.ConsumeIntegralInRange(2, 65);
  const double extent = in.ConsumeFloatingPointInRange(1.0, 1e5);
  const Domain domain = Domain::from_extent({0, 0}, {extent, extent}, {side, side});
  const Graph graph = build(in);
  // Reproducing a finding: OROGEN_FUZZ_PRINT=1 prints the graph and the domain before they are evaluated.
  if (std::getenv("OROGEN_FUZZ_PRINT"))
    std::fprintf(stderr, "domain %d x %d samples over %g m\n%s\n", side, side, extent, serialize_graph(graph).c_str());

  EvaluatorOptions options;
  options.threads = 1;
  options.max_memory = kMemoryBudget;
  options.cache_bytes = 64ull << 20;
  Evaluator evaluator(options);
  EvalRequest request;
  request.domain = domain;
  for (const Node& node : graph.nodes()) request.nodes.push_back(node.id);
  CancelToken cancel;
  request.cancel = &cancel;

  // The watchdog: cancel after the time budget, abort if the cancel is not honoured within the bound.
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  std::thread watchdog([&] {
    std::unique_lock lock(m);
    if (cv.wait_for(lock, kTimeBudget, [&] { return done; })) return;
    cancel.cancel();
    if (cv.wait_for(lock, kCancelBound, [&] { return done; })) return;
    std::fprintf(stderr, "fuzz_graph_eval: the evaluation did not stop within %lld s of the cancel\n",
                 static_cast<long long>(kCancelBound.count()));
    std::abort();
  });
  try {
    (void)evaluator.evaluate(graph, request);
  } catch (const GraphError&) {}
  {
    std::lock_guard lock(m);
    done = true;
  }
  cv.notify_one();
  watchdog.join();
  return 0;
}
