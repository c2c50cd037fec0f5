// WaterFlow on one core: the whole-domain node against the same run across 4 x 4 tiles in one process
// (nodes/hydrology/water_flow_across_tiles.cpp, every round's messages solved as the driver does), exchanging every
// k = 1, 2, 4 and 8 iterations. Items are cell-iterations, so the figures compare the cost per cell per iteration.
//   build/release/bench/orogen_bench_water_flow_tiles --benchmark_repetitions=3
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "graph/tile_graph.h"
#include "nodes/hydrology/water_flow.h"
#include "nodes/hydrology/water_flow_across_tiles.h"
#include "nodes/noise/fbm.h"

namespace {

using namespace orogen;
using namespace orogen::hydrology;

constexpr int kSide = 1025;
constexpr int kTiles = 4;  // 4 x 4 tiles of 257 samples
constexpr int kIterations = 50;

const Heightfield& terrain() {
  static const Heightfield h = [] {
    const Domain d = Domain::from_extent({0.0, 0.0}, {8.0 * (kSide - 1), 8.0 * (kSide - 1)}, {kSide, kSide});
    noise::FbmParams p;
    p.feature_size = 3000.0;
    p.amplitude = 300.0;
    p.octaves = 8;
    p.seed = 5;
    return noise::fbm(d, p);
  }();
  return h;
}

WaterFlowParams params() {
  WaterFlowParams p;
  p.rainfall = 60.0, p.infiltration = 10.0, p.threshold = 0.0, p.max_iterations = kIterations;
  return p;
}

void WholeDomain(benchmark::State& state) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  for (auto _ : state) {
    const WaterFlowResult r = water_flow(terrain(), nullptr, nullptr, params());
    benchmark::DoNotOptimize(r.depth->data.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()) * kIterations);
}

// The tiles' inputs, cut from the terrain.
std::vector<std::vector<PortValue>> tile_inputs() {
  std::vector<std::vector<PortValue>> inputs;
  const auto edge = [](int t) { return t * (kSide - 1) / kTiles; };
  for (int tj = 0; tj < kTiles; ++tj)
    for (int ti = 0; ti < kTiles; ++ti) {
      const int x0 = edge(ti), y0 = edge(tj), w = edge(ti + 1) - x0 + 1, h = edge(tj + 1) - y0 + 1;
      auto t = std::make_shared<Heightfield>(terrain().domain.subdomain(x0, y0, w, h));
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) t->at(i, j) = terrain().at(x0 + i, y0 + j);
      inputs.push_back({HeightfieldPtr(t), PortValue{}, PortValue{}});
    }
  return inputs;
}

void AcrossTiles(benchmark::State& state) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const auto algorithm = water_flow_across_tiles(params(), terrain().domain, static_cast<int>(state.range(0)));
  const auto inputs = tile_inputs();
  std::size_t bytes = 0;
  for (auto _ : state) {
    std::vector<std::unique_ptr<TileGraphTile>> tiles;
    for (const auto& in : inputs) tiles.push_back(algorithm->start(in));
    bytes = 0;
    for (int round = 0;; ++round) {
      std::vector<std::string> messages;
      for (auto& tile : tiles) messages.push_back(tile->message(round)), bytes += messages.back().size();
      const auto answers = algorithm->solve(round, messages);
      for (std::size_t t = 0; t < tiles.size(); ++t) tiles[t]->answer(round, answers[t]);
      if (!algorithm->another_round(round, messages)) break;
    }
    for (auto& tile : tiles) benchmark::DoNotOptimize(tile->outputs());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(terrain().data.size()) * kIterations);
  state.counters["message_MiB"] = static_cast<double>(bytes) / (1 << 20);
}

BENCHMARK(WholeDomain)->Unit(benchmark::kMillisecond);
BENCHMARK(AcrossTiles)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
