#pragma once
// Instanced scenes (a terrain mesh plus meshes placed at points) to glTF 2.0 through tinygltf.
//
// Layout of the file: one root node "orogen" rotated -90 degrees about x, which turns Orogen's z-up world into
// glTF's y-up one; below it a node "terrain" (if any) and, per scene class with instances, either one node
// carrying the EXT_mesh_gpu_instancing extension (TRANSLATION, ROTATION, SCALE accessors with one entry per
// instance) or a group node with one child node per instance, both named by the class (e.g. "class_3") and
// holding the class id in extras.class_id. Positions, rotations and scales inside are Orogen's
// (metres, z up), so they read back exactly.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>

#include "graph/mesh.h"
#include "graph/scene.h"
#include "nodes/io/file_error.h"

namespace orogen {

enum class SceneInstancing { GpuInstancing, Nodes };

struct SceneContent {
  const Mesh* terrain = nullptr;
  const Scene* scene = nullptr;  // the instances and their class meshes (Instance)
  SceneInstancing instancing = SceneInstancing::GpuInstancing;
};

// Writes .gltf (JSON with the buffer embedded as base64) or .glb (binary), chosen by `binary`. Not atomic by
// itself. Throws FileError on failure. Returns the number of instances written.
std::size_t write_scene_gltf(const SceneContent& scene, const std::filesystem::path& path, bool binary,
                             const WriteProgress& progress = {});

}  // namespace orogen
