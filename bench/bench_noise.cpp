// Noise speed against libnoise, in the same run: a 4096 x 4096 grid of 4096 m with 64 m features.
//
//   orogen_bench_noise [--benchmark_filter=...]
//   orogen_bench_noise --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true   (busy machine)
//   orogen_bench_noise --noise_target=AVX2   (kernels limited to an instruction set: AVX3, AVX2, SSE4, SCALAR)
//
// Single-threaded (a oneTBB arena of one thread): Orogen's Perlin, Simplex, Worley F1 and 5-octave Perlin
// fBm beside libnoise's module::Perlin at 1 and 5 octaves (default NoiseQuality, sampled on the plane
// z = 0). Then the Orogen generators on all cores, for the thread speed-up. At the end a table gives
// ns per sample, the speed ratio to libnoise (1 octave for single-octave generators, 5 octaves for fBm)
// and the speed-up on all cores.
//
// Every benchmark writes into one 64 MB buffer, allocated and touched once before the first run: a fresh
// buffer per run (per repetition) would add the kernel's first-touch page faults to the algorithm's time.
// The table also works with --benchmark_report_aggregates_only=true (it reads the "min" aggregate).
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <hwy/targets.h>
#include <noise.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include "nodes/noise/fbm.h"
#include "nodes/noise/lattice_noise.h"
#include "nodes/noise/noise_field.h"
#include "nodes/noise/noise_kernels.h"
#include "nodes/noise/worley.h"

namespace {

using namespace orogen;
using namespace orogen::noise;

constexpr int kSide = 4096;
constexpr double kWorld = 4096.0;  // metres
constexpr double kFeature = 64.0;  // metres: 64 cells across
constexpr double kSamples = double(kSide) * kSide;

const Domain& grid() {
  static const Domain d = Domain::from_extent({0.0, 0.0}, {kWorld, kWorld}, {kSide, kSide});
  return d;
}

// ---- libnoise ----

// The output buffer of every run: allocated once and written through, so no run pays for page faults.
Heightfield& output() {
  static Heightfield out = [] {
    Heightfield h(grid(), 0.0f);
    std::fill(h.data.begin(), h.data.end(), 1.0f);
    return h;
  }();
  return out;
}

void libnoise_perlin(benchmark::State& state, int octaves) {
  ::noise::module::Perlin perlin;
  perlin.SetOctaveCount(octaves);
  perlin.SetFrequency(1.0 / kFeature);
  std::vector<float>& out = output().data;
  const Domain& d = grid();
  for (auto _ : state) {
    float* o = out.data();
    for (int j = 0; j < kSide; ++j) {
      const double y = d.y(j);
      for (int i = 0; i < kSide; ++i) *o++ = static_cast<float>(perlin.GetValue(d.x(i), y, 0.0));
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSamples));
}

// ---- Orogen ----

NoisePlan plan_of(const std::string& name) {
  LatticeNoiseParams lp;
  lp.feature_size = kFeature;
  lp.amplitude = 1.0;
  if (name == "Perlin") return lattice_noise_plan(Basis::Perlin, lp);
  if (name == "Simplex") return lattice_noise_plan(Basis::Simplex, lp);
  if (name == "Value") return lattice_noise_plan(Basis::Value, lp);
  if (name == "WorleyF1") {
    WorleyParams wp;
    wp.feature_size = kFeature;
    wp.amplitude = 1.0;
    return worley_plan(wp);
  }
  FbmParams fp;  // "FBM5Perlin"
  fp.feature_size = kFeature;
  fp.amplitude = 1.0;
  fp.octaves = 5;
  return fbm_plan(fp);
}

void orogen_noise(benchmark::State& state, const std::string& name, bool single_thread) {
  const NoisePlan plan = plan_of(name);
  Heightfield& out = output();  // already the grid's size: evaluate_noise_into reuses it
  tbb::task_arena arena(single_thread ? 1 : tbb::info::default_concurrency());
  for (auto _ : state) {
    arena.execute([&] { evaluate_noise_into(out, plan); });
    benchmark::DoNotOptimize(out.data.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSamples));
}

// Collects ns per sample of every run for the summary table: CPU time of the calling thread (which does
// all the work of a single-thread arena, and is robust to other processes on a busy machine) and wall time,
// each the best over repetitions (--benchmark_repetitions=N, ideally with
// --benchmark_enable_random_interleaving=true so that every benchmark sees the same machine load). With
// --benchmark_report_aggregates_only=true only aggregates arrive here: the "min" statistic every benchmark
// computes stands for the repetitions then.
class TableReporter : public benchmark::ConsoleReporter {
 public:
  struct Times {
    double cpu_ns = 0, wall_ns = 0;
  };
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      if (r.run_type == Run::RT_Iteration ? r.iterations <= 0 : r.aggregate_name != "min") continue;
      // Per-iteration times in the run's unit (milliseconds here), as the console prints them.
      const double per = 1e9 / benchmark::GetTimeUnitMultiplier(r.time_unit) / kSamples;
      Times& t = times[r.run_name.function_name];
      const double cpu = r.GetAdjustedCPUTime() * per, wall = r.GetAdjustedRealTime() * per;
      t.cpu_ns = t.cpu_ns > 0 ? std::min(t.cpu_ns, cpu) : cpu;
      t.wall_ns = t.wall_ns > 0 ? std::min(t.wall_ns, wall) : wall;
    }
  }
  std::map<std::string, Times> times;
};

}  // namespace

int main(int argc, char** argv) {
  const auto min_of = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
  benchmark::RegisterBenchmark("libnoise/Perlin/1octave", libnoise_perlin, 1)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->ComputeStatistics("min", min_of);
  benchmark::RegisterBenchmark("libnoise/Perlin/5octaves", libnoise_perlin, 5)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->ComputeStatistics("min", min_of);
  const std::vector<std::string> ours = {"Perlin", "Simplex", "Value", "WorleyF1", "FBM5Perlin"};
  for (bool single : {true, false})
    for (const std::string& name : ours)
      benchmark::RegisterBenchmark(("orogen/" + name + (single ? "/1thread" : "/allthreads")).c_str(), orogen_noise,
                                   name, single)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->ComputeStatistics("min", min_of);

  benchmark::Initialize(&argc, argv);
  // --noise_target=AVX2 (or SSE4, SCALAR, ...): run the kernels with a lower instruction set than the best.
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a], flag = "--noise_target=";
    if (arg.rfind(flag, 0) != 0) continue;
    bool found = false;
    for (std::int64_t t : kernels::available_targets())
      if (arg.substr(flag.size()) == kernels::target_name(t)) {
        hwy::SetSupportedTargetsForTest(t);
        found = true;
      }
    if (!found) {
      std::fprintf(stderr, "unknown or unsupported target in %s\n", arg.c_str());
      return 1;
    }
    for (int b = a; b + 1 < argc; ++b) argv[b] = argv[b + 1];
    --argc;
    --a;
  }
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::printf("Noise kernels: %s; %d cores for the all-threads runs; grid %dx%d\n", kernels::active_target(),
              tbb::info::default_concurrency(), kSide, kSide);
  TableReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  const auto& t = reporter.times;
  auto get = [&](const std::string& k) { return t.count(k) ? t.at(k) : TableReporter::Times{}; };
  auto fmt = [](double v, const char* suffix = "") {
    char b[32];
    std::snprintf(b, sizeof b, v > 0 ? "%.2f%s" : "-", v, suffix);
    return std::string(b);
  };
  const auto lib1 = get("libnoise/Perlin/1octave"), lib5 = get("libnoise/Perlin/5octaves");
  std::printf(
      "\nns per sample (best of the repetitions); vs libnoise = libnoise time / Orogen time in this run, from\n"
      "the CPU time of the single working thread; speed-up = CPU time on 1 thread / wall time on all threads\n"
      "(the single thread's wall time counts the time other processes held its core, which made the ratio\n"
      "exceed the core count on a busy machine; its CPU time is the work itself)\n");
  std::printf(
      "| generator | ns/sample, 1 thread (CPU) | (wall) | vs libnoise | ns/sample, %d threads (wall) | speed-up |\n",
      tbb::info::default_concurrency());
  std::printf("|---|---|---|---|---|---|\n");
  std::printf("| libnoise Perlin, 1 octave | %s | %s | 1x | | |\n", fmt(lib1.cpu_ns).c_str(),
              fmt(lib1.wall_ns).c_str());
  std::printf("| libnoise Perlin, 5 octaves | %s | %s | 1x | | |\n", fmt(lib5.cpu_ns).c_str(),
              fmt(lib5.wall_ns).c_str());
  for (const std::string& name : ours) {
    const auto one = get("orogen/" + name + "/1thread"), all = get("orogen/" + name + "/allthreads");
    if (one.cpu_ns <= 0) continue;
    const auto lib = name == "FBM5Perlin" ? lib5 : lib1;
    std::printf("| %s | %s | %s | %s | %s | %s |\n", name.c_str(), fmt(one.cpu_ns).c_str(), fmt(one.wall_ns).c_str(),
                lib.cpu_ns > 0 ? fmt(lib.cpu_ns / one.cpu_ns, "x").c_str() : "-", fmt(all.wall_ns).c_str(),
                all.wall_ns > 0 ? fmt(one.cpu_ns / all.wall_ns, "x").c_str() : "-");
  }
  benchmark::Shutdown();
  return 0;
}
