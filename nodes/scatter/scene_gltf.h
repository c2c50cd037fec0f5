#pragma once
// Instanced scenes (a terrain mesh plus meshes placed at points) to glTF 2.0 through tinygltf.
//
// Layout of the file: one root node "orogen" rotated -90 degrees about x, which turns Orogen's z-up world into
// glTF's y-up one; below it a node "terrain" (if any) and, per class with a mesh, either one node carrying
// the EXT_mesh_gpu_instancing extension (TRANSLATION, ROTATION, SCALE accessors with one entry per point) or
// a group node "class_N" with one child node per point. Positions, rotations and scales inside are Orogen's
// (metres, z up), so they read back exactly.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>

#include "graph/mesh.h"
#include "graph/points.h"
#include "nodes/io/file_error.h"

namespace orogen {

enum class SceneInstancing { GpuInstancing, Nodes };

struct SceneContent {
  const Mesh* terrain = nullptr;
  const Points* points = nullptr;
  std::map<std::int32_t, const Mesh*> meshes;  // by class id; classes without a mesh are left out
  SceneInstancing instancing = SceneInstancing::GpuInstancing;
};

// A small proxy mesh (an octahedron of half-size 0.5 m, base at z = 0, height 1 m) for classes without one.
std::shared_ptr<Mesh> proxy_mesh();

// Writes .gltf (JSON with the buffer embedded as base64) or .glb (binary), chosen by `binary`. Not atomic by
// itself. Throws FileError on failure. Returns the number of instances written.
std::size_t write_scene_gltf(const SceneContent& scene, const std::filesystem::path& path, bool binary,
                             const WriteProgress& progress = {});

}  // namespace orogen
