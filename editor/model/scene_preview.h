#pragma once
// CPU side of the populated-scene preview: what a scene writer (WriteScene: points `in`, optional terrain
// mesh `terrain`, class meshes `mesh_0`..) will write, assembled from the preview's results, and the
// per-class instance transforms the 3D viewport draws with GPU instancing.
//
// A scene writer has no outputs, so the preview evaluates the nodes feeding it (scene_sources) and draws
// them together: the terrain mesh, else the heightfield the points were placed on (found upstream of the
// points, e.g. ProjectToTerrain's `height`), and every class mesh at its points. Points are drawn where they
// are (the positions the file will hold): nothing is snapped to the ground.
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "editor/model/terrain_mesh.h"
#include "graph/graph.h"
#include "graph/mesh.h"
#include "graph/port_value.h"

namespace orogen::editor {

// Class mesh inputs a scene writer can have (WriteScene's mesh_0 .. mesh_7).
inline constexpr int kSceneClassSlots = 8;

// Where the parts of a scene come from. An empty PortRef::node: not connected / not found.
struct SceneSources {
  PortRef points;                                  // the writer's `in`
  PortRef terrain;                                 // the writer's `terrain` (a Mesh)
  std::array<PortRef, kSceneClassSlots> meshes;    // mesh_<k>
  PortRef ground;  // a height field upstream of the points (for when there is no terrain mesh)
  bool proxies = true;  // the writer's `proxies`: classes without a mesh get a 1 m octahedron
  // The distinct nodes to evaluate, in a stable order (points, terrain, meshes, ground).
  std::vector<std::string> nodes() const;
};

// Whether `node` writes a scene: a Points input `in` and Mesh inputs named mesh_<k>.
bool is_scene_writer(const Node& node);

// The sources of scene writer `id`, or nullopt if it is not one. The ground is searched breadth-first
// upstream of the points, through Points inputs: the first node with a height-field input named `height`,
// `terrain`, `ground` or `in` (in that order) fed by a height (resolve_output_kind; never a mask or density).
std::optional<SceneSources> scene_sources(const Graph& graph, const std::string& id);

// The values of a scene, as the preview produced them.
struct ScenePreview {
  PointsPtr points;
  MeshPtr terrain;
  std::array<MeshPtr, kSceneClassSlots> meshes;
  HeightfieldPtr ground;
  bool proxies = true;
};

// Picks the sources' values out of a preview's outputs (node id -> outputs in declaration order).
ScenePreview assemble_scene(const Graph& graph, const SceneSources& sources,
                            const std::map<std::string, std::vector<PortValue>>& outputs);

struct MeshGeometryOptions {
  // A mesh whose vertices all have one colour (an uncoloured terrain is white) is tinted by height with
  // the terrain colour map, as height fields are.
  bool tint_uniform_by_height = false;
};
// An OpenMesh mesh as indexed triangles with normals and sRGB colours (the mesh holds linear colours).
// Faces with more than three vertices are fanned.
TerrainMesh mesh_geometry(const Mesh& mesh, const MeshGeometryOptions& options = {});

// The stand-in WriteScene writes for classes without a mesh: an octahedron 1 m tall and 1 m across, its
// base at the origin, in `color` (sRGB).
TerrainMesh proxy_geometry(glm::vec4 color);

// The colour of class `cls`'s proxies (muted, natural: greens, browns, greys), sRGB.
glm::vec4 class_color(int cls);
// The colour of class `cls`'s point markers (bright, to stand out over the terrain), sRGB.
glm::vec4 marker_color(int cls);

// Per class k, the model matrices (translate(position) * rotate(rotation) * scale(scale)) of the points of
// class k, in point order. Points of a class with has_mesh[k] false, or a class id outside 0..slots-1, are
// skipped (counted in `skipped`). Missing rotations / scales (shorter arrays) are identity / 1.
struct SceneInstances {
  std::vector<std::vector<glm::mat4>> per_class;
  std::size_t count = 0;    // instances in total
  std::size_t skipped = 0;  // points without a mesh
};
SceneInstances build_instances(const Points& points, const std::vector<bool>& has_mesh);

// Bounds of every instance's transformed mesh (the corners of each class mesh's box, transformed). Returns
// false if there is no instance.
bool instance_bounds(const SceneInstances& instances, const std::vector<const TerrainMesh*>& class_meshes,
                     glm::vec3& lo, glm::vec3& hi);

}  // namespace orogen::editor
