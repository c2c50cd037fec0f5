#pragma once
// Meshes to OBJ, PLY and STL (the bytes OpenMesh's writers wrote, formatted in one pass from the mesh), and glTF
// 2.0 (tinygltf's document, the buffer streamed from the mesh).
#include <filesystem>
#include <optional>
#include <string>

#include "nodes/io/file_error.h"

namespace orogen {

struct Mesh;

enum class MeshFormat { Obj, Ply, Stl, Gltf, Glb };

std::optional<MeshFormat> mesh_format_from_path(const std::filesystem::path& path);

struct MeshWriteOptions {
  // Orogen is z-up (right-handed). y_up rotates -90 degrees about x, (x, y, z) -> (x, z, -y), the y-up
  // right-handed convention of Blender's and Unity's importers; positions and normals alike.
  bool y_up = false;
  bool binary = true;   // PLY and STL; OBJ is always text
  bool normals = true;  // per-vertex normals (OBJ, PLY); STL always carries face normals only
  bool colors = true;   // per-vertex colors (PLY only: OBJ has no standard vertex color, STL has none), stored
                        // sRGB-encoded 8-bit with alpha when some vertex is not opaque
  // OBJ: per-vertex texture coordinates (vt), the mesh's xy footprint mapped onto [0, 1]^2: u grows east, v
  // north, so an image of the same domain (written north row first) drapes over a terrain mesh. For an
  // image with its pixel centres on the domain's samples this is exact at the centre and half a pixel off at
  // the borders (invisible at a few hundred pixels).
  bool uvs = true;
  // OBJ: the material library named by "mtllib" and the material used by every face ("usemtl terrain");
  // empty: none. write_material_file writes the library.
  std::string material_library;
  // glTF: the name of the mesh in the file (WriteMesh gives its node id), so identical runs write identical
  // bytes whatever the temporary file is called.
  std::string name = "mesh";
};

// The material library of an OBJ: material "terrain", white diffuse, no specular, with `texture` (a path
// relative to the library, as OBJ readers resolve it) as its diffuse map (map_Kd). Text. Throws FileError if
// `texture` is not one printable line (a newline would add directives to the library).
std::string material_library_text(const std::string& texture);

// Writes `mesh` to `path` in `format`. Not atomic by itself. Throws FileError on failure. `progress` (which
// may throw Cancelled) is called per block of vertices and faces (and per MiB of glTF) as the file is written.
void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path, MeshFormat format,
                     const MeshWriteOptions& options = {}, const WriteProgress& progress = {});

// glTF 2.0 (.gltf with the buffer embedded, or binary .glb; y-up as glTF requires): positions, optional
// normals, linear vertex colors (COLOR_0) and the mesh's own texture coordinates (TEXCOORD_0), 32-bit
// indices, one rough non-metallic material. Throws FileError. `progress` as for write_mesh_file.
void write_gltf_file(const Mesh& mesh, const std::filesystem::path& path, bool binary, bool normals, bool colors,
                     bool uvs, const std::string& name, const WriteProgress& progress = {});

}  // namespace orogen
