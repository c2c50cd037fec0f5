#include "editor/model/scene_preview.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <set>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "editor/model/preview_image.h"
#include "graph/points.h"
#include "nodes/common/color_space.h"

namespace orogen::editor {

namespace {

const PortDecl* input_decl(const Node& node, const std::string& name) {
  for (const auto& in : node.type->inputs)
    if (in.name == name) return &in;
  return nullptr;
}

PortRef connected(const Node& node, const std::string& port) {
  auto it = node.inputs.find(port);
  return it == node.inputs.end() ? PortRef{} : it->second;
}

}  // namespace

std::vector<std::string> SceneSources::nodes() const {
  std::vector<std::string> out;
  auto add = [&](const PortRef& r) {
    if (!r.node.empty() && std::find(out.begin(), out.end(), r.node) == out.end()) out.push_back(r.node);
  };
  add(scene);
  add(terrain);
  add(ground);
  return out;
}

bool is_scene_writer(const Node& node) {
  if (!node.type) return false;
  const PortDecl* in = input_decl(node, "in");
  return in && in->type == PortType::Scene && node.type->outputs.empty();
}

int scene_output(const Node& node) {
  if (!node.type) return -1;
  for (std::size_t k = 0; k < node.type->outputs.size(); ++k)
    if (node.type->outputs[k].type == PortType::Scene) return static_cast<int>(k);
  return -1;
}

std::optional<SceneSources> scene_sources(const Graph& graph, const std::string& id) {
  const Node* node = graph.find(id);
  if (!node || !node->type) return std::nullopt;
  SceneSources s;
  if (is_scene_writer(*node)) {
    s.writer = true;
    s.scene = connected(*node, "in");
    if (const PortDecl* t = input_decl(*node, "terrain"); t && t->type == PortType::Mesh)
      s.terrain = connected(*node, "terrain");
  } else if (const int k = scene_output(*node); k >= 0) {
    s.scene = PortRef{id, node->type->outputs[static_cast<std::size_t>(k)].name};
  } else {
    return std::nullopt;
  }
  // The ground: breadth-first upstream of the scene, through Scene and Points inputs.
  std::deque<std::string> queue;
  std::set<std::string> seen;
  if (!s.scene.node.empty()) queue.push_back(s.scene.node);
  while (!queue.empty() && s.ground.node.empty()) {
    const std::string cur = queue.front();
    queue.pop_front();
    if (!seen.insert(cur).second) continue;
    const Node* n = graph.find(cur);
    if (!n || !n->type) continue;
    // Terrain inputs by name, most specific first (a density or mask input is never the ground).
    for (const char* name : {"height", "terrain", "ground", "in"}) {
      const PortDecl* in = input_decl(*n, name);
      if (!in || in->type != PortType::Heightfield) continue;
      const PortRef r = connected(*n, name);
      if (!r.node.empty() && resolve_output_kind(graph, r.node, r.port) == OutputKind::Height) {
        s.ground = r;
        break;
      }
    }
    for (const auto& in : n->type->inputs)
      if (in.type == PortType::Points || in.type == PortType::Scene)
        if (const PortRef r = connected(*n, in.name); !r.node.empty()) queue.push_back(r.node);
  }
  return s;
}

namespace {

template <class T>
std::shared_ptr<const T> value_of(const Graph& graph, const PortRef& ref,
                                  const std::map<std::string, std::vector<PortValue>>& outputs) {
  if (ref.node.empty()) return nullptr;
  const Node* n = graph.find(ref.node);
  auto it = outputs.find(ref.node);
  if (!n || !n->type || it == outputs.end()) return nullptr;
  for (std::size_t k = 0; k < n->type->outputs.size() && k < it->second.size(); ++k)
    if (n->type->outputs[k].name == ref.port)
      if (auto* v = std::get_if<std::shared_ptr<const T>>(&it->second[k])) return *v;
  return nullptr;
}

}  // namespace

ScenePreview assemble_scene(const Graph& graph, const SceneSources& sources,
                            const std::map<std::string, std::vector<PortValue>>& outputs) {
  ScenePreview s;
  s.scene = value_of<Scene>(graph, sources.scene, outputs);
  if (s.scene) s.points = s.scene->instances;
  s.terrain = value_of<Mesh>(graph, sources.terrain, outputs);
  s.ground = value_of<Heightfield>(graph, sources.ground, outputs);
  return s;
}

TerrainMesh mesh_geometry(const Mesh& m, const MeshGeometryOptions& options) {
  TerrainMesh out;
  const TriMesh& mesh = m.mesh;
  if (mesh.n_vertices() == 0) return out;
  out.positions.reserve(mesh.n_vertices());
  out.normals.reserve(mesh.n_vertices());
  out.colors.reserve(mesh.n_vertices());
  out.min = glm::vec3(std::numeric_limits<float>::max());
  out.max = glm::vec3(-std::numeric_limits<float>::max());
  bool uniform = true;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const glm::vec3 pos(p[0], p[1], p[2]);
    auto n = mesh.has_vertex_normals() ? mesh.normal(v) : OpenMesh::Vec3f(0, 0, 1);
    glm::vec3 normal(n[0], n[1], n[2]);
    if (!(glm::length(normal) > 0.0f) || !std::isfinite(normal.x + normal.y + normal.z)) normal = {0, 0, 1};
    const auto c = mesh.has_vertex_colors() ? mesh.color(v) : OpenMesh::Vec4f(0.7f, 0.7f, 0.7f, 1.0f);
    const glm::vec4 color(linear_to_srgb(c[0]), linear_to_srgb(c[1]), linear_to_srgb(c[2]),
                          std::clamp(c[3], 0.0f, 1.0f));
    if (!out.colors.empty() && color != out.colors.front()) uniform = false;
    out.positions.push_back(pos);
    out.normals.push_back(glm::normalize(normal));
    out.colors.push_back(color);
    out.min = glm::min(out.min, pos);
    out.max = glm::max(out.max, pos);
  }
  if (options.tint_uniform_by_height && uniform) {
    const float lo = out.min.z, span = std::max(out.max.z - out.min.z, 1e-6f);
    for (std::size_t k = 0; k < out.positions.size(); ++k)
      out.colors[k] = glm::vec4(colormap(ColorMap::Terrain, (out.positions[k].z - lo) / span), 1.0f);
  }
  out.indices.reserve(mesh.n_faces() * 3);
  for (auto f : mesh.faces()) {
    std::vector<std::uint32_t> ring;
    for (auto v : mesh.fv_range(f)) ring.push_back(static_cast<std::uint32_t>(v.idx()));
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
      out.indices.insert(out.indices.end(), {ring[0], ring[k], ring[k + 1]});
  }
  return out;
}

TerrainMesh proxy_geometry(glm::vec4 color) {
  // Flat-shaded: three vertices per face.
  const glm::vec3 bottom(0, 0, 0), top(0, 0, 1);
  const glm::vec3 ring[4] = {{0.5f, 0, 0.5f}, {0, 0.5f, 0.5f}, {-0.5f, 0, 0.5f}, {0, -0.5f, 0.5f}};
  TerrainMesh out;
  auto face = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    for (const glm::vec3& p : {a, b, c}) {
      out.indices.push_back(static_cast<std::uint32_t>(out.positions.size()));
      out.positions.push_back(p);
      out.normals.push_back(n);
      out.colors.push_back(color);
    }
  };
  for (int k = 0; k < 4; ++k) {
    face(top, ring[k], ring[(k + 1) % 4]);
    face(bottom, ring[(k + 1) % 4], ring[k]);
  }
  out.min = {-0.5f, -0.5f, 0.0f};
  out.max = {0.5f, 0.5f, 1.0f};
  return out;
}

glm::vec4 class_color(int cls) {
  static constexpr glm::vec4 kColors[] = {{0.30f, 0.62f, 0.25f, 1}, {0.62f, 0.55f, 0.45f, 1}, {0.85f, 0.75f, 0.25f, 1},
                                          {0.20f, 0.45f, 0.30f, 1}, {0.55f, 0.55f, 0.58f, 1}, {0.70f, 0.40f, 0.75f, 1},
                                          {0.90f, 0.50f, 0.30f, 1}, {0.35f, 0.65f, 0.85f, 1}};
  return kColors[static_cast<unsigned>(cls) % 8];
}

glm::vec4 marker_color(int cls) {
  static constexpr glm::vec4 kColors[] = {{1.0f, 0.31f, 0.31f, 1}, {1.0f, 0.86f, 0.24f, 1}, {0.31f, 0.86f, 1.0f, 1},
                                          {0.78f, 0.47f, 1.0f, 1}, {0.47f, 1.0f, 0.47f, 1}, {1.0f, 0.59f, 0.24f, 1}};
  return kColors[static_cast<unsigned>(cls) % 6];
}

namespace {

// translate(position) * rotate(rotation) * scale(scale) of point k; missing rotations / scales are identity / 1.
glm::mat4 instance_matrix(const Points& points, std::size_t k) {
  const glm::quat q = k < points.rotation.size() ? points.rotation[k] : glm::quat(1, 0, 0, 0);
  const glm::vec3 s = k < points.scale.size() ? points.scale[k] : glm::vec3(1.0f);
  glm::mat4 m = glm::mat4_cast(glm::normalize(q));
  m[0] *= s.x;
  m[1] *= s.y;
  m[2] *= s.z;
  m[3] = glm::vec4(points.position[k], 1.0f);
  return m;
}

}  // namespace

SceneInstances build_instances(const Points& points, const std::vector<bool>& has_mesh) {
  SceneInstances out;
  out.per_class.resize(has_mesh.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::int32_t cls = k < points.class_id.size() ? points.class_id[k] : 0;
    if (cls < 0 || static_cast<std::size_t>(cls) >= has_mesh.size() || !has_mesh[static_cast<std::size_t>(cls)]) {
      ++out.skipped;
      continue;
    }
    out.per_class[static_cast<std::size_t>(cls)].push_back(instance_matrix(points, k));
    ++out.count;
  }
  return out;
}

SceneClassInstances build_instances(const Scene& scene) {
  SceneClassInstances out;
  std::map<std::int32_t, std::size_t> slot;
  for (const auto& [cls, c] : scene.classes) {
    slot[cls] = out.class_ids.size();
    out.class_ids.push_back(cls);
  }
  out.per_class.resize(out.class_ids.size());
  if (!scene.instances) return out;
  const Points& points = *scene.instances;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::int32_t cls = k < points.class_id.size() ? points.class_id[k] : 0;
    const auto it = slot.find(cls);
    if (it == slot.end()) {
      ++out.skipped;
      continue;
    }
    out.per_class[it->second].push_back(instance_matrix(points, k));
    ++out.count;
  }
  return out;
}

bool instance_bounds(const SceneInstances& instances, const std::vector<const TerrainMesh*>& class_meshes,
                     glm::vec3& lo, glm::vec3& hi) {
  bool any = false;
  for (std::size_t c = 0; c < instances.per_class.size() && c < class_meshes.size(); ++c) {
    const TerrainMesh* tm = class_meshes[c];
    if (!tm || tm->positions.empty()) continue;
    for (const glm::mat4& m : instances.per_class[c])
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local((corner & 1) ? tm->max.x : tm->min.x, (corner & 2) ? tm->max.y : tm->min.y,
                              (corner & 4) ? tm->max.z : tm->min.z);
        const glm::vec3 p(m * glm::vec4(local, 1.0f));
        lo = any ? glm::min(lo, p) : p;
        hi = any ? glm::max(hi, p) : p;
        any = true;
      }
  }
  return any;
}

}  // namespace orogen::editor
