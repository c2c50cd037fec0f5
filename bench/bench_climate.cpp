// Climate speed at 2048 x 2048 (10 m spacing, 8 octaves of simplex fBm, about 0..1100 m):
//  - SunYear: SunIllumination's daily figures for all twelve months at hourly steps, latitude 45 N (lit
//    hours and mean direct irradiance; months sharing a declination share the sweeps: 7 declinations, one
//    horizon sweep per daylight hour). Counter `sweeps`: horizon sweeps per run.
//  - KMeans: KMeansClusters' k-means (k = 8, diagonal seeds, Long's weights, tolerance 1e-4) on the 37-channel resource
//    stack (slope, 12 temperatures, 12 lit hours, 12 soil humidities). Counter `iterations`.
//  - Stack: Temperature + SoilHumidity + ResourceStack (point-wise work around the two above).
//
//   orogen_bench_climate [--benchmark_filter=...]
//
// threads:1 reports process CPU time; the /wall variants run 2 threads and report wall time.
//
// Measured 1 December 2026 on the shared 2-core machine (load average 8-14 from other builds, so wall times
// mean little; CPU times): SunYear 9.6 s CPU on 1 thread (90 sweeps, about 105 ms each for 4.2 M cells;
// 9.55 s CPU in total on 2 threads, so about 4.8 s of wall time on an idle 2-core machine); KMeans 14.2 s
// CPU for 60 iterations (0.24 s per iteration over 4.2 M cells x 37 channels x 8 centres); Stack 1.2 s.
#include <algorithm>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "nodes/climate/kmeans.h"
#include "nodes/climate/resources.h"
#include "nodes/climate/sun.h"
#include "nodes/noise/fbm.h"

namespace {

using namespace orogen;
using namespace orogen::climate;

constexpr int kSide = 2048;
constexpr double kSpacing = 10.0;

const Heightfield& terrain() {
  static const Heightfield h = [] {
    const Domain d = Domain::from_extent({0.0, 0.0}, {kSpacing * (kSide - 1), kSpacing * (kSide - 1)}, {kSide, kSide});
    noise::FbmParams p;
    p.basis = noise::Basis::Simplex;
    p.feature_size = 8000.0;
    p.amplitude = 600.0;
    p.octaves = 8;
    p.seed = 3;
    Heightfield z = noise::fbm(d, p);
    for (auto& v : z.data) v += 500.0f;
    return z;
  }();
  return h;
}

std::vector<int> all_months() {
  std::vector<int> m;
  for (int k = 1; k <= 12; ++k) m.push_back(k);
  return m;
}

const Image& stack() {
  static const std::shared_ptr<Image> s = [] {
    SunParams sp;
    const auto months = all_months();
    const SunDaily sun = sun_daily(terrain(), sp, months);
    const auto t = temperature(terrain(), TemperatureParams{});
    const auto h = soil_humidity(terrain(), SoilHumidityParams::defaults(), nullptr, nullptr, nullptr);
    return resource_stack(terrain(), t.monthly.get(), sun.hours.get(), h.weighted.get());
  }();
  return *s;
}

int sweeps_per_year(double latitude) {
  int n = 0;
  std::vector<double> seen;
  for (int m = 1; m <= 12; ++m) {
    const double d = declination_deg(m);
    if (std::find(seen.begin(), seen.end(), d) != seen.end()) continue;
    seen.push_back(d);
    const double h0 = sunset_hour_angle_deg(latitude, d) / 15.0;
    for (int k = 0; k < 24; ++k) n += std::min(12.0 + h0, k + 1.0) > std::max(12.0 - h0, double(k));
  }
  return n;
}

void SunYear(benchmark::State& state) {
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  (void)terrain();
  const auto months = all_months();
  SunParams p;
  p.latitude = 45.0;
  for (auto _ : state)
    arena.execute([&] {
      const SunDaily d = sun_daily(terrain(), p, months);
      benchmark::DoNotOptimize(d.hours->data.data());
    });
  state.counters["sweeps"] = sweeps_per_year(45.0);
}

void KMeans(benchmark::State& state) {
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  const Image& s = stack();
  KMeansParams p;
  p.k = 8;
  p.max_iterations = 100;
  p.tolerance = 1e-4;  // the node's default
  p.weights = group_weights(s.channel_names, s.channels, 1.0, 1.0, 1.0, 0.1, 1.0);
  int iterations = 0;
  for (auto _ : state)
    arena.execute([&] {
      const KMeansResult r = kmeans(s, p);
      iterations = r.iterations;
      benchmark::DoNotOptimize(r.labels.data());
    });
  state.counters["iterations"] = iterations;
}

void Stack(benchmark::State& state) {
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  const Image& s = stack();
  const Image sun_hours = [&] {
    Image img(s.domain, 12);
    for (std::size_t q = 0; q < s.domain.sample_count(); ++q)
      for (int c = 0; c < 12; ++c) img.data[q * 12 + std::size_t(c)] = s.data[q * 37 + 13 + std::size_t(c)];
    return img;
  }();
  for (auto _ : state)
    arena.execute([&] {
      const auto t = temperature(terrain(), TemperatureParams{});
      const auto h = soil_humidity(terrain(), SoilHumidityParams::defaults(), nullptr, nullptr, nullptr);
      const auto r = resource_stack(terrain(), t.monthly.get(), &sun_hours, h.weighted.get());
      benchmark::DoNotOptimize(r->data.data());
    });
}

void args(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->Iterations(1)->Arg(1);
}
void args2(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime()->Iterations(1)->Arg(2);
}

BENCHMARK(SunYear)->Apply(args);
BENCHMARK(KMeans)->Apply(args);
BENCHMARK(Stack)->Apply(args);
BENCHMARK(SunYear)->Name("SunYear/wall")->Apply(args2);
BENCHMARK(KMeans)->Name("KMeans/wall")->Apply(args2);

}  // namespace

BENCHMARK_MAIN();
