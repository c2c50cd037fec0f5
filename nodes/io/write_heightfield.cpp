// WriteHeightfield: a heightfield to EXR, PNG 16-bit, RAW 16-bit or TIFF, atomically.
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "graph/checked_file.h"
#include "nodes/io/georeference.h"
#include "nodes/io/height_sidecar.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteHeightfield) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes a heightfield to a file inside the output directory, atomically (a failed or cancelled write "
      "leaves the previous file untouched). Formats: EXR (float32 metres), PNG (16-bit gray), RAW (16-bit "
      "unsigned little-endian, headerless, as Unity and Unreal import; .raw or .r16), TIFF (float32 metres). "
      "Rows are stored north (largest y) first. The 16-bit formats map heights linearly to 0..65535 over the "
      "data's own range ('auto') or a fixed range; the mapping is recorded in PNG metadata (and in the "
      "description of every image format) so ReadHeightfield restores metres. PNG16 and RAW16 files get a "
      "sidecar <file>.json with the mapping, the cell size and Unreal's landscape X/Y/Z scale, since engines "
      "and RAW keep no metadata.");
  b.input("in", PortType::Heightfield).description("Heightfield to write, metres");
  b.param_path("path", "height.exr")
      .output_file()
      .extensions({".exr", ".png", ".raw", ".r16", ".tif", ".tiff"})
      .description("Output file, relative to the output directory; the extension selects the format");
  b.param_enum("format", {"auto", "exr", "png16", "raw16", "tiff"}, "auto")
      .description("File format; 'auto' follows the extension. An explicit format must agree with the extension");
  b.param_enum("range", {"auto", "fixed"}, "auto")
      .description(
          "Height mapping of the 16-bit formats: 'auto' maps the data's minimum to 0 and maximum to 65535; "
          "'fixed' maps height_min and height_max (heights outside are clamped). Float formats store metres");
  b.param_float("height_min", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Height stored as 0 when range is 'fixed'");
  b.param_float("height_max", 1000.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 9000)
      .unit(Unit::Metre)
      .description("Height stored as 65535 when range is 'fixed'; must exceed height_min");
  b.param_int("compression_level", 1)
      .unit(Unit::Unitless)
      .range(0, 9)
      .description(
          "zlib (deflate) level of 16-bit PNG, TIFF and EXR with exr_compression 'zip': 1 is the fastest (on "
          "terrain about 1% larger than zlib's default 6 and a third of its time for PNG, 2% and 60% for TIFF), "
          "9 the smallest and slowest, 0 no compression. RAW16 ignores it");
  b.param_enum("exr_compression", {"none", "zip", "piz", "pxr24"}, "none")
      .description(
          "OpenEXR codec of the float32 heights. 'none' (default): computed terrain's low mantissa bytes are "
          "noise, so 'zip' saves only about 5% at 4x the writing time (67 vs 63 MB at 4096^2); 'piz' (lossless "
          "wavelet) saves about 18% at 5x the time; 'pxr24' halves the file but rounds heights to 24-bit floats "
          "(about 1 cm at 1 km), so it is lossy. Other formats ignore it");
  b.param_string("crs", "").description(
      "Coordinate reference system for GIS, e.g. EPSG:32633 (any text GDAL's SetFromUserInput takes): when set, "
      "<file>.aux.xml beside the file gives GDAL and QGIS its CRS and geotransform (the domain's metres are "
      "the CRS's units). Empty: no georeference");
  b.execute([](ExecContext& ctx) {
    const auto h = ctx.require<Heightfield>("in");
    const std::string& path = ctx.param<std::string>("path");
    const auto by_extension = height_format_from_path(path);
    if (!by_extension) throw NodeError("cannot tell the format of '" + path + "' from its extension");
    HeightfieldWriteOptions options;
    options.format = *by_extension;
    options.compression_level = static_cast<int>(ctx.param<std::int64_t>("compression_level"));
    options.exr_compression = ctx.param<std::string>("exr_compression");
    if (const auto& f = ctx.param<std::string>("format"); f != "auto" && f != to_string(*by_extension))
      throw NodeError("format '" + f + "' does not match the extension of '" + path + "' (" + to_string(*by_extension) +
                      ")");
    if (ctx.param<std::string>("range") == "fixed") {
      const HeightRange r{ctx.param<double>("height_min"), ctx.param<double>("height_max")};
      if (!(r.max > r.min)) throw NodeError("height_max must be greater than height_min for a fixed range");
      options.range = r;
    }
    const std::filesystem::path target = ctx.output_path("path");  // NodeError if the path rule refuses it
    std::optional<HeightRange> used;
    std::vector<NodeOutputFile> files;
    files.push_back({target, [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
                       options.progress = progress;
                       used = write_heightfield_file(*h, temporary, options);
                     }});
    if (options.format == HeightFormat::Png16 || options.format == HeightFormat::Raw16) {
      // The mapping beside the 16-bit file, written after it (it needs the range) and renamed after it.
      std::filesystem::path sidecar = target;
      sidecar += ".json";
      files.push_back({sidecar, [&](const std::filesystem::path& temporary, const WriteProgress&) {
                         write_text_file(temporary, height_sidecar_json(*h, options.format, used.value(),
                                                                        target.filename().string()));
                       }});
    }
    if (const std::string& crs = ctx.param<std::string>("crs"); !crs.empty()) {
      if (crs.find_first_of("\n\r") != std::string::npos) throw NodeError("parameter 'crs': one line of text");
      std::filesystem::path pam = target;
      pam += ".aux.xml";
      files.push_back({pam, [&](const std::filesystem::path& temporary, const WriteProgress&) {
                         write_text_file(temporary, gdal_pam_xml(h->domain, crs));
                       }});
    }
    write_node_files(ctx, files);
  });
}

}  // namespace orogen
