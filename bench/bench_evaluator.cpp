// Evaluator overhead: a 200-node graph of cheap nodes (20 Constants feeding a chain of 180 Adds) at 32x32.
//
//   FullEvaluation      a fresh evaluator each iteration: keys, planning, scheduling, caching and compute
//   EditNearEnd         one parameter edited 10 nodes before the end: 190 nodes come from the cache
//   Unchanged           nothing edited: the 200 keys are computed and the last node is a hit
//   DirectExecution     the same 200 node executions through run_node, without evaluator: the baseline
//
// Counters: us_per_node divides the wall-clock time by the 200 nodes of the graph (cpu_us_per_node the CPU
// time of all threads); us_per_run_node divides it by the nodes that actually ran. The evaluator's per-node overhead is
// FullEvaluation's us_per_node minus DirectExecution's.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "graph/graph.h"

namespace {

using namespace orogen;

constexpr int kConstants = 20;
constexpr int kAdds = 180;
constexpr int kNodes = kConstants + kAdds;
constexpr int kEdited = kAdds - 10;  // the Add whose parameter is edited: 10 Adds recompute

const Domain kDomain = Domain::from_extent({0.0, 0.0}, {1000.0, 1000.0}, {32, 32});

std::string id(const char* prefix, int k) {
  std::string s(prefix);
  s += std::to_string(k);
  return s;
}

Graph make_graph() {
  Graph g;
  for (int k = 0; k < kConstants; ++k) g.set_param(g.add_node("Constant", id("c", k)).id, "value", 1.0 + k);
  for (int k = 0; k < kAdds; ++k) {
    const auto n = g.add_node("Add", id("add", k)).id;
    g.set_param(n, "weight_b", 0.5 + 0.001 * k);
    g.connect({k == 0 ? std::string("c0") : id("add", k - 1), "out"}, n, "a");
    g.connect({id("c", k % kConstants), "out"}, n, "b");
  }
  return g;
}

EvalRequest last_node() {
  EvalRequest r;
  r.domain = kDomain;
  r.nodes = {id("add", kAdds - 1)};
  return r;
}

EvaluatorOptions with_threads(int threads) {
  EvaluatorOptions o;
  o.threads = threads;
  return o;
}

// Wall-clock and process CPU time (all threads) of the measured loop, for the per-node counters. Both are
// reported because on a loaded machine the wall-clock time includes waiting for a core.
class LoopTimer {
 public:
  LoopTimer() : wall_(std::chrono::steady_clock::now()), cpu_(process_cpu_seconds()) {}
  void report(benchmark::State& state, int nodes_run) const {
    const double wall_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - wall_).count();
    const double cpu_us = (process_cpu_seconds() - cpu_) * 1e6;
    const double runs = static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
    state.counters["us_per_node"] = wall_us / (runs * kNodes);
    state.counters["cpu_us_per_node"] = cpu_us / (runs * kNodes);
    state.counters["us_per_run_node"] = wall_us / (runs * nodes_run);
  }

 private:
  static double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  std::chrono::steady_clock::time_point wall_;
  double cpu_;
};

void FullEvaluation(benchmark::State& state) {
  const Graph g = make_graph();
  const auto request = last_node();
  const LoopTimer timer;
  for (auto _ : state) {
    Evaluator ev(with_threads(static_cast<int>(state.range(0))));
    auto r = ev.evaluate(g, request);
    if (!r.ok()) state.SkipWithError("evaluation failed");
    benchmark::DoNotOptimize(r);
  }
  timer.report(state, kNodes);
}

void EditNearEnd(benchmark::State& state) {
  Graph g = make_graph();
  const auto request = last_node();
  Evaluator ev(with_threads(static_cast<int>(state.range(0))));
  ev.evaluate(g, request);
  double w = 2.0;
  const LoopTimer timer;
  for (auto _ : state) {
    w += 1e-3;  // a value never seen before, so the edited node and its downstream really recompute
    g.set_param(id("add", kEdited), "weight_b", w);
    auto r = ev.evaluate(g, request);
    if (!r.ok() || r.nodes.at(id("add", kEdited)).status != NodeStatus::Computed)
      state.SkipWithError("unexpected plan");
    benchmark::DoNotOptimize(r);
  }
  timer.report(state, kAdds - kEdited);
}

void Unchanged(benchmark::State& state) {
  const Graph g = make_graph();
  const auto request = last_node();
  Evaluator ev(with_threads(static_cast<int>(state.range(0))));
  ev.evaluate(g, request);
  const LoopTimer timer;
  for (auto _ : state) {
    auto r = ev.evaluate(g, request);
    benchmark::DoNotOptimize(r);
  }
  timer.report(state, 1);
}

void DirectExecution(benchmark::State& state) {
  const Graph g = make_graph();
  const auto order = g.topological_order();
  const LoopTimer timer;
  for (auto _ : state) {
    std::map<std::string, PortValue> values;
    for (const auto& nid : order) {
      const Node& n = g.at(nid);
      std::map<std::string, PortValue> inputs;
      for (const auto& [port, link] : n.inputs) inputs[port] = values.at(link.node);
      values[nid] = run_node(n.type->name, kDomain, n.params, inputs).outputs.at(0);
    }
    benchmark::DoNotOptimize(values);
  }
  timer.report(state, kNodes);
}

BENCHMARK(FullEvaluation)->Arg(1)->Arg(0)->ArgName("threads")->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(EditNearEnd)->Arg(1)->Arg(0)->ArgName("threads")->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(Unchanged)->Arg(1)->Arg(0)->ArgName("threads")->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(DirectExecution)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
