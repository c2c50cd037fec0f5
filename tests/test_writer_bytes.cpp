// The mesh and scene writers write exactly the bytes they wrote before they were made to stream their
// output: every format and option combination on small meshes, compared by size and FNV-1a hash against
// tests/fixtures/writer_bytes.txt, which the writers of commit 4f981f6 (OpenMesh's PLY/STL writers, tinygltf's
// serializer with the buffers copied into one vector) produced.
//
// To regenerate the manifest (only if a byte change is intended):
//   OROGEN_WRITER_BYTES_OUT=/tmp/wb build/release/tests/orogen_test_writer_bytes
// writes every file to /tmp/wb and the manifest to /tmp/wb/writer_bytes.txt.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "graph/mesh.h"
#include "graph/points.h"
#include "graph/scene.h"
#include "nodes/common/color_space.h"
#include "nodes/io/float_text.h"
#include "nodes/io/mesh_file.h"
#include "nodes/scatter/scene_gltf.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

// A small grid with values that exercise number formatting: negative, fractional, large, an edge on y = 0
// (written "0", not "-0", in y-up files), a zero-length normal (the scene writer substitutes +z), colors out of
// range and NaN (clamped), and optionally one translucent vertex and texture coordinates.
Mesh grid(int nx, int ny, bool translucent, bool texcoords) {
  Mesh m;
  TriMesh& t = m.mesh;
  if (texcoords) t.request_vertex_texcoords2D();
  std::vector<TriMesh::VertexHandle> v;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float x = -1234.5678f + 317.25f * static_cast<float>(i) + 0.001f * static_cast<float>(j);
      const float y = 1000.0f / 3.0f * static_cast<float>(j);
      const float z = std::sin(0.7f * static_cast<float>(i * j)) * 12345.678f - 0.5f;
      const auto h = t.add_vertex({x, y, z});
      const float k = static_cast<float>(i + nx * j);
      t.set_normal(h, (i == 1 && j == 1) ? OpenMesh::Vec3f(0, 0, 0) : OpenMesh::Vec3f(0.1f * k - 1.0f, 0.3f, 1.0f));
      OpenMesh::Vec4f c(0.013f * k, 1.0f - 0.05f * k, 0.5f, 1.0f);
      if (i == 2 && j == 0) c = {1.5f, -0.2f, std::nanf(""), 1.0f};
      if (translucent && i == 0 && j == 1) c[3] = 0.25f;
      t.set_color(h, c);
      if (texcoords) t.set_texcoord2D(h, {static_cast<float>(i) / (nx - 1), 0.37f * static_cast<float>(j)});
      v.push_back(h);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const auto a = v[static_cast<std::size_t>(i + nx * j)], b = v[static_cast<std::size_t>(i + 1 + nx * j)];
      const auto c = v[static_cast<std::size_t>(i + nx * (j + 1))],
                 d = v[static_cast<std::size_t>(i + 1 + nx * (j + 1))];
      t.add_face(a, b, d);
      t.add_face(a, d, c);
    }
  t.update_face_normals();
  return m;
}

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Written {
  std::map<std::string, std::string> manifest;  // file name -> "size hash"
  fs::path dir;
  bool keep = false;

  void add(const std::string& name) {
    const fs::path path = dir / name;
    const std::string bytes = read_bytes(path);
    std::ostringstream s;
    s << bytes.size() << ' ' << std::hex << fnv1a(bytes);
    manifest[name] = s.str();
    if (!keep) fs::remove(path);
  }
};

const char* const kExtensions[] = {"obj", "ply", "stl", "gltf", "glb"};

Written write_everything() {
  Written w;
  if (const char* out = std::getenv("OROGEN_WRITER_BYTES_OUT")) {
    w.dir = out;
    w.keep = true;
    fs::create_directories(w.dir);
  } else {
    w.dir = test::scratch_dir("writer_bytes");
  }
  const Mesh meshes[] = {grid(5, 4, false, false), grid(4, 3, true, false), grid(3, 3, false, true)};
  for (int mi = 0; mi < 3; ++mi)
    for (const char* ext : kExtensions)
      for (int bits = 0; bits < 64; ++bits) {
        MeshWriteOptions o;
        o.y_up = bits & 1;
        o.binary = bits & 2;
        o.normals = bits & 4;
        o.colors = bits & 8;
        o.uvs = bits & 16;
        if (bits & 32) o.material_library = "terrain.mtl";
        o.name = "mesh_" + std::to_string(mi);
        const std::string e = ext;
        // Options a format ignores are skipped: the same bytes again would only slow the test.
        if (e != "obj" && (bits & 32)) continue;
        if ((e == "obj" || e == "gltf" || e == "glb") && (bits & 2)) continue;
        if ((e == "stl" || e == "ply") && (bits & 16)) continue;
        if ((e == "stl" || e == "obj") && (bits & 8)) continue;
        if ((e == "gltf" || e == "glb") && (bits & 1)) continue;
        if (e == "stl" && (bits & 4)) continue;
        const std::string name = "m" + std::to_string(mi) + "_" + std::to_string(bits) + "." + e;
        const fs::path path = w.dir / name;
        fs::remove(path);
        write_mesh_file(meshes[mi], path, *mesh_format_from_path(path), o);
        w.add(name);
      }
  // Scenes: terrain alone, instances alone, both; GPU instancing and one node per instance; .gltf and .glb.
  auto terrain = std::make_shared<Mesh>(grid(5, 4, true, false));
  auto plant = std::make_shared<Mesh>(grid(3, 2, false, false));
  auto rock = std::make_shared<Mesh>(grid(2, 2, false, true));
  auto points = std::make_shared<Points>();
  for (int k = 0; k < 7; ++k) {
    points->add({10.5f * k - 3.0f, 0.25f * k * k, 1.0f / (k + 1)}, k % 3 == 0 ? 4 : 1);
    points->rotation.back() = glm::normalize(glm::quat(1.0f, 0.1f * k, -0.2f, 0.05f * k));
    points->scale.back() = {1.0f + 0.1f * k, 0.9f, 1.25f};
  }
  Scene scene;
  scene.instances = points;
  scene.classes[1] = SceneClass{"plant", plant, false};
  scene.classes[2] = SceneClass{"unused", plant, false};  // no instances: left out of the file
  scene.classes[4] = SceneClass{"rock", rock, true};
  for (int content = 1; content < 4; ++content)
    for (int inst = 0; inst < 2; ++inst)
      for (int binary = 0; binary < 2; ++binary) {
        SceneContent c;
        if (content & 1) c.terrain = terrain.get();
        if (content & 2) c.scene = &scene;
        c.instancing = inst ? SceneInstancing::Nodes : SceneInstancing::GpuInstancing;
        if (!(content & 2) && inst) continue;
        const std::string name =
            "scene_" + std::to_string(content) + "_" + std::to_string(inst) + (binary ? ".glb" : ".gltf");
        fs::remove(w.dir / name);
        write_scene_gltf(c, w.dir / name, binary);
        w.add(name);
      }
  return w;
}

TEST(WriterBytes, EveryFormatAndOptionWritesTheReferenceBytes) {
  const Written w = write_everything();
  if (w.keep) {
    std::ofstream out(w.dir / "writer_bytes.txt");
    for (const auto& [name, line] : w.manifest) out << name << ' ' << line << '\n';
    GTEST_SKIP() << "wrote " << w.manifest.size() << " files and the manifest to " << w.dir;
  }
  std::map<std::string, std::string> reference;
  const fs::path manifest = test::source_dir() / "tests" / "fixtures" / "writer_bytes.txt";
  std::ifstream in(manifest);
  ASSERT_TRUE(in) << "cannot read " << manifest;
  std::string name, size, hash;
  while (in >> name >> size >> hash) reference[name] = size + " " + hash;
  ASSERT_EQ(reference.size(), w.manifest.size()) << "the manifest lists other combinations than the test writes";
  for (const auto& [file, line] : w.manifest) {
    const auto it = reference.find(file);
    ASSERT_NE(it, reference.end()) << file << " is not in the manifest";
    EXPECT_EQ(line, it->second) << file << ": size and hash differ from the reference writer's";
  }
}

// PLY colors: the table lookup gives the byte of the pow-per-channel chain for every float at and around each
// code's threshold, on a dense sweep of [0, 1] (every 97th float) and outside it.
TEST(WriterBytes, SrgbByteTableMatchesThePowChain) {
  for (std::uint32_t bits = 0; bits <= std::bit_cast<std::uint32_t>(1.0f); bits += 97) {
    const float c = std::bit_cast<float>(bits);
    ASSERT_EQ(srgb_byte(c), srgb_byte_reference(c)) << c;
  }
  for (int b = 1; b < 256; ++b) {
    std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);  // the first float reaching code b
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (srgb_byte_reference(std::bit_cast<float>(mid)) >= b)
        hi = mid;
      else
        lo = mid + 1;
    }
    ASSERT_GE(srgb_byte_reference(std::bit_cast<float>(lo)), b);
    for (std::uint32_t k = lo - 32; k <= lo + 32; ++k)
      ASSERT_EQ(srgb_byte(std::bit_cast<float>(k)), srgb_byte_reference(std::bit_cast<float>(k))) << k;
  }
  for (float c : {-1.0f, -0.0f, 1.0f, 1.5f, 1e30f, std::nanf(""), INFINITY, -INFINITY})
    EXPECT_EQ(srgb_byte(c), srgb_byte_reference(c)) << c;
}

// The text formats' number formatting is printf's %.{6,9,10}g (std::to_chars with the same precision) for
// every float tried: random bit patterns (all magnitudes), random terrain-like values, powers of ten and their
// neighbours (where the exponent guess and carries go wrong), decimal halves (ties), zeros, NaN, infinities.
template <int P>
void expect_same_text(float v) {
  char fast[64], exact[64];
  char* f = format_float_g<P>(fast, v);
  char* x = std::to_chars(exact, exact + sizeof exact, v, std::chars_format::general, P).ptr;
  ASSERT_EQ(std::string(fast, f), std::string(exact, x))
      << "precision " << P << ", bits " << std::bit_cast<std::uint32_t>(v);
}

TEST(WriterBytes, FloatTextMatchesPrintf) {
  std::mt19937 rng(7);
  std::vector<float> values;
  for (int i = 0; i < 400000; ++i) values.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(rng())));
  std::uniform_real_distribution<float> terrain(-20000.0f, 20000.0f), unit(-1.0f, 1.0f);
  for (int i = 0; i < 400000; ++i) values.push_back(terrain(rng)), values.push_back(unit(rng));
  for (int e = -45; e <= 38; ++e) {
    float t = std::pow(10.0f, static_cast<float>(e));
    for (int k = 0; k < 40; ++k) t = std::nextafter(t, 0.0f);
    for (int k = 0; k < 80; ++k, t = std::nextafter(t, INFINITY)) values.push_back(t), values.push_back(-t);
  }
  for (int i = 0; i < 100000; ++i) values.push_back(static_cast<float>(i) * 0.5f), values.push_back(i * 0.03125f);
  for (float v : {0.0f, -0.0f, std::nanf(""), INFINITY, -INFINITY, 1e-12f, 9.9999999e14f, 1e15f}) values.push_back(v);
  for (float v : values) {
    expect_same_text<6>(v);
    expect_same_text<9>(v);
    expect_same_text<10>(v);
    if (HasFatalFailure()) return;
  }
}

}  // namespace
}  // namespace orogen
