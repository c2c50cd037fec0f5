// Properties of what the example graphs write, read back from the files as the tools users import them into
// would read them: every instance of a written scene stands on that scene's own terrain mesh, every splat
// image's weights sum to one (255) per pixel. Each example is evaluated once, small, for all the checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

// Every example graph evaluated at 65² into its own folder (graph name -> folder); failures are recorded. The
// checks share one test: ctest runs each test in a process of its own, which would evaluate them all again.
class ExampleOutputs : public ::testing::Test {
 public:
  static void SetUpTestSuite() {
    root_ = new fs::path(scratch_dir("example-outputs"));
    results_ = new std::map<std::string, ProcessResult>;
    for (const auto& entry : fs::directory_iterator(source_dir() / "graphs")) {
      if (entry.path().extension() != ".json") continue;
      const std::string name = entry.path().stem().string();
      (*results_)[name] = run_process(
          cli_binary(), {"eval", entry.path().string(), "--resolution", "65", "-q", "-o", (*root_ / name).string()});
    }
  }
  static void TearDownTestSuite() {
    delete root_;
    delete results_;
  }
  // Files with one of `extensions` written by every example that ran, by graph name.
  static std::vector<std::pair<std::string, fs::path>> written(const std::vector<std::string>& extensions) {
    std::vector<std::pair<std::string, fs::path>> files;
    for (const auto& [name, result] : *results_) {
      if (result.exit_code != 0 || !fs::exists(*root_ / name)) continue;
      for (const auto& e : fs::recursive_directory_iterator(*root_ / name))
        if (e.is_regular_file() &&
            std::find(extensions.begin(), extensions.end(), e.path().extension().string()) != extensions.end())
          files.emplace_back(name, e.path());
    }
    std::sort(files.begin(), files.end());
    return files;
  }
  static const std::map<std::string, ProcessResult>& results() { return *results_; }
  static fs::path output_dir(const std::string& graph) { return *root_ / graph; }

 private:
  static inline fs::path* root_ = nullptr;
  static inline std::map<std::string, ProcessResult>* results_ = nullptr;
};

// --- scenes ---------------------------------------------------------------------------------------------------

struct Vec3 {
  double x, y, z;
};

std::vector<Vec3> accessor_vec3(const tinygltf::Model& m, int index) {
  const auto& a = m.accessors.at(index);
  const auto& v = m.bufferViews.at(a.bufferView);
  const std::size_t stride = v.byteStride ? v.byteStride : 3 * sizeof(float);
  const unsigned char* base = m.buffers.at(v.buffer).data.data() + v.byteOffset + a.byteOffset;
  std::vector<Vec3> out(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    const float* f = reinterpret_cast<const float*>(base + i * stride);
    out[i] = {f[0], f[1], f[2]};
  }
  return out;
}

std::vector<std::uint32_t> accessor_indices(const tinygltf::Model& m, int index) {
  const auto& a = m.accessors.at(index);
  const auto& v = m.bufferViews.at(a.bufferView);
  const unsigned char* base = m.buffers.at(v.buffer).data.data() + v.byteOffset + a.byteOffset;
  std::vector<std::uint32_t> out(a.count);
  for (std::size_t i = 0; i < a.count; ++i)
    out[i] = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT ? reinterpret_cast<const std::uint32_t*>(base)[i]
             : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                 ? reinterpret_cast<const std::uint16_t*>(base)[i]
                 : base[i];
  return out;
}

// The terrain's triangles and every instance's base, in the coordinates below the root node (Orogen's: z up).
struct WrittenScene {
  std::vector<std::array<Vec3, 3>> triangles;
  std::vector<Vec3> bases;
};

WrittenScene read_scene(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? loader.LoadBinaryFromFile(&m, &err, &warn, path.string())
                                             : loader.LoadASCIIFromFile(&m, &err, &warn, path.string());
  EXPECT_TRUE(ok) << path << ": " << err;
  WrittenScene scene;
  for (const auto& node : m.nodes) {
    if (node.name == "terrain" && node.mesh >= 0) {
      for (const auto& prim : m.meshes[node.mesh].primitives) {
        const auto pos = accessor_vec3(m, prim.attributes.at("POSITION"));
        const auto idx = accessor_indices(m, prim.indices);
        for (std::size_t k = 0; k + 2 < idx.size(); k += 3)
          scene.triangles.push_back({pos[idx[k]], pos[idx[k + 1]], pos[idx[k + 2]]});
      }
    } else if (auto ext = node.extensions.find("EXT_mesh_gpu_instancing"); ext != node.extensions.end()) {
      const int translation = ext->second.Get("attributes").Get("TRANSLATION").GetNumberAsInt();
      for (const auto& p : accessor_vec3(m, translation)) scene.bases.push_back(p);
    } else if (node.mesh >= 0 && node.translation.size() == 3) {
      scene.bases.push_back({node.translation[0], node.translation[1], node.translation[2]});
    }
  }
  return scene;
}

// The highest surface over (x, y) among the triangles covering it: barycentric, with the triangles binned in
// 64 x 64 buckets over the mesh's bounds (independent of the writer's own search structure).
class Surface {
 public:
  explicit Surface(const WrittenScene& s) : s_(s) {
    for (const auto& t : s.triangles)
      for (const auto& p : t)
        x0_ = std::min(x0_, p.x), x1_ = std::max(x1_, p.x), y0_ = std::min(y0_, p.y), y1_ = std::max(y1_, p.y);
    for (std::size_t k = 0; k < s.triangles.size(); ++k) {
      const auto& t = s.triangles[k];
      const auto [xa, xb] = std::minmax({t[0].x, t[1].x, t[2].x});
      const auto [ya, yb] = std::minmax({t[0].y, t[1].y, t[2].y});
      for (int j = bin(ya, y0_, y1_); j <= bin(yb, y0_, y1_); ++j)
        for (int i = bin(xa, x0_, x1_); i <= bin(xb, x0_, x1_); ++i) bins_[j * kBins + i].push_back(k);
    }
  }
  std::optional<double> at(double x, double y) const {
    std::optional<double> best;
    for (std::size_t k : bins_[bin(y, y0_, y1_) * kBins + bin(x, x0_, x1_)]) {
      const auto& t = s_.triangles[k];
      const double d = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
      if (d == 0.0) continue;
      const double l1 = ((x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (y - t[0].y)) / d;
      const double l2 = ((t[1].x - t[0].x) * (y - t[0].y) - (x - t[0].x) * (t[1].y - t[0].y)) / d;
      const double l0 = 1.0 - l1 - l2;
      if (l0 < -1e-7 || l1 < -1e-7 || l2 < -1e-7) continue;
      const double z = l0 * t[0].z + l1 * t[1].z + l2 * t[2].z;
      if (!best || z > *best) best = z;
    }
    return best;
  }

 private:
  static constexpr int kBins = 64;
  static int bin(double v, double lo, double hi) {
    return std::clamp(static_cast<int>((v - lo) / (hi - lo) * kBins), 0, kBins - 1);
  }
  const WrittenScene& s_;
  double x0_ = INFINITY, x1_ = -INFINITY, y0_ = INFINITY, y1_ = -INFINITY;
  std::vector<std::vector<std::size_t>> bins_ = std::vector<std::vector<std::size_t>>(kBins * kBins);
};

void expect_every_instance_on_its_scenes_mesh() {
  int scenes = 0;
  for (const auto& [name, path] : ExampleOutputs::written({".glb", ".gltf"})) {
    const WrittenScene s = read_scene(path);
    if (s.triangles.empty() || s.bases.empty()) continue;  // a mesh alone, or a scene without terrain
    ++scenes;
    const Surface surface(s);
    double worst = 0.0;
    std::size_t outside = 0;
    for (const auto& b : s.bases) {
      const auto z = surface.at(b.x, b.y);
      if (!z) {
        ++outside;
        continue;
      }
      worst = std::max(worst, std::abs(b.z - *z));
    }
    // The examples sink some stems by 0.1 m on purpose; the mesh itself is metres off the exact heightfield.
    EXPECT_LE(worst, 0.11) << name << ": " << path.filename() << ", " << s.bases.size() << " instances";
    EXPECT_EQ(outside, 0u) << name << ": instances outside the terrain mesh";
  }
  EXPECT_GE(scenes, 5);  // forest, game_world, rural_resources, seamscape, voronoi_island, ...
}

// --- splat weights ---------------------------------------------------------------------------------------------

// The files each SplatWeights node's weights were written to, grouped so that one group holds every layer once:
// its `out` (one channel per layer), or its `splat0` and `splat1` (four layers each).
std::vector<std::vector<fs::path>> splat_groups(const fs::path& graph_file, const fs::path& output_dir) {
  const auto graph = nlohmann::json::parse(read_text(graph_file));
  std::map<std::string, std::string> splat_nodes;  // id -> type
  for (const auto& n : graph["nodes"])
    if (n.value("type", "") == "SplatWeights") splat_nodes[n["id"]] = "";
  std::map<std::string, std::vector<fs::path>> groups;
  for (const auto& n : graph["nodes"]) {
    const std::string type = n.value("type", "");
    if (type != "WriteImage" || !n.contains("inputs") || !n["inputs"].contains("in")) continue;
    const std::string link = n["inputs"]["in"];
    const auto dot = link.find('.');
    const std::string node = link.substr(0, dot), port = link.substr(dot + 1);
    if (!splat_nodes.count(node)) continue;
    const std::string path = n["params"].value("path", "image.png");
    groups[node + (port == "out" ? ".out" : ".splat")].push_back(output_dir / path);
  }
  std::vector<std::vector<fs::path>> out;
  for (auto& [key, files] : groups) out.push_back(files);
  return out;
}

void expect_splat_weights_sum_to_one() {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(source_dir() / "graphs")) {
    if (entry.path().extension() != ".json") continue;
    const std::string name = entry.path().stem().string();
    if (ExampleOutputs::results().at(name).exit_code != 0) continue;
    for (const auto& files : splat_groups(entry.path(), ExampleOutputs::output_dir(name))) {
      SCOPED_TRACE(name + ": " + files.front().filename().string());
      std::vector<double> sum;
      double one = 1.0, rounding = 1e-5;
      int channels = 0;
      for (const auto& file : files) {
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);  // the weights as stored: no premultiplication by alpha
        auto in = OIIO::ImageInput::open(file.string(), &config);
        ASSERT_TRUE(in) << file << ": " << OIIO::geterror();
        const OIIO::ImageSpec& spec = in->spec();
        std::vector<float> px(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
        // Normalized: 8-bit 255 and 16-bit 65535 read as 1.0 with no transfer curve applied.
        ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
        if (spec.format == OIIO::TypeDesc::UINT8) one = 255.0, rounding = 0.5;
        if (spec.format == OIIO::TypeDesc::UINT16) one = 65535.0, rounding = 0.5;
        sum.resize(static_cast<std::size_t>(spec.width) * spec.height, 0.0);
        for (std::size_t k = 0; k < sum.size(); ++k)
          for (int c = 0; c < spec.nchannels; ++c) sum[k] += std::round(px[k * spec.nchannels + c] * one * 1e6) / 1e6;
        channels += spec.nchannels;
      }
      double worst = 0.0;
      for (double v : sum) worst = std::max(worst, std::abs(v - one));
      EXPECT_LE(worst, rounding * channels) << "weights sum to " << one << " +- " << worst;
      ++checked;
    }
  }
  EXPECT_GE(checked, 3);  // forest's splat.png, textured_terrain's splat0+splat1 and weights.exr
}

TEST_F(ExampleOutputs, EveryExampleRunsAndWritesWhatImportersRead) {
  for (const auto& [name, result] : results()) EXPECT_EQ(result.exit_code, 0) << name << ": " << result.err;
  {
    SCOPED_TRACE("every instance stands on the terrain mesh of its scene");
    expect_every_instance_on_its_scenes_mesh();
  }
  {
    SCOPED_TRACE("every splat image's weights sum to one (255) per pixel");
    expect_splat_weights_sum_to_one();
  }
}

}  // namespace
}  // namespace orogen::test
