// WritePoints: points to CSV or ASCII PLY, atomically.
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/points_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WritePoints) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes points (scatter results, sources, ...) to CSV or ASCII PLY inside the output directory, "
      "atomically. Columns: x, y, z (metres, z up), qw, qx, qy, qz (rotation quaternion), sx, sy, sz (scale), "
      "class, then the named attributes sorted by name.");
  b.input("in", PortType::Points).description("Points to write");
  b.param_path("path", "points.csv")
      .output_file()
      .extensions({".csv", ".ply"})
      .description("Output file, relative to the output directory; the extension selects CSV or PLY");
  // The encoder's buffers, about 64 KiB whatever the size (measured: tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery&) -> std::uint64_t { return 64 * 1024; });
  b.execute([](ExecContext& ctx) {
    const auto points = ctx.require<Points>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto format = points_format_from_path(path);
    if (!format) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      write_points_file(*points, temporary, *format, progress);
    });
  });
}

}  // namespace orogen
