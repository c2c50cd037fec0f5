// Terrain meshing: heightfield_tin (greedy insertion + collapses) on the island of graphs/terrain.json
// ("elevation", 4096 m square) sampled at 257^2 .. 4097^2, with a vertical error bound of 0.5% of the height
// range (heights quantised to 16 bits first, like a 16-bit PNG).
//
//   Tin/<n>        the node's algorithm: greedy insertion, then half-edge collapses
//   Greedy/<n>     greedy insertion alone (Garland & Heckbert 1995), for comparison
//   Mesh/<n>       Tin plus the OpenMesh mesh with normals and colours (what HeightfieldToMesh does)
//
// Counters: triangles, vertices, peak_MB (the largest heap in use during one call, input excluded, counted by
// replacing operator new), max_error_m (measured) and bound_m. Run on one core, e.g.
//   taskset -c 0 build/release/bench/orogen_bench_meshing --benchmark_filter='Tin'
// and read the CPU column: the machine may be shared.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <new>

#include <benchmark/benchmark.h>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "nodes/geometry/heightfield_mesh.h"
#include "nodes/geometry/terrain_tin.h"

// --- heap accounting -------------------------------------------------------------------------------------
namespace {
std::atomic<long long> g_in_use{0}, g_peak{0};
void count(long long delta) {
  const long long now = g_in_use.fetch_add(delta, std::memory_order_relaxed) + delta;
  long long peak = g_peak.load(std::memory_order_relaxed);
  while (now > peak && !g_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {}
}
void* allocate(std::size_t n) {
  void* p = std::malloc(n + 16);
  if (!p) throw std::bad_alloc();
  *static_cast<std::size_t*>(p) = n;
  count(static_cast<long long>(n));
  return static_cast<char*>(p) + 16;
}
void release(void* p) noexcept {
  if (!p) return;
  char* base = static_cast<char*>(p) - 16;
  count(-static_cast<long long>(*reinterpret_cast<std::size_t*>(base)));
  std::free(base);
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }

namespace {

using namespace orogen;

struct Terrain {
  Heightfield height;
  double bound = 0.0;
};

const Terrain& terrain(int n) {
  static std::mutex mutex;
  static std::map<int, Terrain> cache;
  std::lock_guard lock(mutex);
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  auto loaded = load_graph_file(std::string(OROGEN_SOURCE_DIR) + "/graphs/terrain.json");
  if (!loaded.ok()) throw std::runtime_error(loaded.error_text());
  Evaluator evaluator;
  EvalRequest request;
  request.domain = Domain::from_extent({0.0, 0.0}, {4096.0, 4096.0}, {n, n});
  request.nodes = {"elevation"};
  const auto result = evaluator.evaluate(*loaded.graph, request);
  const auto h = std::get<HeightfieldPtr>(result.output("elevation", "out", *loaded.graph));
  Terrain t{*h, 0.0};
  const auto [lo, hi] = std::minmax_element(t.height.data.begin(), t.height.data.end());
  const double zmin = *lo, range = *hi - *lo;
  for (float& z : t.height.data)
    z = static_cast<float>(zmin + std::round((z - zmin) / range * 65535.0) / 65535.0 * range);
  t.bound = 0.005 * range;
  return cache.emplace(n, std::move(t)).first->second;
}

void report(benchmark::State& state, std::size_t triangles, std::size_t vertices, double error, double bound,
            long long peak_bytes) {
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["peak_MB"] = static_cast<double>(peak_bytes) / (1 << 20);
  state.counters["max_error_m"] = error;
  state.counters["bound_m"] = bound;
}

void run_tin(benchmark::State& state, bool simplify) {
  const Terrain& t = terrain(static_cast<int>(state.range(0)));
  TinOptions options;
  options.max_error = t.bound;
  options.simplify = simplify;
  Tin tin;
  long long peak = 0;
  for (auto _ : state) {
    tin = Tin();
    const long long base = g_in_use.load();
    g_peak = base;
    tin = heightfield_tin(t.height, options);
    peak = std::max(peak, g_peak.load() - base);
    benchmark::DoNotOptimize(tin.triangles.data());
  }
  report(state, tin.triangles.size(), tin.samples.size(), tin.max_error, t.bound, peak);
}

void TinBench(benchmark::State& state) { run_tin(state, true); }
void GreedyBench(benchmark::State& state) { run_tin(state, false); }

void MeshNode(benchmark::State& state) {
  const Terrain& t = terrain(static_cast<int>(state.range(0)));
  TinOptions options;
  options.max_error = t.bound;
  std::size_t faces = 0, vertices = 0;
  long long peak = 0;
  for (auto _ : state) {
    const long long base = g_in_use.load();
    g_peak = base;
    Mesh m = heightfield_mesh(t.height, nullptr, options);
    faces = m.face_count();
    vertices = m.vertex_count();
    peak = std::max(peak, g_peak.load() - base);
  }
  report(state, faces, vertices, 0.0, t.bound, peak);
}

}  // namespace

BENCHMARK(TinBench)->Name("Tin")->Arg(257)->Arg(513)->Arg(1025)->Arg(2049)->Arg(4097)->Unit(benchmark::kMillisecond);
BENCHMARK(GreedyBench)
    ->Name("Greedy")
    ->Arg(257)
    ->Arg(513)
    ->Arg(1025)
    ->Arg(2049)
    ->Arg(4097)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(MeshNode)->Name("Mesh")->Arg(1025)->Arg(4097)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
