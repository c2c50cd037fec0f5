// Island family speed, single thread (the island pipeline is serial; the raster runs in a 1-thread arena).
//
//   orogen_bench_island [--benchmark_filter=...] [--benchmark_repetitions=5]
//
//  - Delaunay/N: the clipped Voronoi diagram of N uniform sites (CGAL Delaunay + mirrors + dual)
//  - IslandNoRelax/N: points to biomes without Lloyd passes (sites, diagram, water, ocean, lakes, elevation,
//    rivers, moisture, biomes)
//  - Island/N: the same with the default 2 Lloyd passes (3 diagrams)
//  - Raster/R: PolygonMapRaster of a 10^4-cell island on R x R samples (noise displacement on)
// Figures are CPU time; the machine may be shared, so compare runs made together.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "nodes/island/island.h"
#include "nodes/island/island_raster.h"
#include "nodes/island/voronoi.h"

namespace {

using namespace orogen;
using namespace orogen::island;

IslandParams params(int cells, int relaxation) {
  IslandParams p;
  p.cells = cells;
  p.relaxation = relaxation;
  p.distribution = SiteDistribution::Uniform;
  p.shape_scale = 1.1;
  p.shape_offset = -0.3;
  p.rivers = cells / 50;
  p.seed = 7;
  return p;
}

void Delaunay(benchmark::State& state) {
  const IslandParams p = params(static_cast<int>(state.range(0)), 0);
  const auto sites = island_sites(p);
  for (auto _ : state) benchmark::DoNotOptimize(voronoi_diagram(sites, p.min_corner, p.min_corner + p.size));
  state.counters["cells"] = static_cast<double>(sites.size());
}
BENCHMARK(Delaunay)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void IslandNoRelax(benchmark::State& state) {
  const IslandParams p = params(static_cast<int>(state.range(0)), 0);
  for (auto _ : state) benchmark::DoNotOptimize(generate_island(p));
}
BENCHMARK(IslandNoRelax)->Arg(10000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void Island(benchmark::State& state) {
  const IslandParams p = params(static_cast<int>(state.range(0)), 2);
  for (auto _ : state) benchmark::DoNotOptimize(generate_island(p));
}
BENCHMARK(Island)->Arg(10000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void Raster(benchmark::State& state) {
  static const PolygonMap map = generate_island(params(10000, 2));
  const int r = static_cast<int>(state.range(0));
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {r, r});
  tbb::task_arena arena(1);
  for (auto _ : state) arena.execute([&] { benchmark::DoNotOptimize(rasterize_polygon_map(map, d, RasterParams{})); });
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(r) * r, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(Raster)->Arg(1024)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
