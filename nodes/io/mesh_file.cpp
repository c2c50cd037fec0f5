#include "nodes/io/mesh_file.h"
#include "nodes/io/file_extension.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>

#include "graph/file_text.h"
#include "graph/mesh.h"
#include "nodes/common/work_poll.h"
#include "nodes/io/block_writer.h"
#include "nodes/io/float_text.h"
#include "nodes/common/color_space.h"
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

// printf's %.{precision}g of the float's exact value (what an ostream with that precision writes), at `p`.
char* put_float(char* p, float value, int precision) { return format_float_g(p, value, precision); }
char* put_uint(char* p, unsigned value) { return std::to_chars(p, p + 16, value).ptr; }
char* put_text(char* p, std::string_view s) {
  std::memcpy(p, s.data(), s.size());
  return p + s.size();
}
template <class T>
char* put_raw(char* p, T value) {  // little-endian, as every supported host is
  std::memcpy(p, &value, sizeof value);
  return p + sizeof value;
}

// The three corners of a triangle, in the order OpenMesh's face-vertex circulator visits them (the order the
// old copy of the mesh, and so its writers, used).
std::array<TriMesh::VertexHandle, 3> corners(const TriMesh& m, TriMesh::FaceHandle f) {
  const auto h0 = m.halfedge_handle(f), h1 = m.next_halfedge_handle(h0), h2 = m.next_halfedge_handle(h1);
  return {m.to_vertex_handle(h0), m.to_vertex_handle(h1), m.to_vertex_handle(h2)};
}

// Orogen is z-up; y_up writes (x, z, -y). 0 - y, not -y: a southern edge at y = 0 is written "0", not "-0".
OpenMesh::Vec3f axes(OpenMesh::Vec3f p, bool y_up) { return y_up ? OpenMesh::Vec3f(p[0], p[2], 0.0f - p[1]) : p; }

// One OBJ line: `prefix` and `count` floats at 9 significant digits (they read back exactly).
void put_obj_line(BlockWriter& out, std::string_view prefix, const float* values, int count) {
  char* const start = out.room();
  char* p = put_text(start, prefix);
  for (int k = 0; k < count; ++k) {
    if (k > 0) *p++ = ' ';
    p = put_float(p, values[k], 9);
  }
  *p++ = '\n';
  out.advance(static_cast<std::size_t>(p - start));
}

// OBJ (Wavefront) text with positions, optional normals and texture coordinates, and an optional material.
// Written here rather than by OpenMesh's OBJ writer, which has no way to name a texture for vertex UVs.
// Formatted straight into the output block, which is written as it fills.
void write_obj(const TriMesh& m, const std::filesystem::path& path, const MeshWriteOptions& options,
               const std::vector<OpenMesh::Vec2f>& uvs, ProgressPoll& poll) {
  BlockWriter out(path);
  out.put("# Orogen terrain mesh, metres\n");
  if (!options.material_library.empty()) out.put("mtllib " + options.material_library + "\n");
  // Axes converted here, not in a copy of the mesh: copying a mesh of millions of vertices is one long call
  // that cannot be cancelled.
  for (auto v : m.vertices()) {
    put_obj_line(out, "v ", axes(m.point(v), options.y_up).data(), 3);
    poll();
  }
  const bool uv = !uvs.empty();
  for (const auto& t : uvs) {
    put_obj_line(out, "vt ", t.data(), 2);
    poll();
  }
  if (options.normals)
    for (auto v : m.vertices()) {
      put_obj_line(out, "vn ", axes(m.normal(v), options.y_up).data(), 3);
      poll();
    }
  if (!options.material_library.empty()) out.put("usemtl terrain\n");
  for (auto f : m.faces()) {
    char* const start = out.room();
    char* p = start;
    *p++ = 'f';
    for (auto v : m.fv_range(f)) {
      // The vertex, texture and normal indices are the same number: formatted once, copied.
      *p++ = ' ';
      char* const number = p;
      p = put_uint(p, static_cast<unsigned>(v.idx()) + 1);
      const auto digits = static_cast<std::size_t>(p - number);
      if (uv || options.normals) {
        *p++ = '/';
        if (uv) p = static_cast<char*>(std::memcpy(p, number, digits)) + digits;
        if (options.normals) {
          *p++ = '/';
          p = static_cast<char*>(std::memcpy(p, number, digits)) + digits;
        }
      }
    }
    *p++ = '\n';
    out.advance(static_cast<std::size_t>(p - start));
    poll();
  }
  out.finish();
}

// The vertices and faces a file holds: the mesh's, less any marked deleted (which the file skips, numbering
// the rest consecutively, as OpenMesh's writers did).
struct LiveElements {
  std::size_t vertices = 0, faces = 0;
  std::vector<unsigned> index;  // file index by vertex handle; empty when no vertex is deleted
};

LiveElements live_elements(const TriMesh& m) {
  LiveElements live;
  for (auto v : m.vertices()) {
    (void)v;
    ++live.vertices;
  }
  for (auto f : m.faces()) {
    (void)f;
    ++live.faces;
  }
  if (live.vertices != m.n_vertices()) {
    live.index.assign(m.n_vertices(), 0);
    unsigned k = 0;
    for (auto v : m.vertices()) live.index[static_cast<std::size_t>(v.idx())] = k++;
  }
  return live;
}

// PLY (Stanford), ASCII or binary little-endian: positions, optional vertex normals and sRGB 8-bit colors
// (with alpha when some vertex is not opaque), triangles as lists of int indices. The bytes OpenMesh's PLY
// writer wrote from a copy of the mesh (9 significant digits in text), written here in one pass without it.
void write_ply(const TriMesh& m, const std::filesystem::path& path, const MeshWriteOptions& options,
               ProgressPoll& poll) {
  const LiveElements live = live_elements(m);
  bool translucent = false;
  if (options.colors)
    for (auto v : m.vertices()) {
      const float a = m.color(v)[3];
      translucent = translucent || std::clamp(std::isnan(a) ? 1.0f : a, 0.0f, 1.0f) < 1.0f;
      poll();
    }
  const bool binary = options.binary;
  BlockWriter out(path);
  std::string header = "ply\nformat ";
  header += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  header += "element vertex " + std::to_string(live.vertices) + "\n";
  header += "property float x\nproperty float y\nproperty float z\n";
  if (options.normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (options.colors) {
    header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (translucent) header += "property uchar alpha\n";
  }
  header += "element face " + std::to_string(live.faces) + "\n";
  header += "property list uchar int vertex_indices\nend_header\n";
  out.put(header);
  for (auto v : m.vertices()) {
    const auto q = axes(m.point(v), options.y_up);
    char* const start = out.room();
    char* p = start;
    float values[6] = {q[0], q[1], q[2], 0, 0, 0};
    int count = 3;
    if (options.normals) {
      const auto n = axes(m.normal(v), options.y_up);
      values[3] = n[0], values[4] = n[1], values[5] = n[2], count = 6;
    }
    for (int k = 0; k < count; ++k) {
      if (binary) {
        p = put_raw(p, values[k]);
      } else {
        if (k) *p++ = ' ';
        p = put_float(p, values[k], 9);
      }
    }
    if (options.colors) {
      // sRGB clamped to 0..1, rounded to bytes as OpenMesh's color_cast rounds them.
      const auto c = m.color(v);
      const float alpha = std::clamp(std::isnan(c[3]) ? 1.0f : c[3], 0.0f, 1.0f);
      for (int k = 0; k < (translucent ? 4 : 3); ++k) {
        const auto byte = k < 3 ? srgb_byte(c[k]) : static_cast<unsigned char>(alpha * 255.0f + 0.5f);
        if (binary) {
          *p++ = static_cast<char>(byte);
        } else {
          *p++ = ' ';
          p = put_uint(p, byte);
        }
      }
    }
    if (!binary) *p++ = '\n';
    out.advance(static_cast<std::size_t>(p - start));
    poll();
  }
  for (auto f : m.faces()) {
    const auto c = corners(m, f);
    unsigned idx[3];
    for (int k = 0; k < 3; ++k)
      idx[k] =
          live.index.empty() ? static_cast<unsigned>(c[k].idx()) : live.index[static_cast<std::size_t>(c[k].idx())];
    char* const start = out.room();
    char* p = start;
    if (binary) {
      *p++ = 3;
      for (unsigned i : idx) p = put_raw(p, static_cast<std::int32_t>(i));
    } else {
      *p++ = '3';
      for (unsigned i : idx) {
        *p++ = ' ';
        p = put_uint(p, i);
      }
      *p++ = '\n';
    }
    out.advance(static_cast<std::size_t>(p - start));
    poll();
  }
  out.finish();
}

// STL, ASCII or binary: one facet per triangle with its face normal, computed as OpenMesh's
// update_face_normals computes it, from the corners in file axes. The bytes OpenMesh's STL writer wrote (in
// text the first facet normal at its stream's default 6 significant digits, everything after at 10).
void write_stl(const TriMesh& m, const std::filesystem::path& path, const MeshWriteOptions& options,
               ProgressPoll& poll) {
  const LiveElements live = live_elements(m);
  BlockWriter out(path);
  const bool binary = options.binary;
  if (binary) {
    char header[80];
    std::memset(header, ' ', sizeof header);
    std::memcpy(header, "binary stl file", 15);
    header[79] = '\0';
    out.put(header, sizeof header);
    const auto n = static_cast<std::int32_t>(live.faces);
    out.put(&n, sizeof n);
  } else {
    out.put("solid \n");
  }
  int precision = 6;
  for (auto f : m.faces()) {
    const auto c = corners(m, f);
    const OpenMesh::Vec3f a = axes(m.point(c[0]), options.y_up), b = axes(m.point(c[1]), options.y_up),
                          d = axes(m.point(c[2]), options.y_up);
    const OpenMesh::Vec3f n = static_cast<const TriMesh::PolyMesh&>(m).calc_face_normal(a, b, d);
    char* const start = out.room();
    char* p = start;
    if (binary) {
      for (const auto* v : {&n, &a, &b, &d})
        for (int k = 0; k < 3; ++k) p = put_raw(p, (*v)[k]);
      p = put_raw(p, std::uint16_t(0));
    } else {
      p = put_text(p, "facet normal ");
      for (int k = 0; k < 3; ++k) {
        if (k) *p++ = ' ';
        p = put_float(p, n[k], precision);
      }
      p = put_text(p, "\nouter loop\n");
      precision = 10;
      for (const auto* v : {&a, &b, &d}) {
        p = put_text(p, "vertex ");
        for (int k = 0; k < 3; ++k) {
          if (k) *p++ = ' ';
          p = put_float(p, (*v)[k], precision);
        }
        *p++ = '\n';
      }
      p = put_text(p, "\nendloop\nendfacet\n");
    }
    out.advance(static_cast<std::size_t>(p - start));
    poll();
  }
  if (!binary) out.put("endsolid\n");
  out.finish();
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
  // the lines or records written, which go to the file as they are formatted).
  const double nv = static_cast<double>(mesh.mesh.n_vertices()), nf = static_cast<double>(mesh.mesh.n_faces());
  ProgressPoll poll(progress, 3 * nv + nf, 0.0, 1.0);
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
  if (format == MeshFormat::Obj)
    write_obj(mesh.mesh, path, options, uvs, poll);
  else if (format == MeshFormat::Ply)
    write_ply(mesh.mesh, path, options, poll);
  else
    write_stl(mesh.mesh, path, options, poll);
}

}  // namespace orogen
