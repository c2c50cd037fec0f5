// Instance, WriteScene, ProjectToTerrain and MergePoints.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/mesh_file.h"
#include "nodes/io/write_output.h"
#include "nodes/scatter/instance.h"
#include "nodes/scatter/merge_points.h"
#include "nodes/scatter/mesh_surface.h"
#include "nodes/scatter/project_to_terrain.h"
#include "nodes/scatter/scene_gltf.h"

namespace orogen {

inline constexpr int kSceneMeshSlots = 8;

OROGEN_NODE(Instance) {
  b.distribution(Distribution::PerTile);
  b.reach_global();  // outputs a scene, not a field
  b.category("scatter").description(
      "Combines points with one mesh per class into an instanced scene (geometry instancing: Carucci 2005, "
      "Inside Geometry Instancing, GPU Gems 2 ch. 3): every point becomes an instance of its class's mesh, "
      "translated, rotated and scaled by the point. Meshes come from TreeMesh, PlantSprite, RockSet or any "
      "mesh node, in metres with their base at the origin. Points of a class without a mesh are an error, a "
      "1 m octahedron proxy or left out (missing_mesh). WriteScene writes the scene to glTF; the editor draws "
      "it in 3D.");
  b.input("in", PortType::Points).description("Where the instances go: position (m), rotation, scale, class id");
  for (int k = 0; k < kSceneMeshSlots; ++k)
    b.input("mesh_" + std::to_string(k), PortType::Mesh)
        .optional()
        .description("Mesh placed at the points of class " + std::to_string(k) + " (m, base at the origin)");
  b.output("out", PortType::Scene).description("The instances and the mesh and name of every class");
  b.param_table("names", class_name_schema(), empty_table(class_name_schema()))
      .description(
          "Class names, one row per class (id and name); a class without a row is named class_<id>. The names of "
          "the glTF nodes and meshes");
  b.param_enum("missing_mesh", {"error", "proxy", "skip"}, "error")
      .description(
          "Points of a class without a mesh: error stops with the class named; proxy places a 1 m octahedron "
          "(base at the point); skip leaves them out");
  b.execute([](ExecContext& ctx) {
    const auto points = ctx.require<Points>("in");
    std::map<std::int32_t, MeshPtr> meshes;
    for (int k = 0; k < kSceneMeshSlots; ++k)
      if (auto mesh = ctx.input<Mesh>("mesh_" + std::to_string(k))) meshes[k] = mesh;
    InstanceOptions options;
    options.names = class_names_from_table(ctx.param<TableValue>("names"));
    const std::string& missing = ctx.param<std::string>("missing_mesh");
    options.missing = missing == "proxy"  ? MissingMesh::Proxy
                      : missing == "skip" ? MissingMesh::Skip
                                          : MissingMesh::Error;
    try {
      ctx.set_output("out", std::make_shared<Scene>(make_scene(points, meshes, options)));
    } catch (const std::invalid_argument& e) {
      throw NodeError(e.what());
    }
  });
}

OROGEN_NODE(WriteScene) {
  b.reach_global();
  b.category("scatter").writes_files().description(
      "Writes an instanced scene to glTF 2.0 (Khronos glTF 2.0 specification; EXT_mesh_gpu_instancing): the "
      "terrain mesh and, for each class of the scene (from Instance), its instances (translation, rotation, "
      "scale per instance). gpu_instancing writes one node per class with the EXT_mesh_gpu_instancing "
      "extension (game engines draw it in one call); nodes writes one node per instance (every viewer). "
      "Nodes and meshes are named by class. A root node rotates Orogen's z-up world to glTF's y-up. .gltf "
      "embeds the buffer as base64, .glb is binary. With a terrain mesh, instances are grounded on it (ground): "
      "a simplified or coarser mesh lies metres off the heightfield the points were placed on, and a plant "
      "must stand on the terrain the same file shows.");
  b.input("in", PortType::Scene).description("The instanced scene, from Instance");
  b.input("terrain", PortType::Mesh).optional().description("Terrain mesh (m), e.g. from HeightfieldToMesh");
  b.input("height", PortType::Heightfield)
      .optional()
      .description(
          "The heightfield the instances were placed on (m): with it, grounding keeps each instance's height "
          "above it (an offset such as a stem sunk by 0.1 m); without it, each base is set onto the mesh");
  b.param_path("path", "scene.glb")
      .output_file()
      .extensions({".gltf", ".glb"})
      .description("Output file, relative to the output directory; .glb binary or .gltf text");
  b.param_enum("instancing", {"gpu_instancing", "nodes"}, "gpu_instancing")
      .description(
          "gpu_instancing: one node per class with EXT_mesh_gpu_instancing, marked required (game engines, "
          "three.js, Babylon.js; a viewer without it refuses the file instead of drawing one mesh per class at "
          "the origin); nodes: one node per instance (every viewer, Blender's importer too)");
  b.param_enum("ground", {"terrain_mesh", "keep"}, "terrain_mesh")
      .description(
          "terrain_mesh: each instance moves vertically with the written terrain mesh under it (by the mesh's "
          "difference from height, or onto the mesh); keep: positions as they come (instances outside the mesh "
          "always keep theirs)");
  // The glTF document is built in memory, then streamed to the file: per instance a tinygltf node and its JSON
  // object (nodes), or its translation, rotation and scale in the buffer (gpu_instancing). The meshes go from
  // their arrays to the file through a 1 MiB block (no buffer copy, no base64 text). Known once the scene
  // exists, so the check is made just before the node runs. Grounding adds a copy of the points and the mesh
  // surface's triangles and buckets.
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    std::uint64_t bytes = 0;
    if (const PortValue* v = q.input("in")) {
      const bool nodes = q.params.get<std::string>("instancing") == "nodes";
      bytes += static_cast<std::uint64_t>(std::get<ScenePtr>(*v)->size()) *
               ((nodes ? 2048 : 160) + sizeof(glm::vec3) + sizeof(glm::quat) + sizeof(glm::vec3) + 8);
    }
    // The terrain: grounding's surface (triangles and buckets, about the mesh's size, freed before the file is
    // built).
    const bool ground = q.params.get<std::string>("ground") == "terrain_mesh";
    if (const PortValue* t = q.input("terrain")) bytes += ground ? byte_size(*t) : 0;
    return bytes;
  });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Scene>("in");
    const auto terrain = ctx.input<Mesh>("terrain");
    try {
      in->check_consistent();
    } catch (const std::logic_error& e) {
      throw NodeError(std::string("inconsistent scene: ") + e.what());
    }
    SceneContent scene;
    scene.scene = in.get();
    Scene grounded;
    if (terrain && in->instances && ctx.param<std::string>("ground") == "terrain_mesh") {
      const auto placed_on = ctx.input<Heightfield>("height");
      grounded = *in;
      grounded.instances = std::make_shared<Points>(
          ground_on_surface(*in->instances, MeshSurface(terrain->mesh, &ctx), placed_on.get(), &ctx));
      scene.scene = &grounded;
    }
    scene.terrain = terrain.get();
    scene.instancing =
        ctx.param<std::string>("instancing") == "nodes" ? SceneInstancing::Nodes : SceneInstancing::GpuInstancing;
    const std::string& path = ctx.param<std::string>("path");
    const bool binary = mesh_format_from_path(path) == MeshFormat::Glb;  // case-insensitive, like the check
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      write_scene_gltf(scene, temporary, binary, progress);
    });
  });
}

OROGEN_NODE(ProjectToTerrain) {
  b.distribution(Distribution::PerTile);
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Sets each point's z to the terrain height under it (bilinear), plus an offset; optionally tilts its "
      "rotation toward the terrain normal (from central differences in world units), blended by align.");
  b.input("in", PortType::Points).description("Points to place");
  b.input("height", PortType::Heightfield).description("Terrain heights, metres");
  b.output("out", PortType::Points).description("The points on the terrain");
  b.param_float("offset", 0.0).range(-1e4, 1e4).unit(Unit::Metre).description("Added to the terrain height, metres");
  b.param_float("align", 0.0)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description(
          "0: keep the rotation (upright); 1: the point's up axis follows the terrain normal; between: blended");
  b.execute([](ExecContext& ctx) {
    ProjectParams p;
    p.offset = ctx.param<double>("offset");
    p.align = ctx.param<double>("align");
    ctx.set_output("out", std::make_shared<Points>(project_to_terrain(*ctx.require<Points>("in"),
                                                                      *ctx.require<Heightfield>("height"), p, &ctx)));
  });
}

OROGEN_NODE(MergePoints) {
  b.distribution(Distribution::PerTile);
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Concatenates point sets (a first, then b, ...); named attributes missing from one set are 0 there.");
  b.input("a", PortType::Points).description("First points");
  b.input("b", PortType::Points).description("Second points");
  b.input("c", PortType::Points).optional().description("Third points");
  b.input("d", PortType::Points).optional().description("Fourth points");
  b.output("out", PortType::Points).description("All the points, in input order");
  b.execute([](ExecContext& ctx) {
    std::vector<PointsPtr> inputs;  // keeps the sets alive while merging
    std::vector<const Points*> sets;
    for (const char* name : {"a", "b", "c", "d"}) {
      inputs.push_back(ctx.input<Points>(name));
      sets.push_back(inputs.back().get());
    }
    ctx.set_output("out", std::make_shared<Points>(merge_points(sets)));
  });
}

}  // namespace orogen
