#pragma once
// CPU side of the populated-scene preview: a Scene (graph/scene.h: instances and one mesh per class, made
// by Instance) with the terrain it stands on, assembled from the preview's results, and the per-class
// instance transforms the 3D viewport draws with GPU instancing.
//
// Two kinds of node show a scene. A node with a Scene output (Instance) shows that scene, on the ground found
// upstream of it. A scene writer (WriteScene: Scene `in`, optional terrain mesh `terrain`) has no outputs, so
// the preview evaluates the nodes feeding it (scene_sources) and draws them together: the terrain mesh, else
// the ground, and every class mesh at its instances. The ground is the height field the points were placed
// on (found upstream, e.g. ProjectToTerrain's `height`). Instances are drawn where they are (the positions
// the file will hold): nothing is snapped to the ground.
#include <array>
#include <cstddef>
#include <cstdint>
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

// Where the parts of a scene come from. An empty PortRef::node: not connected / not found.
struct SceneSources {
  PortRef scene;        // the Scene: the writer's `in`, or the node's own Scene output
  PortRef terrain;      // the writer's `terrain` (a Mesh); none for a node with a Scene output
  PortRef ground;       // a height field upstream of the instances (for when there is no terrain mesh)
  bool writer = false;  // the node writes the scene (WriteScene), rather than making it
  // The distinct nodes to evaluate, in a stable order (scene, terrain, ground).
  std::vector<std::string> nodes() const;
};

// Whether `node` writes a scene: a Scene input `in` (WriteScene).
bool is_scene_writer(const Node& node);
// The index of `node`'s first Scene output (Instance's `out`), or -1.
int scene_output(const Node& node);

// The sources of the scene that node `id` writes or makes, or nullopt if it does neither. The ground is
// searched breadth-first upstream of the scene, through Scene and Points inputs: the first node with a
// height-field input named `height`, `terrain`, `ground` or `in` (in that order) fed by a height
// (resolve_output_kind; never a mask or density).
std::optional<SceneSources> scene_sources(const Graph& graph, const std::string& id);

// The values of a scene, as the preview produced them.
struct ScenePreview {
  ScenePtr scene;
  PointsPtr points;  // scene->instances
  MeshPtr terrain;
  HeightfieldPtr ground;
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

// The stand-in Instance places for classes without a mesh (missing_mesh = proxy): an octahedron 1 m tall and 1 m
// across, its base at the origin, in `color` (sRGB).
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
// The same for a scene: per_class[k] holds the instances of the k-th class of scene.classes (map order),
// whose id is class_ids[k].
struct SceneClassInstances : SceneInstances {
  std::vector<std::int32_t> class_ids;
};
SceneClassInstances build_instances(const Scene& scene);

// Bounds of every instance's transformed mesh (the corners of each class mesh's box, transformed). Returns
// false if there is no instance.
bool instance_bounds(const SceneInstances& instances, const std::vector<const TerrainMesh*>& class_meshes,
                     glm::vec3& lo, glm::vec3& hi);

}  // namespace orogen::editor
