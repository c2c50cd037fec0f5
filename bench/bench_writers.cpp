// File writers at 4096^2: a heightfield to EXR (float32), 16-bit PNG, TIFF (float32) and RAW16, and a colour
// image (RGB) to 8-bit PNG and EXR, each at its default and at the fastest compression level.
//
// Counters: MB_per_s is the uncompressed payload (width x height x channels x bytes per stored sample)
// divided by the wall-clock time of one write, file_MB the size of the file. Writers may use several threads
// (OpenEXR compresses chunks in parallel): "CPU" is the main thread's time, process_cpu_ms the CPU time of all
// threads per write and MB_per_cpu_s the payload over it, which a loaded machine does not inflate the way it
// inflates wall time. The machine may be shared: run e.g.
//   build/release/bench/orogen_bench_writers --benchmark_min_time=1
// and say how loaded it was.
#include <ctime>
#include <filesystem>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_file.h"

namespace {

using namespace orogen;
namespace fs = std::filesystem;

constexpr int kSide = 4096;

const Domain& domain() {
  static const Domain d = Domain::from_extent({0.0, 0.0}, {16384.0, 16384.0}, {kSide, kSide});
  return d;
}

// fBm terrain: realistic entropy for the compressors (a constant field would compress to nothing).
const Heightfield& terrain() {
  static const Heightfield h =
      *run_node("FBM", domain(), {{"feature_size", 3000.0}, {"amplitude", 800.0}, {"octaves", std::int64_t(10)}})
           .get<Heightfield>();
  return h;
}

const Image& colors() {
  static const Image img = [] {
    Image i(domain(), 3);
    const Heightfield& h = terrain();
    for (std::size_t k = 0; k < h.data.size(); ++k) {
      const float t = std::clamp((h.data[k] + 800.0f) / 1600.0f, 0.0f, 1.0f);
      i.data[3 * k] = t;
      i.data[3 * k + 1] = 0.5f * t + 0.2f;
      i.data[3 * k + 2] = 1.0f - t;
    }
    return i;
  }();
  return img;
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "orogen_bench_writers";
  fs::create_directories(dir);
  return dir / name;
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The writers create their file exclusively (never through a planted link), so each write needs the previous
// one gone; deleting it is not part of the measurement.
void remove_untimed(benchmark::State& state, const fs::path& path) {
  state.PauseTiming();
  fs::remove(path);
  state.ResumeTiming();
}

void finish(benchmark::State& state, const fs::path& path, double payload_bytes, double cpu_seconds) {
  const double per_write = cpu_seconds / static_cast<double>(state.iterations());
  state.counters["process_cpu_ms"] = 1e3 * per_write;
  state.counters["MB_per_cpu_s"] = payload_bytes / 1e6 / per_write;
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * payload_bytes));
  state.counters["MB_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * payload_bytes / 1e6, benchmark::Counter::kIsRate);
  state.counters["file_MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
  fs::remove(path);
}

void Height(benchmark::State& state, HeightFormat format, const char* name, int level, const char* exr_codec = "zip") {
  const Heightfield& h = terrain();
  const fs::path path = scratch(name);
  HeightfieldWriteOptions options;
  options.format = format;
  options.compression_level = level;
  options.exr_compression = exr_codec;
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) {
    remove_untimed(state, path);
    write_heightfield_file(h, path, options);
  }
  const double cpu = process_cpu_seconds() - cpu0;
  const double bytes_per_sample = format == HeightFormat::Exr || format == HeightFormat::Tiff ? 4.0 : 2.0;
  finish(state, path, bytes_per_sample * kSide * kSide, cpu);
}

void Color(benchmark::State& state, ImageFormat format, const char* name, int level) {
  const Image& img = colors();
  const fs::path path = scratch(name);
  ImageWriteOptions options;
  options.format = format;
  options.compression_level = level;
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) {
    remove_untimed(state, path);
    write_image_file(img, path, options);
  }
  const double cpu = process_cpu_seconds() - cpu0;
  const double bytes_per_sample = format == ImageFormat::Png8 ? 1.0 : format == ImageFormat::Png16 ? 2.0 : 4.0;
  finish(state, path, bytes_per_sample * 3 * kSide * kSide, cpu);
}

}  // namespace

// -1: each library's default level (what Orogen wrote before the compression_level parameter); 1: the
// fastest zlib level (WriteHeightfield's default now; WriteImage keeps 6). EXR heights: WriteHeightfield's
// default codec is none (exr_float32_none); zip and piz for comparison.
BENCHMARK_CAPTURE(Height, exr_float32_none, HeightFormat::Exr, "h.exr", 1, "none")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(Height, exr_float32_piz, HeightFormat::Exr, "h.exr", 1, "piz")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(Height, exr_float32, HeightFormat::Exr, "h.exr", -1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Height, exr_float32_level1, HeightFormat::Exr, "h.exr", 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(Height, png16, HeightFormat::Png16, "h.png", -1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Height, png16_level1, HeightFormat::Png16, "h.png", 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Height, tiff_float32, HeightFormat::Tiff, "h.tif", -1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Height, tiff_float32_level1, HeightFormat::Tiff, "h.tif", 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(Height, raw16, HeightFormat::Raw16, "h.raw", -1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Color, png8_rgb, ImageFormat::Png8, "c.png", -1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Color, png8_rgb_level1, ImageFormat::Png8, "c.png", 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(Color, exr_rgb_float32, ImageFormat::Exr, "c.exr", -1)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
