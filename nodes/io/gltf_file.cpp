// glTF 2.0 (Khronos 2017) through tinygltf (Debian libtinygltf-dev): one mesh, one node, vertex colors,
// normals and texture coordinates, 32-bit indices; .gltf with the buffer embedded as a data URI or binary .glb.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <tiny_gltf.h>

#include "graph/mesh.h"
#include "nodes/common/work_poll.h"
#include "nodes/io/gltf_bytes.h"
#include "nodes/io/mesh_file.h"

namespace orogen {
namespace {

int add_view(tinygltf::Model& m, GltfBuffer& buffer, std::size_t bytes, GltfBuffer::Emit emit, int target) {
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.add(bytes, std::move(emit));
  view.byteLength = bytes;
  view.target = target;
  m.bufferViews.push_back(view);
  return static_cast<int>(m.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& m, int view, int component, int type, std::size_t count) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size()) - 1;
}

// One float attribute of every vertex, `components` floats each from `get` (v, out), staged for the sink.
template <int components, class Get>
GltfBuffer::Emit vertex_floats(const TriMesh& src, Get get) {
  return [&src, get](const GltfBuffer::Sink& sink) {
    SinkStaging<float> out(sink);
    float q[components];
    for (auto v : src.vertices()) {
      get(v, q);
      for (int k = 0; k < components; ++k) out.push(q[k]);
    }
    out.done();
  };
}

}  // namespace

void write_gltf_file(const Mesh& mesh, const std::filesystem::path& path, bool binary, bool normals, bool colors,
                     bool uvs, const std::string& name, const WriteProgress& progress) {
  const TriMesh& src = mesh.mesh;
  const std::size_t nv = src.n_vertices();
  // Cancellation polled per block of vertices while the bounds are found, then per MiB written: the arrays go
  // from the mesh to the file in one pass.
  ProgressPoll poll(progress, static_cast<double>(nv), 0.0, 0.1);
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  std::size_t live_vertices = 0, live_faces = 0;
  for (auto v : src.vertices()) {
    // glTF is y-up, right-handed: (x, y, z) -> (x, z, -y).
    const auto p = src.point(v);
    const float q[3] = {p[0], p[2], -p[1]};
    for (int k = 0; k < 3; ++k) {
      lo[k] = v.idx() == 0 ? q[k] : std::min(lo[k], q[k]);
      hi[k] = v.idx() == 0 ? q[k] : std::max(hi[k], q[k]);
    }
    ++live_vertices;
    poll();
  }
  for (auto f : src.faces()) {
    (void)f;
    ++live_faces;
  }
  if (live_faces == 0) throw FileError("cannot write '" + path.string() + "': the mesh has no faces");
  const bool has_normal = normals && src.has_vertex_normals(), has_color = colors && src.has_vertex_colors();
  const bool has_uv = uvs && src.has_vertex_texcoords2D();

  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "Orogen";
  m.buffers.resize(1);
  GltfBuffer buffer;
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  // A float attribute of N components per vertex, streamed from the mesh by `get` (vertex, out).
  const auto attribute = [&]<int N>(std::integral_constant<int, N>, int type, auto get) {
    return add_accessor(m,
                        add_view(m, buffer, live_vertices * N * sizeof(float), vertex_floats<N>(src, get),
                                 TINYGLTF_TARGET_ARRAY_BUFFER),
                        TINYGLTF_COMPONENT_TYPE_FLOAT, type, nv);
  };
  constexpr std::integral_constant<int, 2> two;
  constexpr std::integral_constant<int, 3> three;
  constexpr std::integral_constant<int, 4> four;
  // glTF is y-up, right-handed: (x, y, z) -> (x, z, -y).
  const int pos = attribute(three, TINYGLTF_TYPE_VEC3, [&src](auto v, float* q) {
    const auto p = src.point(v);
    q[0] = p[0], q[1] = p[2], q[2] = -p[1];
  });
  m.accessors[static_cast<std::size_t>(pos)].minValues = {lo[0], lo[1], lo[2]};
  m.accessors[static_cast<std::size_t>(pos)].maxValues = {hi[0], hi[1], hi[2]};
  prim.attributes["POSITION"] = pos;
  if (has_normal)
    prim.attributes["NORMAL"] = attribute(three, TINYGLTF_TYPE_VEC3, [&src](auto v, float* q) {
      const auto n = src.normal(v);
      q[0] = n[0], q[1] = n[2], q[2] = -n[1];
    });
  if (has_color)
    prim.attributes["COLOR_0"] = attribute(four, TINYGLTF_TYPE_VEC4, [&src](auto v, float* q) {
      const auto c = src.color(v);  // linear, as glTF expects
      for (int k = 0; k < 4; ++k) q[k] = std::clamp(std::isnan(c[k]) ? 1.0f : c[k], 0.0f, 1.0f);
    });
  if (has_uv)
    prim.attributes["TEXCOORD_0"] = attribute(two, TINYGLTF_TYPE_VEC2, [&src](auto v, float* q) {
      const auto t = src.texcoord2D(v);
      q[0] = t[0], q[1] = 1.0f - t[1];  // glTF's v runs down the image
    });
  const auto indices = [&src](const GltfBuffer::Sink& sink) {
    SinkStaging<std::uint32_t> out(sink);
    for (auto f : src.faces())
      for (auto v : src.fv_range(f)) out.push(static_cast<std::uint32_t>(v.idx()));
    out.done();
  };
  prim.indices = add_accessor(
      m, add_view(m, buffer, live_faces * 3 * sizeof(std::uint32_t), indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, live_faces * 3);
  tinygltf::Material mat;
  mat.name = "orogen";
  mat.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  mat.pbrMetallicRoughness.metallicFactor = 0.0;
  mat.pbrMetallicRoughness.roughnessFactor = 1.0;
  m.materials.push_back(mat);
  prim.material = 0;
  tinygltf::Mesh gm;
  gm.name = name;  // from the graph: the file's own name is a temporary one
  gm.primitives.push_back(prim);
  m.meshes.push_back(gm);
  tinygltf::Node node;
  node.mesh = 0;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m.scenes.push_back(scene);
  m.defaultScene = 0;

  poll.check();  // the model is described
  write_gltf_model(m, buffer, path, binary, [&progress](double written) {
    if (progress) progress(0.1 + 0.9 * written);
  });
}

}  // namespace orogen
