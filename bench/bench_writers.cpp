// Mesh and scene writers (Mesh/*, Scene/*) at a 1025^2 grid mesh, 2.1 M triangles (OROGEN_BENCH_MESH_SIDE=n for
// another side): PLY (binary and ASCII), OBJ, STL, glTF and GLB, and a glTF scene of that terrain with instances.
// Their bytes_per_second (and MB_per_s) is the file's size over the wall-clock time of one write, e.g.
//   build/release/bench/orogen_bench_writers --benchmark_filter='Mesh|Scene' --benchmark_min_time=2
//
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
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/mesh.h"
#include "graph/points.h"
#include "graph/scene.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_file.h"
#include "nodes/io/mesh_file.h"
#include "nodes/scatter/scene_gltf.h"

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

// A grid mesh of side^2 vertices (2 (side - 1)^2 triangles) over a rolling surface, with normals and colors as
// the terrain mesher gives them.
const Mesh& grid_mesh() {
  static const Mesh m = [] {
    const char* env = std::getenv("OROGEN_BENCH_MESH_SIDE");
    const int side = env ? std::max(2, std::atoi(env)) : 1025;
    Mesh out;
    TriMesh& t = out.mesh;
    t.reserve(static_cast<std::size_t>(side) * side, 3u * side * side, 2u * side * side);
    std::vector<TriMesh::VertexHandle> v;
    v.reserve(static_cast<std::size_t>(side) * side);
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const float x = 16.0f * i, y = 16.0f * j;
        const float z = 300.0f * std::sin(x / 900.0f) * std::cos(y / 1300.0f) + 0.37f * ((i * 7 + j * 13) % 17);
        const auto h = t.add_vertex({x, y, z});
        t.set_color(h, {0.2f + 0.5f * z / 300.0f, 0.45f, 0.3f, 1.0f});
        v.push_back(h);
      }
    for (int j = 0; j + 1 < side; ++j)
      for (int i = 0; i + 1 < side; ++i) {
        const auto a = v[static_cast<std::size_t>(j) * side + i], b = v[static_cast<std::size_t>(j) * side + i + 1];
        const auto c = v[static_cast<std::size_t>(j + 1) * side + i],
                   d = v[static_cast<std::size_t>(j + 1) * side + i + 1];
        t.add_face(a, b, d);
        t.add_face(a, d, c);
      }
    t.update_normals();
    return out;
  }();
  return m;
}

// Output bytes per second: the file's size over the write's wall time.
void finish_file(benchmark::State& state, const fs::path& path) {
  const double bytes = static_cast<double>(fs::file_size(path));
  state.SetBytesProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) * bytes));
  state.counters["MB_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * bytes / 1e6, benchmark::Counter::kIsRate);
  state.counters["file_MB"] = bytes / 1e6;
  state.counters["triangles"] = static_cast<double>(grid_mesh().face_count());
  fs::remove(path);
}

void MeshFile(benchmark::State& state, const char* name, bool binary) {
  const Mesh& m = grid_mesh();
  const fs::path path = scratch(name);
  MeshWriteOptions options;
  options.binary = binary;
  for (auto _ : state) {
    remove_untimed(state, path);
    write_mesh_file(m, path, *mesh_format_from_path(path), options);
  }
  finish_file(state, path);
}

// The terrain and 10,000 instances of two small meshes, as WriteScene writes them.
void SceneFile(benchmark::State& state, const char* name, bool binary) {
  static const auto plant = [] {
    auto p = std::make_shared<Mesh>();
    TriMesh& t = p->mesh;
    const auto a = t.add_vertex({0, 0, 0}), b = t.add_vertex({1, 0, 0}), c = t.add_vertex({0, 1, 2});
    t.add_face(a, b, c);
    t.update_normals();
    return p;
  }();
  static const Scene scene = [] {
    Scene s;
    auto pts = std::make_shared<Points>();
    for (int k = 0; k < 10000; ++k) pts->add({1.5f * (k % 100), 2.5f * (k / 100), 3.0f}, k % 2);
    s.instances = pts;
    s.classes[0] = SceneClass{"plant_a", plant, false};
    s.classes[1] = SceneClass{"plant_b", plant, false};
    return s;
  }();
  SceneContent content;
  content.terrain = &grid_mesh();
  content.scene = &scene;
  const fs::path path = scratch(name);
  for (auto _ : state) {
    remove_untimed(state, path);
    write_scene_gltf(content, path, binary);
  }
  finish_file(state, path);
}

}  // namespace

BENCHMARK_CAPTURE(MeshFile, ply_binary, "m.ply", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(MeshFile, ply_ascii, "m.ply", false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(MeshFile, obj, "m.obj", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(MeshFile, stl_binary, "m.stl", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(MeshFile, glb, "m.glb", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(MeshFile, gltf, "m.gltf", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(SceneFile, glb, "s.glb", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(SceneFile, gltf, "s.gltf", false)->Unit(benchmark::kMillisecond)->UseRealTime();

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
