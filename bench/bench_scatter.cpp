// PoissonDisk speed: points per second over a 10 km square at r = 5 m (about 2.8 M points), on one thread
// and on all cores; and the same over a 2 km square (quick runs).
//
//   orogen_bench_scatter --benchmark_filter=10km
//
// Reported: points per second of wall time (items_per_second; the one-thread figure is the per-core speed,
// the all-cores one over it the speed-up) and the calling thread's CPU time. Default parameters (attempts 8,
// gap filling on): the constant-radius fast path. On a shared machine compare interleaved runs only.
#include <benchmark/benchmark.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "nodes/scatter/poisson_disk.h"

namespace {

using namespace orogen;

void run(benchmark::State& state, double side, int threads, bool fill) {
  PoissonParams p;
  p.classes = {{5.0, 0, nullptr}};
  p.fill_gaps = fill;
  p.seed = 1;
  tbb::task_arena arena(threads);
  std::size_t points = 0;
  for (auto _ : state) {
    arena.execute([&] {
      const Points pts = poisson_disk({0, 0}, {side, side}, p);
      points = pts.size();
      benchmark::DoNotOptimize(pts.position.data());
    });
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points));
  state.counters["points"] = static_cast<double>(points);
}

void BM_Poisson10km_1thread(benchmark::State& s) { run(s, 10000.0, 1, true); }
void BM_Poisson10km_allcores(benchmark::State& s) { run(s, 10000.0, tbb::info::default_concurrency(), true); }
void BM_Poisson2km_1thread(benchmark::State& s) { run(s, 2000.0, 1, true); }
void BM_Poisson2km_allcores(benchmark::State& s) { run(s, 2000.0, tbb::info::default_concurrency(), true); }
void BM_Poisson2km_1thread_nofill(benchmark::State& s) { run(s, 2000.0, 1, false); }

BENCHMARK(BM_Poisson10km_1thread)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_Poisson10km_allcores)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_Poisson2km_1thread)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Poisson2km_allcores)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Poisson2km_1thread_nofill)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
