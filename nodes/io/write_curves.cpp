// WriteCurves: polylines to GeoJSON-like JSON or OBJ lines, atomically.
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/curves_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteCurves) {
  b.reach_global();  // writes the whole input
  b.category("io").writes_files().description(
      "Writes curves (rivers, feature curves) inside the output directory, atomically: GeoJSON-like JSON (a "
      "FeatureCollection of LineStrings in world metres with z, properties index, parent, per-vertex width and "
      "every attribute) or Wavefront OBJ lines (v and l elements, one group per curve, attributes as comments).");
  b.input("in", PortType::Curves).description("Curves to write");
  b.param_path("path", "curves.json")
      .output_file()
      .extensions({".json", ".geojson", ".obj"})
      .description("Output file, relative to the output directory; the extension selects JSON or OBJ");
  // The encoder holds about four times the curves (measured: tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return 4 * input_bytes(q, "in"); });
  b.execute([](ExecContext& ctx) {
    const auto curves = ctx.require<Curves>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto format = curves_format_from_path(path);
    if (!format) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      write_curves_file(*curves, temporary, *format, progress);
    });
  });
}

}  // namespace orogen
