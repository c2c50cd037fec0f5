// WriteMesh: a mesh to OBJ, PLY or STL, atomically.
#include "graph/checked_file.h"
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/geometry/mesh_base.h"
#include "nodes/io/block_writer.h"
#include "nodes/io/mesh_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteMesh) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes a mesh to OBJ, PLY or STL or glTF 2.0 (.gltf or binary .glb; "
      "always y-up, linear vertex colors, the mesh's own texture coordinates) inside the output directory, "
      "atomically. Vertex "
      "normals go to OBJ and PLY, vertex colors to PLY (sRGB 8-bit); STL has face normals only. OBJ also gets "
      "texture coordinates (the mesh's own, e.g. around and along tree branches, else over its footprint) and, with a "
      "texture, a material library (.mtl beside the "
      "OBJ) that drapes the image over the terrain. base_depth closes a terrain into a solid (skirt walls and a "
      "flat bottom) for 3D printing. Orogen's coordinates are z-up; up_axis auto writes OBJ y-up, (x, y, z) -> "
      "(x, z, -y), as Blender, Maya, Unity and most DCC tools import OBJ, and PLY and STL z-up as slicers and "
      "point-cloud tools expect.");
  b.input("in", PortType::Mesh).description("Mesh to write, metres");
  b.param_path("path", "terrain.obj")
      .output_file()
      .extensions({".obj", ".ply", ".stl", ".gltf", ".glb"})
      .description("Output file, relative to the output directory; the extension selects the format");
  b.param_enum("up_axis", {"auto", "Z", "Y"}, "auto")
      .description(
          "Up axis of the file: auto is Y for OBJ and Z for PLY and STL; Z keeps Orogen's coordinates; Y "
          "rotates to y-up (x, z, -y), right-handed. glTF is y-up whatever the setting (its specification)");
  b.param_bool("binary", true).description("Binary PLY and STL (smaller, faster); off writes text. OBJ is always text");
  b.param_bool("normals", true).description("Write per-vertex normals (OBJ, PLY)");
  b.param_bool("colors", true).description("Write per-vertex colors (PLY only)");
  b.param_bool("uvs", true)
      .description(
          "OBJ: per-vertex texture coordinates: the mesh's own when it has them (TreeMesh, HullRock), else the xy "
          "footprint mapped onto 0..1 (u east, v north), so an image of "
          "the same domain drapes over the terrain");
  b.param_string("texture", "")
      .file_text()
      .description(
          "OBJ: the color image to drape, as a path relative to the OBJ file (e.g. color.png when WriteImage "
          "writes it beside the mesh); written as map_Kd into <name>.mtl beside the OBJ, which the OBJ names with "
          "mtllib. One printable line (no control characters). Empty: no material file");
  b.param_float("base_depth", 0.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 500.0)
      .unit(Unit::Metre)
      .description(
          "Closes the mesh into a solid (every edge shared by two faces) for 3D printing: walls down from the open "
          "border to this many metres below the lowest vertex and a flat bottom. 0: the open surface");
  // The writers stream the file from the mesh through a 1 MiB block (counted); beyond it only OBJ's texture coordinates
  // (8 of a vertex's ~100 bytes; a quarter of the mesh allowed), and with base_depth the closed copy of the mesh.
  b.extra_bytes([](const CostQuery& q) {
    const std::uint64_t in = input_bytes(q, "in");
    return BlockWriter::kBlock + BlockWriter::kMaxRoom + in / 4 +
           (q.params.get<double>("base_depth") > 0.0 ? 3 * in / 2 : 0);
  });
  b.execute([](ExecContext& ctx) {
    const auto mesh = ctx.require<Mesh>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto format = mesh_format_from_path(path);
    if (!format) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    MeshWriteOptions options;
    const std::string& up_axis = ctx.param<std::string>("up_axis");
    options.y_up = up_axis == "Y" || (up_axis == "auto" && *format == MeshFormat::Obj);
    options.binary = ctx.param<bool>("binary");
    options.normals = ctx.param<bool>("normals");
    options.colors = ctx.param<bool>("colors");
    options.uvs = ctx.param<bool>("uvs");
    const std::string& texture = ctx.param<std::string>("texture");
    const double base_depth = ctx.param<double>("base_depth");
    MeshPtr solid = mesh;
    if (base_depth > 0.0) solid = std::make_shared<const Mesh>(mesh_with_base(*mesh, base_depth));
    options.name = ctx.node_id();
    const std::filesystem::path target = ctx.output_path("path");  // NodeError if the path rule refuses it
    std::vector<NodeOutputFile> files;
    if (*format == MeshFormat::Obj && !texture.empty()) {
      // The material library beside the OBJ: checked like the OBJ and renamed before it, so the OBJ never
      // names a missing file.
      std::filesystem::path library = target;
      library.replace_extension(".mtl");
      options.material_library = library.filename().string();
      std::string text;
      try {
        text = material_library_text(texture);
      } catch (const FileError& e) {
        throw NodeError(std::string("parameter 'texture': ") + e.what());
      }
      files.push_back({library, [text](const std::filesystem::path& temporary, const WriteProgress&) {
                         write_text_file(temporary, text);
                       }});
    }
    files.push_back({target, [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
                       write_mesh_file(*solid, temporary, *format, options, progress);
                       if (progress) progress(1.0);
                     }});
    write_node_files(ctx, files);
  });
}

}  // namespace orogen
