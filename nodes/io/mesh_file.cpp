// OpenMesh's IO header must come before any mesh kernel header: it registers the readers and writers.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "nodes/io/mesh_file.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "graph/checked_file.h"
#include "graph/mesh.h"
#include "nodes/io/image_file.h"

namespace orogen {

std::optional<MeshFormat> mesh_format_from_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  return std::nullopt;
}

void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path, MeshFormat format,
                     const MeshWriteOptions& options) {
  // OpenMesh narrates every write on its log stream ("[OBJWriter] : write file"); the CLI and the editor
  // should stay quiet. Its error stream stays on. Done once, before any writer runs.
  static const bool quiet = [] {
    omlog().disable();
    return true;
  }();
  (void)quiet;
  if (mesh.face_count() == 0) throw FileError("cannot write '" + path.string() + "': the mesh has no faces");
  // A copy in file conventions: axes, and colours as 8-bit viewers expect them (sRGB, clamped to 0..1,
  // which also keeps OpenMesh's float-to-byte conversion in range).
  TriMesh out = mesh.mesh;
  bool translucent = false;
  for (auto v : out.vertices()) {
    if (options.y_up) {
      const auto p = out.point(v);
      const auto n = out.normal(v);
      out.set_point(v, {p[0], p[2], -p[1]});
      out.set_normal(v, {n[0], n[2], -n[1]});
    }
    auto c = out.color(v);
    for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(linear_to_srgb(c[k]));
    c[3] = std::clamp(std::isnan(c[3]) ? 1.0f : c[3], 0.0f, 1.0f);
    translucent = translucent || c[3] < 1.0f;
    out.set_color(v, c);
  }
  out.update_face_normals();

  OpenMesh::IO::Options opt;
  if (options.binary && format != MeshFormat::Obj) opt += OpenMesh::IO::Options::Binary;
  if (options.normals && format != MeshFormat::Stl) opt += OpenMesh::IO::Options::VertexNormal;
  if (options.colors && format == MeshFormat::Ply) {
    opt += OpenMesh::IO::Options::VertexColor;
    if (translucent) opt += OpenMesh::IO::Options::ColorAlpha;
  }
  if (format == MeshFormat::Stl) opt += OpenMesh::IO::Options::FaceNormal;
  // 9 significant digits: text formats read back the same float (OpenMesh's default of 6 would round
  // x = 12345.67 m to 12345.7 m).
  std::unique_ptr<CheckedOStream> stream;
  try {
    stream = std::make_unique<CheckedOStream>(path);
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool written = OpenMesh::IO::write_mesh(out, *stream, ext, opt, 9);
  if (!stream->file().ok()) throw FileError(stream->file().error());
  if (!written) throw FileError("cannot write '" + path.string() + "' (OpenMesh could not write the mesh)");
  try {
    stream->finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

}  // namespace orogen
