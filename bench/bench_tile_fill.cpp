// Depression filling across tiles (nodes/hydrology/tile_fill.h, Barnes 2016) against the whole-domain
// Priority-Flood (Flat) on one fBm terrain: the per-tile flood, the solve of all tiles' spill graphs (what one rank
// does once for the job) and the per-tile application, each as cells per second of one core, and the bytes of the
// spill graphs that travel. Barnes (2016) reports about 2.5 M cells per core-second for the whole parallel fill.
#include <benchmark/benchmark.h>

#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/noise/fbm.h"

namespace {

using namespace orogen;
using namespace orogen::hydrology;

constexpr int kSide = 4097;
constexpr int kTiles = 4;  // 4 x 4 tiles of 1025 samples

const Heightfield& terrain() {
  static const Heightfield h = [] {
    const Domain d = Domain::from_extent({0.0, 0.0}, {16.0 * (kSide - 1), 16.0 * (kSide - 1)}, {kSide, kSide});
    noise::FbmParams p;
    p.feature_size = 12000.0;
    p.amplitude = 900.0;
    p.octaves = 10;
    p.seed = 5;
    return noise::fbm(d, p);
  }();
  return h;
}

TileRect tile(int ti, int tj) {
  const auto edge = [](int t) { return t * (kSide - 1) / kTiles; };
  return {{edge(ti), edge(tj)}, {edge(ti + 1) - edge(ti) + 1, edge(tj + 1) - edge(tj) + 1}};
}

std::vector<float> tile_heights(const TileRect& r) {
  std::vector<float> z;
  z.reserve(static_cast<std::size_t>(r.size.x) * r.size.y);
  for (int j = 0; j < r.size.y; ++j)
    for (int i = 0; i < r.size.x; ++i) z.push_back(terrain().at(r.first.x + i, r.first.y + j));
  return z;
}

struct Phases {
  std::vector<TileFlood> floods;
  std::vector<TileSpillGraph> graphs;
  std::vector<std::vector<float>> levels;
};

const Phases& phases() {
  static const Phases p = [] {
    Phases q;
    for (int tj = 0; tj < kTiles; ++tj)
      for (int ti = 0; ti < kTiles; ++ti) {
        q.floods.push_back(flood_tile(tile_heights(tile(ti, tj)), tile(ti, tj)));
        q.graphs.push_back(q.floods.back().graph);
      }
    q.levels = solve_spill_graphs(q.graphs, {kSide, kSide});
    return q;
  }();
  return p;
}

void WholeDomainFlat(benchmark::State& state) {
  const FlowGrid g = FlowGrid::of(terrain().domain);
  for (auto _ : state) {
    std::vector<float> z = terrain().data;
    fill_depressions(g, z, FlatMode::Flat);
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

void FloodOneTile(benchmark::State& state) {
  const TileRect r = tile(1, 1);
  const std::vector<float> z = tile_heights(r);
  for (auto _ : state) benchmark::DoNotOptimize(flood_tile(z, r).level.data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(z.size()));
}

void SolveAllSpillGraphs(benchmark::State& state) {
  std::size_t bytes = 0;
  for (const auto& g : phases().graphs) bytes += encode(g).size();
  for (auto _ : state) benchmark::DoNotOptimize(solve_spill_graphs(phases().graphs, {kSide, kSide}).data());
  state.counters["graph_MiB"] = static_cast<double>(bytes) / (1 << 20);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

void ApplyOneTile(benchmark::State& state) {
  const std::size_t k = kTiles + 1;  // tile (1, 1)
  for (auto _ : state) benchmark::DoNotOptimize(apply_spill_levels(phases().floods[k], phases().levels[k]).data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(phases().floods[k].level.size()));
}

BENCHMARK(WholeDomainFlat)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(FloodOneTile)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(SolveAllSpillGraphs)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(ApplyOneTile)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
