// WriteScene, ProjectToTerrain and MergePoints.
#include <algorithm>
#include <cmath>
#include <string>

#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/io/write_output.h"
#include "nodes/scatter/scene_gltf.h"

namespace orogen {

inline constexpr int kSceneMeshSlots = 8;

OROGEN_NODE(WriteScene) {
  b.reach_global();
  b.category("scatter").writes_files().description(
      "Writes an instanced scene to glTF 2.0 (Khronos glTF 2.0 specification; EXT_mesh_gpu_instancing): the "
      "terrain mesh and, for each class with a mesh, its points as instances (translation, rotation, scale "
      "per point). gpu_instancing writes one node per class with the EXT_mesh_gpu_instancing extension (game "
      "engines draw it in one call); nodes writes one node per instance (every viewer). A root node rotates "
      "Orogen's z-up world to glTF's y-up. .gltf embeds the buffer as base64, .glb is binary.");
  b.input("in", PortType::Points).description("Instances: position (m), rotation, scale, class id");
  b.input("terrain", PortType::Mesh).optional().description("Terrain mesh (m), e.g. from HeightfieldToMesh");
  for (int k = 0; k < kSceneMeshSlots; ++k)
    b.input("mesh_" + std::to_string(k), PortType::Mesh)
        .optional()
        .description("Mesh placed at the points of class " + std::to_string(k) + " (m, base at the origin)");
  b.param_path("path", "scene.glb").output_file().extensions({".gltf", ".glb"}).description(
      "Output file, relative to the output directory; .glb binary or .gltf text");
  b.param_enum("instancing", {"gpu_instancing", "nodes"}, "gpu_instancing").description(
      "gpu_instancing: one node per class with EXT_mesh_gpu_instancing; nodes: one node per instance");
  b.param_bool("proxies", true).description(
      "Classes 0..7 without a mesh get a 1 m octahedron proxy (off: their points are left out)");
  b.execute([](ExecContext& ctx) {
    const auto points = ctx.require<Points>("in");
    const auto terrain = ctx.input<Mesh>("terrain");
    std::vector<MeshPtr> keep;
    SceneContent scene;
    scene.points = points.get();
    scene.terrain = terrain.get();
    scene.instancing = ctx.param<std::string>("instancing") == "nodes" ? SceneInstancing::Nodes : SceneInstancing::GpuInstancing;
    std::shared_ptr<Mesh> proxy;
    for (int k = 0; k < kSceneMeshSlots; ++k) {
      auto mesh = ctx.input<Mesh>("mesh_" + std::to_string(k));
      if (!mesh && ctx.param<bool>("proxies")) {
        if (!proxy) proxy = proxy_mesh();
        mesh = proxy;
      }
      if (mesh) {
        scene.meshes[k] = mesh.get();
        keep.push_back(mesh);
      }
    }
    const std::string& path = ctx.param<std::string>("path");
    const bool binary = path.size() >= 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      write_scene_gltf(scene, temporary, binary, progress);
    });
  });
}

OROGEN_NODE(ProjectToTerrain) {
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Sets each point's z to the terrain height under it (bilinear), plus an offset; optionally tilts its "
      "rotation toward the terrain normal (from central differences in world units), blended by align.");
  b.input("in", PortType::Points).description("Points to place");
  b.input("height", PortType::Heightfield).description("Terrain heights, metres");
  b.output("out", PortType::Points).description("The points on the terrain");
  b.param_float("offset", 0.0).range(-1e4, 1e4).unit("m").description("Added to the terrain height, metres");
  b.param_float("align", 0.0).range(0.0, 1.0).unit("").description(
      "0: keep the rotation (upright); 1: the point's up axis follows the terrain normal; between: blended");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Points>("in");
    const auto h = ctx.require<Heightfield>("height");
    const double offset = ctx.param<double>("offset");
    const double align = ctx.param<double>("align");
    auto out = std::make_shared<Points>(*in);
    const auto sp = h->domain.spacing;
    for (std::size_t i = 0; i < out->size(); ++i) {
      if (i % 65536 == 0) ctx.check_cancelled();
      auto& p = out->position[i];
      const double z = h->sample_world(p.x, p.y);
      p.z = std::isfinite(z) ? static_cast<float>(z + offset) : p.z;
      if (align > 0.0) {
        const double gx = (h->sample_world(p.x + sp.x, p.y) - h->sample_world(p.x - sp.x, p.y)) / (2.0 * sp.x);
        const double gy = (h->sample_world(p.x, p.y + sp.y) - h->sample_world(p.x, p.y - sp.y)) / (2.0 * sp.y);
        glm::dvec3 n(-gx, -gy, 1.0);
        if (!std::isfinite(n.x) || !std::isfinite(n.y)) continue;
        n = glm::normalize(n);
        const glm::dquat tilt = glm::rotation(glm::dvec3(0, 0, 1), n);
        const glm::dquat blended = glm::slerp(glm::dquat(1, 0, 0, 0), tilt, align);
        out->rotation[i] = glm::quat(glm::normalize(blended * glm::dquat(out->rotation[i])));
      }
    }
    ctx.set_output("out", out);
  });
}

OROGEN_NODE(MergePoints) {
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Concatenates point sets (a first, then b, ...); named attributes missing from one set are 0 there.");
  b.input("a", PortType::Points).description("First points");
  b.input("b", PortType::Points).description("Second points");
  b.input("c", PortType::Points).optional().description("Third points");
  b.input("d", PortType::Points).optional().description("Fourth points");
  b.output("out", PortType::Points).description("All the points, in input order");
  b.execute([](ExecContext& ctx) {
    auto out = std::make_shared<Points>();
    for (const char* name : {"a", "b", "c", "d"}) {
      const auto in = ctx.input<Points>(name);
      if (!in) continue;
      const std::size_t base = out->size();
      out->position.insert(out->position.end(), in->position.begin(), in->position.end());
      out->rotation.insert(out->rotation.end(), in->rotation.begin(), in->rotation.end());
      out->scale.insert(out->scale.end(), in->scale.begin(), in->scale.end());
      out->class_id.insert(out->class_id.end(), in->class_id.begin(), in->class_id.end());
      for (auto& [attr, values] : out->attributes) values.resize(out->size(), 0.0f);
      for (const auto& [attr, values] : in->attributes) {
        auto& dst = out->attributes[attr];
        dst.resize(base, 0.0f);
        dst.insert(dst.end(), values.begin(), values.end());
      }
    }
    for (auto& [attr, values] : out->attributes) values.resize(out->size(), 0.0f);
    ctx.set_output("out", out);
  });
}

}  // namespace orogen
