#pragma once
// Meshes to OBJ, PLY and STL through OpenMesh's writers.
#include <filesystem>
#include <optional>

#include "nodes/io/file_error.h"

namespace orogen {

struct Mesh;

enum class MeshFormat { Obj, Ply, Stl };

std::optional<MeshFormat> mesh_format_from_path(const std::filesystem::path& path);

struct MeshWriteOptions {
  // Orogen is z-up (right-handed). y_up rotates -90 degrees about x, (x, y, z) -> (x, z, -y), the y-up
  // right-handed convention of Blender's and Unity's importers; positions and normals alike.
  bool y_up = false;
  bool binary = true;   // PLY and STL; OBJ is always text
  bool normals = true;  // per-vertex normals (OBJ, PLY); STL always carries face normals only
  bool colors = true;   // per-vertex colours (PLY only: OpenMesh's OBJ writer has none, STL has none), stored
                        // sRGB-encoded 8-bit with alpha when some vertex is not opaque
};

// Writes `mesh` to `path` in `format` (OpenMesh picks the writer by extension, so it must match). Not atomic
// by itself. Throws FileError on failure.
void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path, MeshFormat format,
                     const MeshWriteOptions& options = {});

}  // namespace orogen
