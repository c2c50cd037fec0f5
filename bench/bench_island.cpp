// Island family speed, single thread (the island pipeline is serial; the raster runs in a 1-thread arena).
//
//   orogen_bench_island [--benchmark_filter=...] [--benchmark_repetitions=5]
//
//  - Delaunay/N: the clipped Voronoi diagram of N uniform sites (CGAL Delaunay + mirrors + dual)
//  - IslandNoRelax/N: points to biomes without Lloyd passes (sites, diagram, water, ocean, lakes, elevation,
//    rivers, moisture, biomes)
//  - Island/N: the same with the default 2 Lloyd passes (3 diagrams)
//  - Raster/R: PolygonMapRaster of a 10^4-cell island on R x R samples (noise displacement on)
//  - RiverNetwork/D: the river tree on a 4096 m square at D inner points per km^2
//  - Carve/R: CarveRivers of that network (D = 15) into a flat R x R terrain, radius 250 m
// Figures are CPU time; the machine may be shared, so compare runs made together.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "nodes/island/island.h"
#include "nodes/island/island_raster.h"
#include "nodes/island/river_network.h"
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
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(r) * r, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(Raster)->Arg(1024)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void RiverNetwork(benchmark::State& state) {
  RiverNetworkParams p;
  p.density = static_cast<double>(state.range(0));
  p.max_length = 500.0;
  p.seed = 5;
  std::size_t curves = 0;
  for (auto _ : state) curves = river_network(p).size();
  state.counters["curves"] = static_cast<double>(curves);
}
BENCHMARK(RiverNetwork)->Arg(15)->Arg(60)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void Carve(benchmark::State& state) {
  RiverNetworkParams p;
  p.density = 15.0;
  p.max_length = 500.0;
  p.seed = 5;
  static const Curves net = river_network(p);
  const int r = static_cast<int>(state.range(0));
  const Heightfield flat(Domain::from_extent({0, 0}, {4096, 4096}, {r, r}), 100.0f);
  CarveParams c;
  c.radius = 250.0;
  tbb::task_arena arena(1);
  for (auto _ : state) arena.execute([&] { benchmark::DoNotOptimize(carve_rivers(flat, net, c)); });
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(r) * r, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(Carve)->Arg(512)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
