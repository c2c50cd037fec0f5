#include "nodes/scatter/scene_gltf.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "nodes/common/work_poll.h"
#include "nodes/io/gltf_bytes.h"

namespace orogen {
namespace {

// Adds a buffer view of `bytes` bytes written by `emit`; returns its index.
int add_view(tinygltf::Model& m, GltfBuffer& buffer, std::size_t bytes, GltfBuffer::Emit emit, int target) {
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = buffer.add(bytes, std::move(emit));
  v.byteLength = bytes;
  if (target) v.target = target;
  m.bufferViews.push_back(v);
  return static_cast<int>(m.bufferViews.size() - 1);
}

// A float accessor over `values` (kept alive by `buffer`'s segment until the file is written).
int add_accessor(tinygltf::Model& m, GltfBuffer& buffer, std::shared_ptr<const std::vector<float>> values,
                 int components, int type, int target, bool minmax = false) {
  tinygltf::Accessor a;
  const std::size_t bytes = values->size() * sizeof(float);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.count = values->size() / static_cast<std::size_t>(components);
  a.type = type;
  if (minmax && a.count) {
    a.minValues.assign(components, INFINITY);
    a.maxValues.assign(components, -INFINITY);
    for (std::size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < components; ++c) {
        const double v = (*values)[i * components + c];
        a.minValues[c] = std::min(a.minValues[c], v);
        a.maxValues[c] = std::max(a.maxValues[c], v);
      }
  }
  a.bufferView = add_view(
      m, buffer, bytes,
      [values](const GltfBuffer::Sink& sink) { sink(values->data(), values->size() * sizeof(float)); }, target);
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size() - 1);
}

// The mesh as one triangle primitive: POSITION, NORMAL (unit length; +z where the mesh's is zero), COLOR_0,
// uint32 indices, written from the mesh itself when the file is written (the mesh is stored once, never
// copied). Returns the mesh index.
int add_mesh(tinygltf::Model& m, GltfBuffer& buffer, const Mesh& mesh, const std::string& name, ProgressPoll& poll) {
  const TriMesh& t = mesh.mesh;
  std::size_t nv = 0, nf = 0;
  std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
  for (auto v : t.vertices()) {
    const auto p = t.point(v);
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], double(p[c])), hi[c] = std::max(hi[c], double(p[c]));
    ++nv;
    poll();
  }
  for (auto f : t.faces()) {
    (void)f;
    ++nf;
  }
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const auto accessor = [&](std::size_t components, int type, GltfBuffer::Emit emit, bool minmax) {
    tinygltf::Accessor a;
    a.bufferView = add_view(m, buffer, nv * components * sizeof(float), std::move(emit), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.count = nv;
    a.type = type;
    if (minmax && nv) a.minValues = lo, a.maxValues = hi;
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size() - 1);
  };
  prim.attributes["POSITION"] = accessor(
      3, TINYGLTF_TYPE_VEC3,
      [&t](const GltfBuffer::Sink& sink) {
        SinkStaging<OpenMesh::Vec3f> out(sink);
        for (auto v : t.vertices()) out.push(t.point(v));
        out.done();
      },
      true);
  if (t.has_vertex_normals())
    prim.attributes["NORMAL"] = accessor(
        3, TINYGLTF_TYPE_VEC3,
        [&t](const GltfBuffer::Sink& sink) {
          SinkStaging<OpenMesh::Vec3f> out(sink);
          for (auto v : t.vertices()) {
            auto n = t.normal(v);
            const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (len > 0 && std::isfinite(len))
              n /= len;
            else
              n = OpenMesh::Vec3f(0, 0, 1);
            out.push(n);
          }
          out.done();
        },
        false);
  if (t.has_vertex_colors())
    prim.attributes["COLOR_0"] = accessor(
        4, TINYGLTF_TYPE_VEC4,
        [&t](const GltfBuffer::Sink& sink) {
          SinkStaging<OpenMesh::Vec4f> out(sink);
          for (auto v : t.vertices()) out.push(t.color(v));
          out.done();
        },
        false);
  tinygltf::Accessor ia;
  ia.bufferView = add_view(
      m, buffer, nf * 3 * sizeof(std::uint32_t),
      [&t](const GltfBuffer::Sink& sink) {
        SinkStaging<std::uint32_t> out(sink);
        for (auto f : t.faces())
          for (auto v : t.fv_range(f)) out.push(static_cast<std::uint32_t>(v.idx()));
        out.done();
      },
      TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  ia.count = nf * 3;
  ia.type = TINYGLTF_TYPE_SCALAR;
  m.accessors.push_back(ia);
  prim.indices = static_cast<int>(m.accessors.size() - 1);
  prim.material = 0;
  tinygltf::Mesh gm;
  gm.name = name;
  gm.primitives.push_back(prim);
  m.meshes.push_back(gm);
  return static_cast<int>(m.meshes.size() - 1);
}

int add_node(tinygltf::Model& m, tinygltf::Node n) {
  m.nodes.push_back(std::move(n));
  return static_cast<int>(m.nodes.size() - 1);
}

}  // namespace

std::size_t write_scene_gltf(const SceneContent& scene, const std::filesystem::path& path, bool binary,
                             const WriteProgress& progress) {
  // Cancellation (through `progress`) is polled per block of vertices, faces and instances while the model is
  // built, and per 64 KiB while it is written: a scene of millions of instances stops within milliseconds.
  // The units: the terrain's vertices and faces, each class's scan of the instances, and the instances.
  std::size_t units = scene.terrain ? scene.terrain->mesh.n_vertices() + scene.terrain->mesh.n_faces() : 0;
  if (scene.scene && scene.scene->instances)
    units += scene.scene->instances->size() * (scene.scene->classes.size() + 1);
  ProgressPoll poll(progress, static_cast<double>(units), 0.0, 0.2);
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "Orogen";
  m.buffers.resize(1);
  GltfBuffer buffer;
  tinygltf::Material mat;
  mat.name = "default";
  mat.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  mat.pbrMetallicRoughness.metallicFactor = 0.0;
  mat.pbrMetallicRoughness.roughnessFactor = 0.9;
  mat.doubleSided = true;
  m.materials.push_back(mat);

  tinygltf::Node root;
  root.name = "orogen";
  root.rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};  // x, y, z, w: -90 degrees about x (z up -> y up)
  std::vector<int> children;
  if (scene.terrain) {
    tinygltf::Node n;
    n.name = "terrain";
    n.mesh = add_mesh(m, buffer, *scene.terrain, "terrain", poll);
    children.push_back(add_node(m, n));
  }
  std::size_t instances = 0;
  if (scene.scene && scene.scene->instances) {
    scene.scene->check_consistent();
    const Points& pts = *scene.scene->instances;
    bool gpu = false;
    for (const auto& [cls, entry] : scene.scene->classes) {
      std::vector<std::size_t> members;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        if (pts.class_id[i] == cls) members.push_back(i);
        poll();
      }
      if (members.empty()) continue;
      const std::string& name = entry.name;
      ProgressPoll mesh_poll(progress, 1.0, 0.0, 0.0);  // a class's mesh: polled, its progress not counted
      const int mesh_index = add_mesh(m, buffer, *entry.mesh, name, mesh_poll);
      tinygltf::Value::Object extras;
      extras["class_id"] = tinygltf::Value(static_cast<int>(cls));
      if (scene.instancing == SceneInstancing::GpuInstancing) {
        auto tr = std::make_shared<std::vector<float>>(), rot = std::make_shared<std::vector<float>>(),
             sc = std::make_shared<std::vector<float>>();
        for (std::size_t i : members) {
          const auto& p = pts.position[i];
          const auto& q = pts.rotation[i];
          const auto& s = pts.scale[i];
          tr->insert(tr->end(), {p.x, p.y, p.z});
          rot->insert(rot->end(), {q.x, q.y, q.z, q.w});
          sc->insert(sc->end(), {s.x, s.y, s.z});
          poll();
        }
        tinygltf::Value::Object attrs;
        attrs["TRANSLATION"] = tinygltf::Value(add_accessor(m, buffer, tr, 3, TINYGLTF_TYPE_VEC3, 0, true));
        attrs["ROTATION"] = tinygltf::Value(add_accessor(m, buffer, rot, 4, TINYGLTF_TYPE_VEC4, 0));
        attrs["SCALE"] = tinygltf::Value(add_accessor(m, buffer, sc, 3, TINYGLTF_TYPE_VEC3, 0));
        tinygltf::Value::Object ext;
        ext["attributes"] = tinygltf::Value(attrs);
        tinygltf::Node n;
        n.name = name;
        n.mesh = mesh_index;
        n.extensions["EXT_mesh_gpu_instancing"] = tinygltf::Value(ext);
        n.extras = tinygltf::Value(extras);
        children.push_back(add_node(m, n));
        gpu = true;
      } else {
        tinygltf::Node group;
        group.name = name;
        group.extras = tinygltf::Value(extras);
        for (std::size_t i : members) {
          const auto& p = pts.position[i];
          const auto& q = pts.rotation[i];
          const auto& s = pts.scale[i];
          tinygltf::Node n;
          n.mesh = mesh_index;
          n.translation = {p.x, p.y, p.z};
          n.rotation = {q.x, q.y, q.z, q.w};
          n.scale = {s.x, s.y, s.z};
          group.children.push_back(add_node(m, n));
          poll();
        }
        children.push_back(add_node(m, group));
      }
      instances += members.size();
    }
    // Required, not only used: a viewer without the extension would draw each class's mesh once at the class
    // node (the origin, under the terrain) as glTF's fallback; required, it says why it cannot show the file.
    if (gpu) {
      m.extensionsUsed.push_back("EXT_mesh_gpu_instancing");
      m.extensionsRequired.push_back("EXT_mesh_gpu_instancing");
    }
  }
  root.children = children;
  const int root_index = add_node(m, root);
  tinygltf::Scene s;
  s.name = "scene";
  s.nodes = {root_index};
  m.scenes.push_back(s);
  m.defaultScene = 0;
  // Buffers are embedded (base64 in .gltf, the BIN chunk in .glb): the file stands alone. Every byte is written
  // through a checked file (tinygltf's own file writer ignores a full disk), the arrays straight from the meshes.
  poll.check();  // the model is described
  write_gltf_model(m, buffer, path, binary, [&progress](double written) {
    if (progress) progress(0.2 + 0.8 * written);
  });
  if (progress) progress(1.0);
  return instances;
}

}  // namespace orogen
