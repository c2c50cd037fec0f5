#pragma once
// Instancing: points plus one mesh per class make a Scene (graph/scene.h), what WriteScene writes and the
// editor draws. Every point becomes one instance with its position, rotation, scale and class; the class's
// mesh is drawn there.
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/mesh.h"
#include "graph/points.h"
#include "graph/scene.h"
#include "graph/table_value.h"

namespace orogen {

// What happens to points of a class that has no mesh.
enum class MissingMesh {
  Error,  // refuse (std::invalid_argument naming the class)
  Proxy,  // a 1 m octahedron stands in (proxy_mesh())
  Skip,   // the points are left out of the scene
};

struct InstanceOptions {
  MissingMesh missing = MissingMesh::Error;
  // Class names by class id; classes without one are named "class_<id>".
  std::map<std::int32_t, std::string> names;
};

// The scene of `points` with `meshes` by class id. Every connected mesh is listed (even a class without
// points); the instances share `points` unless some are skipped. Throws std::invalid_argument for a class
// with points but no mesh when options.missing is Error, and for inconsistent points.
Scene make_scene(std::shared_ptr<const Points> points, const std::map<std::int32_t, MeshPtr>& meshes,
                 const InstanceOptions& options = {});

// Instance's `names` table: one row per class, its id and name.
TableSchema class_name_schema();
// Names by class id from that table; empty names are skipped (class_<id>), a class named twice takes its last.
std::map<std::int32_t, std::string> class_names_from_table(const TableValue& table);

// A small proxy mesh (an octahedron of half-size 0.5 m, base at z = 0, height 1 m) for classes without one.
std::shared_ptr<Mesh> proxy_mesh();

}  // namespace orogen
