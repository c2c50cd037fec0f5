// WriteImage: an Image to PNG (8 or 16-bit), EXR or TIFF, atomically.
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/image_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteImage) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes an image (color map, splat weights, ...) to a file inside the output directory, atomically. "
      "PNG (8 or 16-bit, 1 to 4 channels, values clamped to 0..1; a color image's color channels sRGB-encoded by "
      "default, weights, masks, ids and normals stored linear as the data they are), "
      "EXR and TIFF (float32, linear, any channel count). Rows are stored north (largest y) first; alpha is "
      "straight, not premultiplied.");
  b.input("in", PortType::Image).description("Image to write; linear values");
  b.param_path("path", "image.png")
      .output_file()
      .extensions({".png", ".exr", ".tif", ".tiff"})
      .description("Output file, relative to the output directory; the extension selects the format");
  b.param_enum("bit_depth", {"8", "16"}, "8").description("Bits per channel of PNG files (EXR and TIFF are float32)");
  b.param_bool("srgb", true)
      .description(
          "Encode the color channels of a color image (ColorRamp, ColorByLayers, Biomes, ...) in PNG with the "
          "sRGB transfer curve (what image viewers expect); off stores the linear values. Data images (splat "
          "weights, masks, ids, normals), alpha and the float formats are never encoded");
  b.param_int("compression_level", 6)
      .unit(Unit::Unitless)
      .range(0, 9)
      .description(
          "zlib (deflate) level of PNG, EXR (zip) and TIFF: 6 is zlib's balance, 1 the fastest (about twice as "
          "fast for 8-bit PNG, but the file can be half again as large), 9 the smallest and slowest, 0 no "
          "compression");
  // The encoder's buffers, about 224 KiB whatever the size (measured: tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery&) -> std::uint64_t { return 224 * 1024; });
  b.execute([](ExecContext& ctx) {
    const auto image = ctx.require<Image>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto format = image_format_from_path(path);
    if (!format) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    ImageWriteOptions options;
    options.format = *format;
    if (*format == ImageFormat::Png8 && ctx.param<std::string>("bit_depth") == "16")
      options.format = ImageFormat::Png16;
    options.srgb = ctx.param<bool>("srgb") && image->color;  // weights must still sum to 255 when written
    options.compression_level = static_cast<int>(ctx.param<std::int64_t>("compression_level"));
    write_node_output(ctx, "path", [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
      options.progress = progress;
      write_image_file(*image, temporary, options);
    });
  });
}

}  // namespace orogen
