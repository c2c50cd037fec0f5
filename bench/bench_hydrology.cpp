// Hydrology speed on a 4096 x 4096 fBm terrain (16 m spacing, 10 octaves of Perlin fBm; the counter
// `closed_fraction` gives the share of cells inside closed depressions).
//
//   orogen_bench_hydrology [--benchmark_filter=...] [--benchmark_repetitions=5]
//
// Each benchmark runs in a oneTBB arena of 1 thread (/threads:1 in the name; rate per second of process CPU
// time). The `.../wall` variants run with 1 thread and with every hardware thread (rate per second of wall
// time): their ratio is the speed-up on all cores. On a busy machine compare the single-thread figures.
// The figures (4096^2 fBm, one thread):
//   orogen_bench_hydrology --benchmark_filter='^(FillEpsilon|D8Accumulation|MFDAccumulation|RiverExtract)/threads:1'
//   --benchmark_min_time=1
// and the speed-up:
//   orogen_bench_hydrology --benchmark_filter='/wall/' --benchmark_min_time=1
// Measured:
//  - FillEpsilon / FillFlat: Priority-Flood with Zhou et al. 2016 queues, branch-free neighbour masks, closed
//    flags as bits, stale queue cells skipped on their bits, working array in huge pages (serial)
//  - Breach: complete breaching down the D8 tree of the epsilon surface (the epsilon fill, D8, the tree's order and
//    one pass; 18.7 M cells/s at 4096^2 on 2026-12-07, where the Priority-Flood breach it replaced took every cell
//    through the priority queue at 6-8 M cells/s, measured by the CLI)
//  - D8Accumulation: D8 receivers and donors (parallel rows) + dependency-counting accumulation (parallel)
//  - MFDAccumulation / DinfAccumulation: receivers and in-degrees (parallel) + accumulation in row bands merged up a
//  fixed tree (parallel)
//  - RiverExtract: the whole RiverExtract node function (fill, D8, accumulation, reaches, curves, mask)
//  - FillDepressionsNode / D8AccumulationNode: the nodes run as the evaluator runs them when only their primary
//    output is linked (ExecContext::output_requested), next to the library calls they wrap (FillEpsilon;
//    D8Accumulation, the node with fill off on the filled terrain); .../all: every output requested, as
//    before requested outputs. #27 item 8's figures:
//    orogen_bench_hydrology --benchmark_filter='^(FillEpsilon|FillDepressionsNode|D8Accumulation|D8AccumulationNode)'
//    Measured (process CPU, medians of 6 runs on the shared 2-core machine): FillDepressionsNode 583 ms against
//    FillEpsilon 590 ms (1.0x), all outputs 882 ms; D8AccumulationNode 343 ms against D8Accumulation 310 ms
//    (1.1x), all outputs 808 ms.
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "bench/heap_reuse.h"
#include "evaluator/run_node.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/rivers.h"
#include "nodes/noise/fbm.h"

namespace {

using namespace orogen;
using namespace orogen::hydrology;

constexpr int kSide = 4096;
constexpr double kSpacing = 16.0;

const Heightfield& terrain() {
  static const Heightfield h = [] {
    const Domain d = Domain::from_extent({0.0, 0.0}, {kSpacing * (kSide - 1), kSpacing * (kSide - 1)}, {kSide, kSide});
    noise::FbmParams p;
    p.feature_size = 12000.0;
    p.amplitude = 900.0;
    p.octaves = 10;
    p.seed = 5;
    return noise::fbm(d, p);
  }();
  return h;
}

const std::vector<float>& filled() {
  static const std::vector<float> z = [] {
    std::vector<float> v = terrain().data;
    fill_depressions(FlowGrid::of(terrain().domain), v, FlatMode::Epsilon);
    return v;
  }();
  return z;
}

double closed_fraction() {
  static const double f = [] {
    std::vector<float> flat = terrain().data;
    fill_depressions(FlowGrid::of(terrain().domain), flat, FlatMode::Flat);
    std::size_t n = 0;
    for (std::size_t c = 0; c < flat.size(); ++c) n += flat[c] > terrain().data[c];
    return static_cast<double>(n) / static_cast<double>(flat.size());
  }();
  return f;
}

template <class Fn>
void run(benchmark::State& state, Fn&& fn) {
  const int threads = static_cast<int>(state.range(0));
  tbb::task_arena arena(threads);
  const FlowGrid g = FlowGrid::of(terrain().domain);
  (void)filled();
  (void)closed_fraction();
  // One untimed call first: the timed ones then reuse memory the heap already holds (first-touch page faults
  // cost this VM up to a second on the first 4096^2 call).
  arena.execute([&] { fn(g); });
  for (auto _ : state) arena.execute([&] { fn(g); });
  state.counters["cells_per_s"] = benchmark::Counter(
      static_cast<double>(g.size()) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["closed_fraction"] = closed_fraction();
}

void FillEpsilon(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    std::vector<float> z = terrain().data;
    fill_depressions(g, z, FlatMode::Epsilon);
    benchmark::DoNotOptimize(z.data());
  });
}

void FillFlat(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    std::vector<float> z = terrain().data;
    fill_depressions(g, z, FlatMode::Flat);
    benchmark::DoNotOptimize(z.data());
  });
}

void Breach(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    std::vector<float> z = terrain().data;
    breach_depressions(g, z, FlatMode::Epsilon);
    benchmark::DoNotOptimize(z.data());
  });
}

void D8Accumulation(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    const D8Flow f = d8_flow(g, filled());
    const auto acc = accumulate_d8(g, f);
    benchmark::DoNotOptimize(acc.data());
  });
}

void MFDAccumulation(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    const auto acc = accumulate(g, filled(), RoutingOptions{FlowMethod::MFD, 1.1, {}});
    benchmark::DoNotOptimize(acc.data());
  });
}

void DinfAccumulation(benchmark::State& state) {
  run(state, [](const FlowGrid& g) {
    const auto acc = accumulate(g, filled(), RoutingOptions{FlowMethod::DInfinity, 1.1, {}});
    benchmark::DoNotOptimize(acc.data());
  });
}

void RiverExtract(benchmark::State& state) {
  run(state, [](const FlowGrid&) {
    RiverParams p;
    p.threshold = 2e6;  // about 7800 cells
    const RiverResult r = extract_rivers(terrain(), nullptr, p);
    benchmark::DoNotOptimize(r.curves.get());
  });
}

// The node with only `outputs` requested (empty: all of them) on `in`.
void node(benchmark::State& state, const std::vector<std::string>& outputs, const std::string& type,
          const std::map<std::string, ParamValue>& params, const Heightfield& in) {
  static std::map<const Heightfield*, HeightfieldPtr> shared;  // the input as a node input, copied once
  auto& ptr = shared[&in];
  if (!ptr) ptr = std::make_shared<const Heightfield>(in);
  run(state, [&](const FlowGrid&) {
    const NodeRun r = outputs.empty()
                          ? run_node(type, in.domain, params, {{"in", PortValue(ptr)}})
                          : run_node_for_outputs(outputs, type, in.domain, params, {{"in", PortValue(ptr)}});
    benchmark::DoNotOptimize(r.outputs.data());
  });
}

const Heightfield& filled_terrain() {
  static const Heightfield h = [] {
    Heightfield f(terrain().domain);
    f.data = filled();
    return f;
  }();
  return h;
}

void FillDepressionsNode(benchmark::State& state) { node(state, {"out"}, "FillDepressions", {}, terrain()); }
void FillDepressionsNodeAll(benchmark::State& state) { node(state, {}, "FillDepressions", {}, terrain()); }
const std::map<std::string, ParamValue> kD8NoFill{{"method", std::string("d8")}, {"fill", false}};
void D8AccumulationNode(benchmark::State& state) {
  node(state, {"out"}, "FlowAccumulation", kD8NoFill, filled_terrain());
}
void D8AccumulationNodeAll(benchmark::State& state) {
  node(state, {}, "FlowAccumulation", kD8NoFill, filled_terrain());
}

// One thread: rate per second of process CPU time. Two threads: per second of wall time (the CPU column then
// shows the process's total).
void args(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
  b->Arg(1);
}
// Speed-up on all cores: 1 thread and every hardware thread (at least 2), wall time.
void args2(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
  b->Arg(1)->Arg(std::max(2, static_cast<int>(std::thread::hardware_concurrency())));
}

BENCHMARK(FillEpsilon)->Apply(args);
BENCHMARK(FillFlat)->Apply(args);
BENCHMARK(Breach)->Apply(args);
BENCHMARK(D8Accumulation)->Apply(args);
BENCHMARK(MFDAccumulation)->Apply(args);
BENCHMARK(DinfAccumulation)->Apply(args);
BENCHMARK(RiverExtract)->Apply(args);
BENCHMARK(FillDepressionsNode)->Apply(args);
BENCHMARK(FillDepressionsNodeAll)->Name("FillDepressionsNode/all")->Apply(args);
BENCHMARK(D8AccumulationNode)->Apply(args);
BENCHMARK(D8AccumulationNodeAll)->Name("D8AccumulationNode/all")->Apply(args);
BENCHMARK(FillEpsilon)->Name("FillEpsilon/wall")->Apply(args2);
BENCHMARK(D8Accumulation)->Name("D8Accumulation/wall")->Apply(args2);
BENCHMARK(MFDAccumulation)->Name("MFDAccumulation/wall")->Apply(args2);
BENCHMARK(RiverExtract)->Name("RiverExtract/wall")->Apply(args2);

}  // namespace

int main(int argc, char** argv) {
  orogen::bench::keep_freed_memory_in_heap();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
