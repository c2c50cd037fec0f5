#pragma once
// An instanced scene: placed instances (position, rotation, scale, class per instance) and, for every class
// that has instances, the mesh drawn at them with a name. Made by Instance from points and class meshes;
// written with a terrain by WriteScene (glTF 2.0) and drawn by the editor's 3D view.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "graph/points.h"

namespace orogen {

struct Mesh;  // graph/mesh.h; kept out of this header (OpenMesh is only compiled where meshes are used)

struct SceneClass {
  std::string name;                  // e.g. "tree", or "class_3" by default
  std::shared_ptr<const Mesh> mesh;  // metres, z up, base at the origin; never null in a consistent scene
  bool proxy = false;                // a stand-in (1 m octahedron) for a class that had no mesh
};

struct Scene {
  // One entry per instance: position (world metres, z up), rotation, scale, class id, named attributes.
  // Shared with the points it was made from when nothing was filtered (links never copy data).
  std::shared_ptr<const Points> instances;
  std::map<std::int32_t, SceneClass> classes;  // by class id

  std::size_t size() const { return instances ? instances->size() : 0; }
  // Instances of class `cls`, in instance order.
  std::size_t count(std::int32_t cls) const;
  // Throws std::logic_error unless the instances are consistent (Points::check_consistent), every class has
  // a mesh and every instance's class has an entry.
  void check_consistent() const;
  std::size_t byte_size() const;
};

using ScenePtr = std::shared_ptr<const Scene>;

}  // namespace orogen
