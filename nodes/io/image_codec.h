#pragma once
// Image files (PNG, EXR, TIFF) through a codec loaded at run time. OpenImageIO drags some 250 shared
// libraries (ffmpeg, OpenCV, GDAL, ...) whose loading cost every start of the CLI ~0.6 s of CPU, so it
// lives in a module (orogen_image_codec, nodes/io/oiio/) that is opened on the first image read or written.
// This header names no OpenImageIO type: plain descriptions of a file cross the boundary, errors as text.
//
// The module is looked for, in order: $OROGEN_IMAGE_CODEC (only there, when set); beside an installed
// program (<prefix>/bin/../<libdir>/orogen_image_codec.so); the build tree's copy, for programs of the build
// tree. image_codec() throws std::runtime_error naming the paths tried and the loader's reason.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace orogen {

// Sample types of image files, as OpenImageIO names its base types.
enum class PixelType { U8, I8, U16, I16, U32, I32, Half, F32, F64, Other };
std::size_t pixel_type_size(PixelType t);  // 0 for Other

// A named metadata attribute ("compression", "png:compressionLevel", "ImageDescription", ...).
struct ImageAttribute {
  std::string name;
  std::variant<int, float, std::string> value;
};

// What a writer creates. Attributes are set on the file's header in this order.
struct ImageWriteSpec {
  int width = 0, height = 0, channels = 0;
  PixelType type = PixelType::F32;
  std::vector<std::string> channel_names;
  int alpha_channel = -1;
  std::vector<ImageAttribute> attributes;
  void set(std::string name, std::variant<int, float, std::string> value) {
    attributes.push_back({std::move(name), std::move(value)});
  }
};

// Where a writer's bytes go: the host's checked file (full-disk checks stay with the host).
class ImageByteSink {
 public:
  virtual ~ImageByteSink() = default;
  virtual bool pwrite(const void* data, std::size_t size, std::int64_t offset) = 0;
  virtual std::int64_t size() const = 0;
};

class ImageWriter {
 public:
  virtual ~ImageWriter() = default;
  // File rows [y0, y1) of the spec's type, `row_stride` bytes from the start of a row to the next (negative
  // walks memory backwards). False on failure (error() says why).
  virtual bool write_rows(int y0, int y1, const void* data, std::ptrdiff_t row_stride) = 0;
  virtual bool close() = 0;
  virtual std::string error() = 0;
};

// An image file's header as read.
struct ImageInfo {
  int x = 0, y = 0, z = 0;  // data window origin
  int width = 0, height = 0, depth = 1, channels = 0;
  int tile_width = 0, tile_height = 0;  // 0: scanline file
  PixelType format = PixelType::Other;  // the file's overall sample type
  std::string format_text;              // its name ("uint16", "float", ...)
  std::vector<PixelType> channel_types;
  std::vector<std::string> channel_type_texts;
  std::vector<std::size_t> channel_sizes;  // bytes of each channel's native sample
  std::vector<std::string> channel_names;  // as the file names them; empty when the reader does not say
  std::size_t native_pixel_bytes = 0, native_tile_bytes = 0;
};

class ImageReader {
 public:
  virtual ~ImageReader() = default;
  // Opens `path` (never premultiplying by alpha). False on failure (error() says why).
  virtual bool open(const std::string& path) = 0;
  virtual std::string format_name() const = 0;
  virtual const ImageInfo& info() const = 0;
  virtual std::string string_attribute(const std::string& name) const = 0;  // "" when absent
  // Channels [c0, c1) of rows [y0, y1) in their native types, packed.
  virtual bool read_native_scanlines(int y0, int y1, int c0, int c1, void* data) = 0;
  // The whole tile (every channel, native) whose corner is (x, y).
  virtual bool read_native_tile(int x, int y, void* data) = 0;
  // Channels [c0, c1) of the whole image converted to `type`, packed.
  virtual bool read_image(int c0, int c1, PixelType type, void* data) = 0;
  virtual std::string error() = 0;
};

class ImageCodec {
 public:
  // A writer of the format `filename`'s extension names, writing into `sink`; null with `error` set.
  virtual std::unique_ptr<ImageWriter> create_writer(const std::string& filename, ImageByteSink& sink,
                                                     const ImageWriteSpec& spec, std::string& error) const = 0;
  // An unopened reader of `format` (a format name or an extension without its dot), null if there is none.
  // Only that reader: never every format's on a damaged file.
  virtual std::unique_ptr<ImageReader> create_reader(const std::string& format) const = 0;
  // A reader chosen by the file's name (and content), opened; null with `error` set.
  virtual std::unique_ptr<ImageReader> open_reader(const std::string& path, std::string& error) const = 0;

 protected:
  ~ImageCodec() = default;  // the module owns it
};

// The codec, loaded on first use (thread-safe). Throws std::runtime_error if the module cannot be loaded.
const ImageCodec& image_codec();

}  // namespace orogen

// The module's entry point; the version in the name keeps a stale module from being used.
#define OROGEN_IMAGE_CODEC_ENTRY "orogen_image_codec_v2"
