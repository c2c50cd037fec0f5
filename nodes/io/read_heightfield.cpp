// ReadHeightfield: a heightfield from an image file, placed on a world rectangle and resampled to the
// requested domain.
#include <memory>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/output_path.h"
#include "graph/registry.h"
#include "nodes/io/heightfield_file.h"

namespace orogen {

OROGEN_NODE(ReadHeightfield) {
  b.distribution(Distribution::Gathered);
  b.reach(
      [](const ParamView& p) {
        // Spread over the request by default: what a sample reads then depends on the whole requested domain.
        return p.get<glm::dvec2>("size") == glm::dvec2(0.0) ? Reach::global() : Reach::pointwise();
      },
      "global (the image spans the requested domain); point-wise when size is set");
  b.category("io").description(
      "Reads a heightfield from an EXR, PNG (8 or 16-bit), TIFF or RAW 16-bit file and resamples it "
      "(bilinear) to the requested domain. By default the image covers the requested domain exactly (its "
      "pixel centers span the domain's rectangle edge to edge); set `size` (and `origin`) to place it on a "
      "fixed world rectangle instead. The first file row is the northern one (largest y); samples outside the "
      "image's rectangle repeat its edge. Unsigned integer pixels are mapped to heights through "
      "height_min/height_max (or the mapping WriteHeightfield stored in the file); float and signed integer "
      "pixels are heights in metres. RAW files must be square.");
  b.output("out", PortType::Heightfield)
      .description("The heightfield on the requested domain, metres")
      .kind(OutputKind::Height);
  b.param_path("path", "")
      .extensions({".exr", ".png", ".tif", ".tiff", ".raw", ".r16"})
      .description(
          "Image file to read. A relative path is resolved against the directory of the graph file (not the "
          "current directory, not the output directory)");
  b.param_int("channel", 0).unit(Unit::Count).range(0, 63).description("Channel of the image to read (0 = first)");
  b.param_vec2("origin", {0.0, 0.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("With size set: world position of the south-west pixel center (first column, last file row)");
  b.param_vec2("size", {0.0, 0.0})
      .range(0.0, 1e7)
      .unit(Unit::Metre)
      .description(
          "World extent from the first to the last pixel center in x and y; [0, 0] (the default): the requested "
          "domain's, at its origin");
  b.param_float("height_min", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Height of pixel value 0 in integer formats (and of 0.0 in float formats when remap_float is on)");
  b.param_float("height_max", 1000.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 9000)
      .unit(Unit::Metre)
      .description(
          "Height of full scale (255 or 65535) in integer formats (and of 1.0 in float formats when remap_float "
          "is on)");
  b.param_bool("remap_float", false)
      .description(
          "Treat float (and signed integer) pixels as fractions 0..1 and map them through height_min/height_max; "
          "off: they are heights in metres");
  b.param_bool("use_file_mapping", true)
      .description(
          "When the file carries the height mapping WriteHeightfield records (PNG, EXR, TIFF metadata), use it "
          "instead of height_min/height_max");
  // The file is streamed onto the domain (read_heightfield_onto): beyond the output, a band of the file and
  // two rows (the header tells their width), whatever its height.
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    const auto& path = q.params.get<std::string>("path");
    if (path.empty()) return 0;
    const auto channel = static_cast<int>(q.params.get<std::int64_t>("channel"));
    return height_stream_read_bytes(probe_height_raster(resolve_input_path(q.input_dir, path), channel));
  });
  b.execute([](ExecContext& ctx) {
    if (ctx.param<std::string>("path").empty()) throw NodeError("no file given: set 'path' to the image to read");
    const std::filesystem::path path = ctx.input_path("path");
    HeightfieldReadOptions options;
    options.origin = ctx.param<glm::dvec2>("origin");
    options.size = ctx.param<glm::dvec2>("size");
    if (options.size == glm::dvec2(0.0)) {
      options.origin = ctx.domain().min_corner();
      options.size = glm::max(ctx.domain().size(), glm::dvec2(1e-9));  // a single row or column: a line
    } else if (!(options.size.x > 0.0 && options.size.y > 0.0)) {
      throw NodeError("size must be [0, 0] (the requested domain) or positive in both x and y");
    }
    options.range = {ctx.param<double>("height_min"), ctx.param<double>("height_max")};
    options.remap_float = ctx.param<bool>("remap_float");
    options.use_file_mapping = ctx.param<bool>("use_file_mapping");
    const double rows = ctx.domain().height();
    HeightfieldPtr out;
    try {
      out = std::make_shared<Heightfield>(read_heightfield_onto(
          path, static_cast<int>(ctx.param<std::int64_t>("channel")), options, ctx.domain(), [&](int done) {
            ctx.check_cancelled();
            ctx.progress(done / rows);
          }));
    } catch (const FileError& e) {
      throw NodeError(e.what());
    }
    ctx.set_output("out", std::move(out));
  });
}

}  // namespace orogen
