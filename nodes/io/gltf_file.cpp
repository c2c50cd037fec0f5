// glTF 2.0 (Khronos 2017) through tinygltf (Debian libtinygltf-dev): one mesh, one node, vertex colors,
// normals and texture coordinates, 32-bit indices; .gltf with the buffer embedded as a data URI or binary .glb.
#include <cstring>

#include <tiny_gltf.h>

#include "graph/mesh.h"
#include "nodes/common/work_poll.h"
#include "nodes/io/gltf_bytes.h"
#include "nodes/io/mesh_file.h"

namespace orogen {
namespace {

template <class T>
int add_view(tinygltf::Model& m, const std::vector<T>& data, int target) {
  auto& buffer = m.buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = data.size() * sizeof(T);
  view.target = target;
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  buffer.insert(buffer.end(), bytes, bytes + view.byteLength);
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

}  // namespace

void write_gltf_file(const Mesh& mesh, const std::filesystem::path& path, bool binary, bool normals, bool colors,
                     bool uvs, const std::string& name, const WriteProgress& progress) {
  const TriMesh& src = mesh.mesh;
  const std::size_t nv = src.n_vertices();
  // Cancellation polled per block of vertices and faces, then per 64 KiB written.
  ProgressPoll poll(progress, static_cast<double>(nv + src.n_faces()), 0.0, 0.9);
  std::vector<float> position, normal, color, texcoord;
  std::vector<std::uint32_t> index;
  position.reserve(nv * 3);
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const bool has_uv = uvs && src.has_vertex_texcoords2D();
  for (auto v : src.vertices()) {
    // glTF is y-up, right-handed: (x, y, z) -> (x, z, -y).
    const auto p = src.point(v);
    const float q[3] = {p[0], p[2], -p[1]};
    for (int k = 0; k < 3; ++k) {
      lo[k] = v.idx() == 0 ? q[k] : std::min(lo[k], q[k]);
      hi[k] = v.idx() == 0 ? q[k] : std::max(hi[k], q[k]);
      position.push_back(q[k]);
    }
    if (normals && src.has_vertex_normals()) {
      const auto n = src.normal(v);
      normal.insert(normal.end(), {n[0], n[2], -n[1]});
    }
    if (colors && src.has_vertex_colors()) {
      const auto c = src.color(v);  // linear, as glTF expects
      for (int k = 0; k < 4; ++k) color.push_back(std::clamp(std::isnan(c[k]) ? 1.0f : c[k], 0.0f, 1.0f));
    }
    if (has_uv) {
      const auto t = src.texcoord2D(v);
      texcoord.insert(texcoord.end(), {t[0], 1.0f - t[1]});  // glTF's v runs down the image
    }
    poll();
  }
  for (auto f : src.faces()) {
    for (auto v : src.fv_range(f)) index.push_back(static_cast<std::uint32_t>(v.idx()));
    poll();
  }
  if (index.empty()) throw FileError("cannot write '" + path.string() + "': the mesh has no faces");

  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "Orogen";
  m.buffers.resize(1);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const int pos = add_accessor(m, add_view(m, position, TINYGLTF_TARGET_ARRAY_BUFFER), TINYGLTF_COMPONENT_TYPE_FLOAT,
                               TINYGLTF_TYPE_VEC3, nv);
  m.accessors[static_cast<std::size_t>(pos)].minValues = {lo[0], lo[1], lo[2]};
  m.accessors[static_cast<std::size_t>(pos)].maxValues = {hi[0], hi[1], hi[2]};
  prim.attributes["POSITION"] = pos;
  if (!normal.empty())
    prim.attributes["NORMAL"] = add_accessor(m, add_view(m, normal, TINYGLTF_TARGET_ARRAY_BUFFER),
                                             TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, nv);
  if (!color.empty())
    prim.attributes["COLOR_0"] = add_accessor(m, add_view(m, color, TINYGLTF_TARGET_ARRAY_BUFFER),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, nv);
  if (!texcoord.empty())
    prim.attributes["TEXCOORD_0"] = add_accessor(m, add_view(m, texcoord, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                 TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, nv);
  prim.indices = add_accessor(m, add_view(m, index, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, index.size());
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

  poll.check();  // the model is built
  write_gltf_model(m, path, binary, [&progress] {
    if (progress) progress(0.95);
  });
}

}  // namespace orogen
