// Depression filling across tiles (nodes/hydrology/tile_fill.h, Barnes 2016) against the whole-domain
// Priority-Flood (Flat) on one fBm terrain: the per-tile flood, the solve of all tiles' spill graphs (what one rank
// does once for the job) and the per-tile application, each as cells per second of one core, and the bytes of the
// spill graphs that travel. Barnes (2016) reports about 2.5 M cells per core-second for the whole parallel fill.
// Then the epsilon surface across the tiles from their flat levels (TileEpsilon) against the whole-domain epsilon
// fill.
#include <memory>

#include <benchmark/benchmark.h>

#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_phases.h"
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

void WholeDomainEpsilon(benchmark::State& state) {
  const FlowGrid g = FlowGrid::of(terrain().domain);
  for (auto _ : state) {
    std::vector<float> z = terrain().data;
    fill_depressions(g, z, FlatMode::Epsilon);
    benchmark::DoNotOptimize(z.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

// The epsilon surface across the 16 tiles from their flat levels (TileEpsilon): every tile's first relaxation,
// then rounds of the perimeter values that fell until none does (all tiles on this core: what the ranks do
// together). Counters: the rounds, the bytes of all messages and answers, and whether the joined tiles equal the
// whole-domain epsilon fill bit for bit (checked once, outside the timing).
void EpsilonAllTiles(benchmark::State& state) {
  std::vector<std::vector<float>> flat(phases().floods.size());
  for (std::size_t k = 0; k < flat.size(); ++k) flat[k] = apply_spill_levels(phases().floods[k], phases().levels[k]);
  int rounds = 0;
  std::size_t bytes = 0;
  std::vector<std::unique_ptr<TileEpsilon>> tiles;
  for (auto _ : state) {
    tiles.clear();
    rounds = 0, bytes = 0;
    for (std::size_t k = 0; k < flat.size(); ++k)
      tiles.push_back(std::make_unique<TileEpsilon>(flat[k], phases().graphs[k].rect, glm::ivec2(kSide)));
    for (bool fell = true; fell; ++rounds) {
      std::vector<std::string> messages;
      for (auto& t : tiles) messages.push_back(t->message()), bytes += messages.back().size();
      fell = perimeter_minima_fell(message_views(messages));
      const auto answers = solve_perimeter_minima(message_views(messages), glm::ivec2(kSide));
      for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->answer(answers[k]), bytes += answers[k].size();
    }
  }
  std::vector<float> whole = terrain().data;
  fill_depressions(FlowGrid::of(terrain().domain), whole, FlatMode::Epsilon);
  bool equal = true;
  for (std::size_t k = 0; k < tiles.size(); ++k) {
    const TileRect& r = phases().graphs[k].rect;
    for (int j = 0; j < r.size.y; ++j)
      for (int i = 0; i < r.size.x; ++i)
        equal = equal && tiles[k]->surface()[static_cast<std::size_t>(j) * r.size.x + i] ==
                             whole[static_cast<std::size_t>(r.first.y + j) * kSide + r.first.x + i];
  }
  state.counters["rounds"] = rounds;
  state.counters["message_MiB"] = static_cast<double>(bytes) / (1 << 20);
  state.counters["equal"] = equal;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

// D8 flow accumulation across the 16 tiles (Barnes 2017, nodes/hydrology/tile_accumulation.h), from the D8
// directions of the epsilon-filled terrain as each tile sees them: every tile's local counts and perimeter links, the
// solve of all tiles' links, every tile's final counts (all tiles on this core: the work the ranks share). Barnes
// (2017) reports about 38 M cells per core-second for this step. WholeDomainD8Counts is the library call on one grid,
// from the same directions. Counter equal: the joined tiles' counts are the whole domain's (checked once, outside the
// timing).
struct Directions {
  FlowGrid grid{1, 1, 1.0, 1.0};
  D8Flow flow;
  std::vector<std::vector<std::uint8_t>> tiles;  // per tile, its cells' directions
};

const Directions& directions() {
  static const Directions d = [] {
    Directions q;
    q.grid = FlowGrid::of(terrain().domain);
    std::vector<float> z = terrain().data;
    fill_depressions(q.grid, z, FlatMode::Epsilon);
    q.flow = d8_flow(q.grid, z);
    for (int tj = 0; tj < kTiles; ++tj)
      for (int ti = 0; ti < kTiles; ++ti) {
        const TileRect r = tile(ti, tj);
        std::vector<std::uint8_t> dir;
        for (int j = 0; j < r.size.y; ++j)
          for (int i = 0; i < r.size.x; ++i)
            dir.push_back(q.flow.direction[static_cast<std::size_t>(r.first.y + j) * kSide + r.first.x + i]);
        q.tiles.push_back(std::move(dir));
      }
    return q;
  }();
  return d;
}

void WholeDomainD8Counts(benchmark::State& state) {
  const Directions& d = directions();
  for (auto _ : state) benchmark::DoNotOptimize(count_d8(d.grid, d.flow).data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

void AccumulationAllTiles(benchmark::State& state) {
  const Directions& d = directions();
  std::vector<std::vector<std::int64_t>> counts(d.tiles.size());
  for (auto _ : state) {
    std::vector<TileAccumulation> tiles;
    std::vector<std::string> messages;
    for (int tj = 0, k = 0; tj < kTiles; ++tj)
      for (int ti = 0; ti < kTiles; ++ti, ++k) {
        tiles.push_back(start_tile_accumulation(d.tiles[static_cast<std::size_t>(k)], tile(ti, tj), glm::ivec2(kSide)));
        messages.push_back(accumulation_message(tiles.back()));
      }
    const auto answers = solve_tile_accumulation(message_views(messages), glm::ivec2(kSide));
    for (std::size_t k = 0; k < tiles.size(); ++k) counts[k] = finish_tile_accumulation(tiles[k], answers[k]);
  }
  const std::vector<double> whole = count_d8(d.grid, d.flow);
  bool equal = true;
  for (int tj = 0, k = 0; tj < kTiles; ++tj)
    for (int ti = 0; ti < kTiles; ++ti, ++k) {
      const TileRect r = tile(ti, tj);
      for (int j = 0; j < r.size.y; ++j)
        for (int i = 0; i < r.size.x; ++i)
          equal = equal && static_cast<double>(
                               counts[static_cast<std::size_t>(k)][static_cast<std::size_t>(j) * r.size.x + i]) ==
                               whole[static_cast<std::size_t>(r.first.y + j) * kSide + r.first.x + i];
    }
  state.counters["equal"] = equal;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()));
}

BENCHMARK(WholeDomainFlat)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(WholeDomainD8Counts)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(AccumulationAllTiles)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(WholeDomainEpsilon)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(EpsilonAllTiles)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->Iterations(1);
BENCHMARK(FloodOneTile)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(SolveAllSpillGraphs)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(ApplyOneTile)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
