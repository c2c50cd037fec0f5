// WriteMesh: a mesh to OBJ, PLY or STL, atomically.
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/mesh_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteMesh) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes a mesh to OBJ, PLY or STL inside the output directory, atomically (through OpenMesh). Vertex "
      "normals go to OBJ and PLY, vertex colors to PLY (sRGB 8-bit); STL has face normals only. up_axis Y "
      "converts Orogen's z-up coordinates to y-up, (x, y, z) -> (x, z, -y), for Unity and Blender.");
  b.input("in", PortType::Mesh).description("Mesh to write, metres");
  b.param_path("path", "terrain.obj").output_file().extensions({".obj", ".ply", ".stl"}).description(
      "Output file, relative to the output directory; the extension selects the format");
  b.param_enum("up_axis", {"Z", "Y"}, "Z").description(
      "Up axis of the file: Z keeps Orogen's coordinates; Y rotates to y-up (x, z, -y), right-handed");
  b.param_bool("binary", true).description("Binary PLY and STL (smaller, faster); off writes text. OBJ is always text");
  b.param_bool("normals", true).description("Write per-vertex normals (OBJ, PLY)");
  b.param_bool("colors", true).description("Write per-vertex colors (PLY only)");
  b.execute([](ExecContext& ctx) {
    const auto mesh = ctx.require<Mesh>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto format = mesh_format_from_path(path);
    if (!format) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    MeshWriteOptions options;
    options.y_up = ctx.param<std::string>("up_axis") == "Y";
    options.binary = ctx.param<bool>("binary");
    options.normals = ctx.param<bool>("normals");
    options.colors = ctx.param<bool>("colors");
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      write_mesh_file(*mesh, temporary, *format, options);
      if (progress) progress(1.0);
    });
  });
}

}  // namespace orogen
