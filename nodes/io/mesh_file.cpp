// OpenMesh's IO header must come before any mesh kernel header: it registers the readers and writers.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "nodes/io/mesh_file.h"
#include "nodes/io/file_extension.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <string>

#include "graph/checked_file.h"
#include "graph/file_text.h"
#include "graph/mesh.h"
#include "nodes/common/work_poll.h"
#include "nodes/io/image_file.h"

#include <limits>
#include <vector>

namespace orogen {

std::optional<MeshFormat> mesh_format_from_path(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".gltf") return MeshFormat::Gltf;
  if (ext == ".glb") return MeshFormat::Glb;
  return std::nullopt;
}

namespace {

// 9 significant digits: a float reads back exactly.
void append(std::string& out, float value) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 9);
  out.append(buffer, r.ptr);
}
void append(std::string& out, unsigned value) {
  char buffer[16];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, r.ptr);
}

// OBJ (Wavefront) text with positions, optional normals and texture coordinates, and an optional material.
// Written here rather than by OpenMesh's OBJ writer, which has no way to name a texture for vertex UVs.
// Formatted in memory in blocks of rows and flushed to the file as it goes.
void write_obj(const TriMesh& m, const std::filesystem::path& path, const MeshWriteOptions& options,
               const std::vector<OpenMesh::Vec2f>& uvs, ProgressPoll& poll) {
  std::unique_ptr<CheckedFile> file;
  try {
    file = std::make_unique<CheckedFile>(path);
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  std::string out;
  out.reserve(1 << 20);
  auto flush = [&](bool force) {
    if (!force && out.size() < (1u << 20)) return;
    if (!file->write(out.data(), out.size())) throw FileError(file->error());
    out.clear();
  };
  out += "# Orogen terrain mesh, metres\n";
  if (!options.material_library.empty()) out += "mtllib " + options.material_library + "\n";
  // Axes converted here, not in a copy of the mesh: copying a mesh of millions of vertices is one long call
  // that cannot be cancelled.
  // 0 - y, not -y: a southern edge at y = 0 is written "0", not "-0".
  auto axes = [&](OpenMesh::Vec3f p) { return options.y_up ? OpenMesh::Vec3f(p[0], p[2], 0.0f - p[1]) : p; };
  for (auto v : m.vertices()) {
    const auto p = axes(m.point(v));
    out += "v ";
    append(out, p[0]);
    out += ' ';
    append(out, p[1]);
    out += ' ';
    append(out, p[2]);
    out += '\n';
    flush(false);
    poll();
  }
  const bool uv = !uvs.empty();
  for (std::size_t k = 0; k < uvs.size(); ++k) {
    out += "vt ";
    append(out, uvs[k][0]);
    out += ' ';
    append(out, uvs[k][1]);
    out += '\n';
    flush(false);
    poll();
  }
  if (options.normals)
    for (auto v : m.vertices()) {
      const auto n = axes(m.normal(v));
      out += "vn ";
      append(out, n[0]);
      out += ' ';
      append(out, n[1]);
      out += ' ';
      append(out, n[2]);
      out += '\n';
      flush(false);
      poll();
    }
  if (!options.material_library.empty()) out += "usemtl terrain\n";
  for (auto f : m.faces()) {
    out += 'f';
    for (auto v : m.fv_range(f)) {
      const unsigned i = static_cast<unsigned>(v.idx()) + 1;
      out += ' ';
      append(out, i);
      if (uv || options.normals) {
        out += '/';
        if (uv) append(out, i);
        if (options.normals) {
          out += '/';
          append(out, i);
        }
      }
    }
    out += '\n';
    flush(false);
    poll();
  }
  flush(true);
  try {
    file->finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

}  // namespace

std::string material_library_text(const std::string& texture) {
  if (auto why = check_file_text(texture); !why.empty()) throw FileError("texture '" + texture + "' " + why);
  std::string s =
      "# Orogen terrain material\n"
      "newmtl terrain\n"
      "Ka 0 0 0\n"
      "Kd 1 1 1\n"
      "Ks 0 0 0\n"
      "d 1\n"
      "illum 1\n";
  if (!texture.empty()) s += "map_Kd " + texture + "\n";
  return s;
}

void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path, MeshFormat format,
                     const MeshWriteOptions& options, const WriteProgress& progress) {
  // OpenMesh narrates every write on its log stream ("[OBJWriter] : write file"); the CLI and the editor
  // should stay quiet. Its error stream stays on. Done once, before any writer runs.
  static const bool quiet = [] {
    omlog().disable();
    return true;
  }();
  (void)quiet;
  if (mesh.face_count() == 0) throw FileError("cannot write '" + path.string() + "': the mesh has no faces");
  // No format stores a NaN or infinite position meaningfully (OBJ would get "nan" text, GLB and STL NaN
  // floats that viewers reject): refused, naming the vertex, in every format, by one quick pass (no poll: a
  // comparison per coordinate) before any format's writer.
  for (auto v : mesh.mesh.vertices()) {
    const auto& q = mesh.mesh.point(v);
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2]))
      throw FileError("cannot write '" + path.string() + "': vertex " + std::to_string(v.idx()) +
                      " has a non-finite position (" + std::to_string(q[0]) + ", " + std::to_string(q[1]) + ", " +
                      std::to_string(q[2]) +
                      "); a mesh of a heightfield with NaN or infinite samples cannot be written (fill or clamp them "
                      "upstream)");
  }
  if (format == MeshFormat::Gltf || format == MeshFormat::Glb)
    return write_gltf_file(mesh, path, format == MeshFormat::Glb, options.normals, options.colors, options.uvs,
                           options.name, progress);
  // Cancellation is polled per block of vertices and faces (units: the passes below over the vertices, and
  // the OBJ's lines), then per 64 KiB written.
  const double nv = static_cast<double>(mesh.mesh.n_vertices()), nf = static_cast<double>(mesh.mesh.n_faces());
  ProgressPoll poll(progress, 5 * nv + nf, 0.0, 0.9);
  // Texture coordinates from the footprint, before any change of axes.
  std::vector<OpenMesh::Vec2f> uvs;
  if (format == MeshFormat::Obj && options.uvs && mesh.mesh.has_vertex_texcoords2D()) {
    // The mesh's own texture coordinates (tree meshes: around and along each branch).
    uvs.reserve(mesh.mesh.n_vertices());
    for (auto v : mesh.mesh.vertices()) {
      uvs.push_back(mesh.mesh.texcoord2D(v));
      poll();
    }
  } else if (format == MeshFormat::Obj && options.uvs) {
    float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (auto v : mesh.mesh.vertices()) {
      const auto p = mesh.mesh.point(v);
      x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]), y1 = std::max(y1, p[1]);
      poll();
    }
    const double sx = x1 > x0 ? 1.0 / (double(x1) - x0) : 0.0, sy = y1 > y0 ? 1.0 / (double(y1) - y0) : 0.0;
    uvs.reserve(mesh.mesh.n_vertices());
    for (auto v : mesh.mesh.vertices()) {
      const auto p = mesh.mesh.point(v);
      uvs.emplace_back(static_cast<float>((p[0] - double(x0)) * sx), static_cast<float>((p[1] - double(y0)) * sy));
      poll();
    }
  }
  if (format == MeshFormat::Obj) {  // positions and normals only: no copy needed
    write_obj(mesh.mesh, path, options, uvs, poll);
    return;
  }
  // A copy in file conventions, built vertex by vertex and face by face (polled: OpenMesh's copy of a mesh of
  // millions of vertices is one long call): axes, and colors as 8-bit viewers expect them (sRGB, clamped to
  // 0..1, which also keeps OpenMesh's float-to-byte conversion in range).
  const TriMesh& src = mesh.mesh;
  TriMesh out;
  out.reserve(src.n_vertices(), src.n_edges(), src.n_faces());
  std::vector<TriMesh::VertexHandle> copy_of(src.n_vertices());
  bool translucent = false;
  for (auto v : src.vertices()) {
    auto p = src.point(v);
    auto n = src.normal(v);
    if (options.y_up) p = {p[0], p[2], 0.0f - p[1]}, n = {n[0], n[2], 0.0f - n[1]};
    const auto w = out.add_vertex(p);
    copy_of[static_cast<std::size_t>(v.idx())] = w;
    out.set_normal(w, n);
    auto c = src.color(v);
    for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(linear_to_srgb(static_cast<double>(c[k])));
    c[3] = std::clamp(std::isnan(c[3]) ? 1.0f : c[3], 0.0f, 1.0f);
    translucent = translucent || c[3] < 1.0f;
    out.set_color(w, c);
    poll();
  }
  std::vector<TriMesh::VertexHandle> corners;
  for (auto f : src.faces()) {
    corners.clear();
    for (auto v : src.fv_range(f)) corners.push_back(copy_of[static_cast<std::size_t>(v.idx())]);
    // The source is an OpenMesh mesh, so its faces are always accepted again, in the same order.
    if (!out.add_face(corners).is_valid())
      throw FileError("cannot write '" + path.string() + "': face " + std::to_string(f.idx()) + " could not be copied");
    poll();
  }
  out.update_face_normals();
  poll.check();  // the copy in file conventions is ready

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
  // OpenMesh writes the whole file in one call: the stream polls per 64 KiB, and what the poll throws
  // (Cancelled) fails the stream, which stops OpenMesh, and is rethrown here.
  stream->set_poll([&progress] {
    if (progress) progress(0.95);
  });
  // OpenMesh picks its writer by this name: from the format decided once, never from the file's spelling.
  const char* ext = format == MeshFormat::Ply ? ".ply" : ".stl";
  const bool written = OpenMesh::IO::write_mesh(out, *stream, ext, opt, 9);
  stream->rethrow_poll();
  if (!stream->file().ok()) throw FileError(stream->file().error());
  if (!written) throw FileError("cannot write '" + path.string() + "' (OpenMesh could not write the mesh)");
  try {
    stream->finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

}  // namespace orogen
