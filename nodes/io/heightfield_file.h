#pragma once
// Heightfields to and from image files: EXR, PNG, TIFF (through OpenImageIO) and RAW 16-bit.
//
// Row order: files store rows from north to south, like a map seen from above with +x to the right and +y
// up. The first row of a file is the heightfield's last row (largest y), the last row its row 0. Columns run
// west to east (increasing x). RAW files use the same order (the first 2 * width bytes are the northern row).
//
// Height mapping: integer formats store a fraction of full scale; `HeightRange` says which heights in metres
// 0 and full scale stand for. Float formats (EXR, TIFF float32) store metres directly.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graph/heightfield.h"
#include "nodes/io/file_error.h"

namespace orogen {

struct ImageWriteSpec;  // nodes/io/image_codec.h

enum class HeightFormat {
  Exr,    // OpenEXR, float32, zip (lossless), written in blocks of scanlines that OpenEXR compresses in parallel
  Png16,  // PNG, 16-bit grey, mapped through a HeightRange
  Raw16,  // headerless unsigned 16-bit little-endian, row-major, north row first (Unity/Unreal .raw/.r16)
  Tiff,   // TIFF, float32, zip
};

// The format a file name's extension designates (.exr, .png, .raw, .r16, .tif, .tiff; case-insensitive).
std::optional<HeightFormat> height_format_from_path(const std::filesystem::path& path);
const char* to_string(HeightFormat f);

// Heights in metres stored as 0 and as full scale by integer formats.
struct HeightRange {
  double min = 0.0;
  double max = 1.0;
  bool operator==(const HeightRange&) const = default;
};

// Smallest and largest sample; throws FileError if some sample is not finite (NaN or infinite).
HeightRange data_range(const Heightfield& h);

// The unsigned 16-bit code of height `h` under `range`: round((h - min) / (max - min) * 65535), clamped to
// 0..65535; 0 when max == min. Throws FileError for a non-finite height.
std::uint16_t quantize16(double h, const HeightRange& range);
// The height a 16-bit code stands for under `range`.
double dequantize16(std::uint16_t q, const HeightRange& range);

struct HeightfieldWriteOptions {
  HeightFormat format = HeightFormat::Exr;
  // Mapping for the 16-bit formats; nullopt: the data's own range (data_range).
  std::optional<HeightRange> range;
  // zlib (deflate) level of EXR (zip), PNG and TIFF: 0 none, 1 fastest ... 9 smallest; -1 each library's
  // default (see nodes/io/compression.h). RAW16 ignores it.
  int compression_level = -1;
  // OpenEXR codec of float heights: "zip", "none", "piz" (lossless) or "pxr24" (lossy: 24-bit floats).
  std::string exr_compression = "zip";
  WriteProgress progress;  // optional
};

// Writes `h` to `path` in `options.format` (the extension is not consulted, but OpenImageIO formats need a
// matching one). Not atomic by itself: writer nodes call it through write_file_atomically. Records the
// mapping used in the file's metadata where the format allows it (EXR and PNG attributes
// "orogen:height_min", "orogen:height_max" and, for all three image formats, the ImageDescription).
// Returns the mapping used by the 16-bit formats, nullopt for the float formats (they store metres).
// Throws FileError on failure; `options.progress` may throw to abort.
std::optional<HeightRange> write_heightfield_file(const Heightfield& h, const std::filesystem::path& path,
                                                  const HeightfieldWriteOptions& options);

// The image header write_heightfield_file gives a heightfield of `domain` in `options.format` (EXR, PNG16 or
// TIFF; `range` is the 16-bit mapping, needed for PNG16): also what a merge of a tiled build's files writes
// (cli/merge_tiles.h), so that the merged file equals the untiled build's. Throws FileError for RAW16.
ImageWriteSpec heightfield_image_spec(const Domain& domain, const HeightfieldWriteOptions& options,
                                      const std::optional<HeightRange>& range);

// One channel of an image file as read, before any mapping, top (north) row first.
struct HeightRaster {
  int width = 0, height = 0;
  int channels = 0;                         // channels in the file
  std::vector<double> values;               // the chosen channel: fraction of full scale for unsigned integers,
                                            // the stored value for signed integers and floats
  bool unsigned_integer = false;            // values are fractions 0..1 of full scale
  std::string format;                       // e.g. "uint16", "float"
  std::optional<HeightRange> file_mapping;  // Orogen's mapping metadata, if the file carries it
};

// Reads channel `channel` of an EXR, PNG (8/16-bit), TIFF or RAW 16-bit file. RAW files must be square
// (side = sqrt(bytes / 2)) and are returned as unsigned integer fractions. Throws FileError if the file is
// missing, unreadable, or has no such channel.
HeightRaster read_height_raster(const std::filesystem::path& path, int channel = 0);

// An image file's size from its header, before any pixel is read.
struct HeightRasterShape {
  int width = 0, height = 0;
  int channels = 0;
  std::size_t bytes_per_value = 0;  // of the channel read, as stored
  int band_rows = 1;                // rows decoded together when streamed (a tile's height, or a band)
};
// Opens `path` as read_height_raster does (same checks and FileErrors) and reads only its header.
HeightRasterShape probe_height_raster(const std::filesystem::path& path, int channel = 0);
// The bytes read_height_raster and raster_to_heightfield hold for such a file at their peak.
std::uint64_t height_raster_read_bytes(const HeightRasterShape& shape);
// The bytes read_heightfield_onto holds beyond its result: one band of the file and two rows.
std::uint64_t height_stream_read_bytes(const HeightRasterShape& shape);

struct HeightfieldReadOptions {
  glm::dvec2 origin{0.0, 0.0};      // world position of the south-west pixel centre, metres
  glm::dvec2 size{1024.0, 1024.0};  // world extent from the first to the last pixel centre, metres
  HeightRange range{0.0, 1000.0};   // heights for 0 and full scale of unsigned integer formats
  bool remap_float = false;         // also map float and signed values v to min + v * (max - min)
  bool use_file_mapping = true;     // prefer the file's Orogen mapping metadata over `range`
};

// The raster as a heightfield on its own lattice: pixel centres span [origin, origin + size] edge to edge
// (Domain::from_extent with the image's pixel counts), rows flipped so row 0 is the southern row.
Heightfield raster_to_heightfield(const HeightRaster& raster, const HeightfieldReadOptions& options);

// Channel `channel` of the file placed by `options` and resampled (bilinear) onto `target`: the values
// resample_bilinear(raster_to_heightfield(read_height_raster(...)), target) gives, bit for bit, but streamed:
// the file is decoded in file order a band at a time and only the two rows each target row interpolates are
// kept, so the memory is the result plus a band, however large the file (a 16384^2 image onto 257^2 holds
// 257^2 floats and a few rows, not 16384^2 doubles). Rows no target row reads are decoded (the formats are
// sequential) but not kept. `row_done(k)` is called after each of the target's rows, k rows done; it may
// throw to abort (cancellation). Throws FileError like read_height_raster.
Heightfield read_heightfield_onto(const std::filesystem::path& path, int channel, const HeightfieldReadOptions& options,
                                  const Domain& target, const std::function<void(int)>& row_done = {});

}  // namespace orogen
