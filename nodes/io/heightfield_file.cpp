#include "nodes/io/heightfield_file.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/file_timestamp.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <span>
#include <type_traits>

#include "nodes/common/huge_page_buffer.h"
#include "nodes/common/resample.h"
#include "nodes/io/block_rows.h"
#include "nodes/io/checked_image_output.h"
#include "nodes/io/compression.h"
#include "nodes/io/image_codec.h"
#include "nodes/io/native/native_image_readers.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

// Shortest text that reads back as the same double.
std::string exact_number(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::optional<double> parse_number(std::string_view s) {
  double v = 0.0;
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// "key=value" inside a free-text description (value up to ';' or the end).
std::optional<double> find_key(std::string_view text, std::string_view key) {
  const auto at = text.find(std::string(key) + "=");
  if (at == std::string_view::npos) return std::nullopt;
  auto rest = text.substr(at + key.size() + 1);
  return parse_number(rest.substr(0, rest.find(';')));
}

std::string describe_domain(const Domain& d) {
  const auto lo = d.min_corner();
  const auto sz = d.size();
  return "world_origin=" + exact_number(lo.x) + "," + exact_number(lo.y) + " m; world_size=" + exact_number(sz.x) +
         "," + exact_number(sz.y) + " m";
}

void check_finite(float v, int i, int j) {
  if (!std::isfinite(v))
    throw FileError("height at sample (" + std::to_string(i) + ", " + std::to_string(j) +
                    ") is not a finite number and cannot be stored in a 16-bit format");
}

void report(const WriteProgress& progress, int rows_done, int rows) {
  if (progress) progress(static_cast<double>(rows_done) / std::max(rows, 1));
}

// Writes through an image writer (create_checked_output) in blocks of block_rows() scanlines (north row first).
// `convert(j, row, out)` turns heightfield row j into file samples of type T; for float files the rows go straight from
// the heightfield (a negative row stride walks them north to south) without a copy.
template <class T, class Convert>
void write_image(const Heightfield& h, const fs::path& path, const ImageWriteSpec& spec, const WriteProgress& progress,
                 Convert convert) {
  CheckedImageSink sink(path);
  std::string error;
  auto out = create_checked_output(path, sink, spec, error);
  if (!out) throw FileError("cannot create '" + path.string() + "': " + error);
  const std::size_t w = static_cast<std::size_t>(h.width());
  std::vector<T> block;
  const int rows_per_block = block_rows(h.height());
  for (int r0 = 0; r0 < h.height(); r0 += rows_per_block) {
    const int r1 = std::min(r0 + rows_per_block, h.height());
    bool ok = false;
    if constexpr (std::is_same_v<T, float>) {
      const float* first = h.row(h.height() - 1 - r0).data();  // file row r0 is heightfield row H - 1 - r0
      ok = out->write_rows(r0, r1, first, -static_cast<std::ptrdiff_t>(w * sizeof(float)));
    } else {
      block.resize(static_cast<std::size_t>(r1 - r0) * w);
      for (int r = r0; r < r1; ++r) {
        const int j = h.height() - 1 - r;
        convert(j, h.row(j), std::span<T>(block.data() + static_cast<std::size_t>(r - r0) * w, w));
      }
      ok = out->write_rows(r0, r1, block.data(), static_cast<std::ptrdiff_t>(w * sizeof(T)));
    }
    if (!ok)
      throw FileError(sink.file().ok() ? "cannot write '" + path.string() + "': " + out->error() : sink.file().error());
    report(progress, r1, h.height());
  }
  const bool closed = out->close();
  if (!sink.file().ok()) throw FileError(sink.file().error());  // a short write the plugin ignored
  if (!closed) throw FileError("cannot finish '" + path.string() + "': " + out->error());
  try {
    sink.file().finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

void write_raw16(const Heightfield& h, const fs::path& path, const HeightRange& range, const WriteProgress& progress) {
  CheckedFile out(path);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(h.width()) * 2);
  for (int r = 0; r < h.height(); ++r) {
    const int j = h.height() - 1 - r;
    const auto row = h.row(j);
    for (int i = 0; i < h.width(); ++i) {
      check_finite(row[static_cast<std::size_t>(i)], i, j);
      const std::uint16_t q = quantize16(row[static_cast<std::size_t>(i)], range);
      bytes[2 * static_cast<std::size_t>(i)] = static_cast<unsigned char>(q & 0xff);  // little endian
      bytes[2 * static_cast<std::size_t>(i) + 1] = static_cast<unsigned char>(q >> 8);
    }
    if (!out.write(bytes.data(), bytes.size())) throw FileError(out.error());
    report(progress, r + 1, h.height());
  }
  try {
    out.finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

HeightRaster read_raw16(const fs::path& path, int channel) {
  if (channel != 0)
    throw FileError("'" + path.string() + "' is a RAW file with one channel; channel " + std::to_string(channel) +
                    " does not exist");
  std::error_code ec;
  const auto bytes = fs::file_size(path, ec);
  if (ec) throw FileError("cannot read '" + path.string() + "': " + ec.message());
  const auto side = static_cast<std::uint64_t>(std::llround(std::sqrt(static_cast<double>(bytes / 2))));
  if (bytes == 0 || bytes % 2 != 0 || side * side * 2 != bytes)
    throw FileError("'" + path.string() + "' is not a square RAW 16-bit heightmap (" + std::to_string(bytes) +
                    " bytes is not 2 * side * side)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot open '" + path.string() + "'");
  std::vector<unsigned char> data(bytes);
  in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(bytes));
  if (!in) throw FileError("cannot read '" + path.string() + "'");
  HeightRaster r;
  r.width = r.height = static_cast<int>(side);
  r.channels = 1;
  r.unsigned_integer = true;
  r.format = "uint16 (raw, little endian)";
  r.values.resize(side * side);
  for (std::size_t k = 0; k < r.values.size(); ++k) r.values[k] = (data[2 * k] | (data[2 * k + 1] << 8)) / 65535.0;
  return r;
}

// An IEEE 754 binary16 value, exactly.
float half_to_float(std::uint16_t bits) {
  const int sign = bits >> 15, exponent = (bits >> 10) & 0x1f, mantissa = bits & 0x3ff;
  float v = 0.0f;
  if (exponent == 0)
    v = std::ldexp(static_cast<float>(mantissa), -24);  // subnormal (or zero)
  else if (exponent == 31)
    v = mantissa ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
  else
    v = std::ldexp(static_cast<float>(mantissa | 0x400), exponent - 25);
  return sign ? -v : v;
}

// Values of a native-format buffer as doubles: unsigned integers as fractions of full scale, signed integers
// and floats as stored.
double native_value(const unsigned char* p, PixelType t) {
  switch (t) {
    case PixelType::U8:
      return *p / 255.0;
    case PixelType::U16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v / 65535.0;
    }
    case PixelType::U32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v / 4294967295.0;
    }
    case PixelType::I8:
      return static_cast<double>(*reinterpret_cast<const std::int8_t*>(p));
    case PixelType::I16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case PixelType::I32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PixelType::Half: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return half_to_float(v);
    }
    case PixelType::F32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PixelType::F64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    case PixelType::Other:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

bool is_unsigned_integer(PixelType t) { return t == PixelType::U8 || t == PixelType::U16 || t == PixelType::U32; }

bool is_supported(PixelType t) { return t != PixelType::Other; }

std::optional<HeightRange> mapping_from_spec(const ImageReader& spec) {
  const std::string lo = spec.string_attribute("orogen:height_min");
  const std::string hi = spec.string_attribute("orogen:height_max");
  if (auto a = parse_number(lo), b = parse_number(hi); a && b) return HeightRange{*a, *b};
  const std::string desc = spec.string_attribute("ImageDescription");
  if (desc.find("Orogen heightfield") != std::string::npos) {
    auto a = find_key(desc, "height_min"), b = find_key(desc, "height_max");
    if (a && b) return HeightRange{*a, *b};
  }
  return std::nullopt;
}

}  // namespace

std::optional<HeightFormat> height_format_from_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return HeightFormat::Exr;
  if (ext == ".png") return HeightFormat::Png16;
  if (ext == ".raw" || ext == ".r16") return HeightFormat::Raw16;
  if (ext == ".tif" || ext == ".tiff") return HeightFormat::Tiff;
  return std::nullopt;
}

const char* to_string(HeightFormat f) {
  switch (f) {
    case HeightFormat::Exr:
      return "exr";
    case HeightFormat::Png16:
      return "png16";
    case HeightFormat::Raw16:
      return "raw16";
    case HeightFormat::Tiff:
      return "tiff";
  }
  return "?";
}

HeightRange data_range(const Heightfield& h) {
  if (h.data.empty()) throw FileError("the heightfield has no samples");
  HeightRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (int j = 0; j < h.height(); ++j)
    for (int i = 0; i < h.width(); ++i) {
      const float v = h.at(i, j);
      check_finite(v, i, j);
      r.min = std::min(r.min, static_cast<double>(v));
      r.max = std::max(r.max, static_cast<double>(v));
    }
  return r;
}

std::uint16_t quantize16(double h, const HeightRange& range) {
  if (!std::isfinite(h)) throw FileError("a height is not a finite number and cannot be stored in a 16-bit format");
  if (!(range.max > range.min)) return 0;
  const double t = std::clamp((h - range.min) / (range.max - range.min), 0.0, 1.0);
  return static_cast<std::uint16_t>(std::lround(t * 65535.0));
}

double dequantize16(std::uint16_t q, const HeightRange& range) {
  return range.min + (q / 65535.0) * (range.max - range.min);
}

ImageWriteSpec heightfield_image_spec(const Domain& domain, const HeightfieldWriteOptions& options,
                                      const std::optional<HeightRange>& range) {
  if (options.format == HeightFormat::Raw16) throw FileError("RAW files have no image header");
  if (options.format == HeightFormat::Png16 && !range) throw FileError("a 16-bit PNG needs its height range");
  const bool is_float = options.format != HeightFormat::Png16;
  ImageWriteSpec spec;
  spec.width = domain.width();
  spec.height = domain.height();
  spec.channels = 1;
  spec.type = is_float ? PixelType::F32 : PixelType::U16;
  spec.channel_names = {"Y"};
  spec.set("Software", "Orogen");
  spec.set("DateTime", file_timestamp());  // never the time of writing: reproducible files
  std::string description = "Orogen heightfield; ";
  set_compression(spec,
                  options.format == HeightFormat::Exr ? "openexr"
                  : is_float                          ? "tiff"
                                                      : "png",
                  options.compression_level, options.exr_compression);
  if (is_float) {
    description += "float32 heights in metres; ";
  } else {
    description += "height_min=" + exact_number(range->min) + " m; height_max=" + exact_number(range->max) +
                   " m (heights of 0 and full scale); ";
    spec.set("orogen:height_min", exact_number(range->min));
    spec.set("orogen:height_max", exact_number(range->max));
  }
  description += describe_domain(domain) + "; north row first";
  spec.set("ImageDescription", description);
  return spec;
}

std::optional<HeightRange> write_heightfield_file(const Heightfield& h, const fs::path& path,
                                                  const HeightfieldWriteOptions& options) {
  if (h.width() < 1 || h.height() < 1 || h.data.size() != h.domain.sample_count())
    throw FileError("cannot write '" + path.string() + "': the heightfield is empty or inconsistent");
  const bool sixteen = options.format == HeightFormat::Png16 || options.format == HeightFormat::Raw16;
  std::optional<HeightRange> range;
  if (sixteen) {
    range = options.range ? *options.range : data_range(h);
    if (range->max < range->min)
      throw FileError("height range maximum " + exact_number(range->max) + " m is below the minimum " +
                      exact_number(range->min) + " m");
  }
  if (options.format == HeightFormat::Raw16) {
    write_raw16(h, path, *range, options.progress);
    return range;
  }

  const bool is_float = options.format != HeightFormat::Png16;
  const ImageWriteSpec spec = heightfield_image_spec(h.domain, options, range);
  if (is_float) {
    write_image<float>(h, path, spec, options.progress, [](int, std::span<const float>, std::span<float>) {});
  } else {
    const HeightRange r = *range;
    write_image<std::uint16_t>(h, path, spec, options.progress,
                               [&](int j, std::span<const float> row, std::span<std::uint16_t> line) {
                                 for (std::size_t i = 0; i < row.size(); ++i) {
                                   check_finite(row[i], static_cast<int>(i), j);
                                   line[i] = quantize16(row[i], r);
                                 }
                               });
  }
  return range;
}

namespace {

void check_readable_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    // ReadHeightfield passes the path already resolved against the graph file's directory.
    throw FileError("file '" + path.string() + "' does not exist" +
                    (path.is_relative() ? " (relative to the current directory " + fs::current_path(ec).string() + ")"
                                        : std::string()));
  if (fs::is_directory(path, ec)) throw FileError("'" + path.string() + "' is a directory, not an image file");
}

std::unique_ptr<ImageReader> check_height_image(const fs::path& path, std::unique_ptr<ImageReader> in, int channel);

// The image in `path` opened by the reader its extension names, its header checked (the channel exists, 2D,
// at most 65536 per side, a supported pixel type). Throws FileError.
std::unique_ptr<ImageReader> open_height_image(const fs::path& path, const std::string& ext, int channel) {
  // PNG and EXR heights without the codec module when their own libraries read them (its loading costs more
  // than decoding a 4097^2 heightmap); anything else, and any file they refuse, through the codec.
  if (auto in = ext.size() > 1 ? open_native_image_reader(ext.substr(1), path.string()) : nullptr)
    return check_height_image(path, std::move(in), channel);
  const ImageCodec& codec = image_codec_for(path, "read");
  // Only the reader the extension names: OpenImageIO would otherwise try every format plugin it has (movie,
  // camera raw, ...) on a damaged file, a much larger attack surface and slow for nothing.
  // (Given the file name, create() would still sniff the content; given only the extension, it cannot.)
  auto in = ext.size() > 1 ? codec.create_reader(ext.substr(1)) : nullptr;
  if (!in)
    throw FileError("cannot read '" + path.string() + "': no image reader for the extension '" + ext +
                    "' (for example .png, .exr, .tif, .raw or .r16)");
  // Never premultiplies a height channel by alpha.
  if (!in->open(path.string()))
    throw FileError("cannot read '" + path.string() + "' as " + in->format_name() +
                    " (is the extension right?): " + in->error());
  return check_height_image(path, std::move(in), channel);
}

// An opened image's header checked (the channel exists, 2D, at most 65536 per side, a supported pixel type).
std::unique_ptr<ImageReader> check_height_image(const fs::path& path, std::unique_ptr<ImageReader> in, int channel) {
  const ImageInfo& spec = in->info();
  if (channel < 0 || channel >= spec.channels)
    throw FileError("'" + path.string() + "' has " + std::to_string(spec.channels) + " channel(s); channel " +
                    std::to_string(channel) + " does not exist");
  if (spec.width < 1 || spec.height < 1 || spec.depth > 1) throw FileError("'" + path.string() + "' is not a 2D image");
  // A header is not a promise: a few bytes can claim a gigapixel image. Refuse what no domain can hold.
  if (spec.width > 65536 || spec.height > 65536)
    throw FileError("'" + path.string() + "' is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    " pixels; at most 65536 per side can be read");
  const PixelType type = spec.channel_types[static_cast<std::size_t>(channel)];
  if (!is_supported(type))
    throw FileError("'" + path.string() + "' stores pixels as " +
                    spec.channel_type_texts[static_cast<std::size_t>(channel)] + ", which is not supported");
  return in;
}

// Rows decoded in one call when streaming: a tile's height (a tile is decoded whole), else a small band.
int band_rows_of(const ImageInfo& spec) { return spec.tile_height > 0 ? spec.tile_height : 16; }

// The rows of a height file in file order (the northern first), a band at a time: values as read_height_raster
// gives them (fractions of full scale for unsigned integers, stored values otherwise).
class HeightRowReader {
 public:
  HeightRowReader(const fs::path& path, int channel) : path_(path) {
    check_readable_file(path);
    const std::string ext = lower_extension(path);
    if (ext == ".raw" || ext == ".r16") {
      if (channel != 0)
        throw FileError("'" + path.string() + "' is a RAW file with one channel; channel " + std::to_string(channel) +
                        " does not exist");
      const HeightRasterShape shape = probe_height_raster(path, channel);
      std::error_code ec;
      const auto bytes = fs::file_size(path, ec);
      const auto side = static_cast<std::uint64_t>(shape.width);
      if (ec || bytes == 0 || bytes % 2 != 0 || side * side * 2 != bytes)
        throw FileError("'" + path.string() + "' is not a square RAW 16-bit heightmap (" + std::to_string(bytes) +
                        " bytes is not 2 * side * side)");
      raw_.open(path, std::ios::binary);
      if (!raw_) throw FileError("cannot open '" + path.string() + "'");
      width_ = height_ = shape.width;
      unsigned_integer_ = true;
      type_ = PixelType::U16;
      band_rows_ = 1;
    } else {
      in_ = open_height_image(path, ext, channel);
      const ImageInfo& spec = in_->info();
      width_ = spec.width;
      height_ = spec.height;
      channel_ = channel;
      type_ = spec.channel_types[static_cast<std::size_t>(channel)];
      unsigned_integer_ = is_unsigned_integer(type_);
      file_mapping_ = mapping_from_spec(*in_);
      band_rows_ = band_rows_of(spec);
    }
    type_size_ = pixel_type_size(type_);
    band_.resize(static_cast<std::size_t>(band_rows_) * static_cast<std::size_t>(width_) * type_size_);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  bool unsigned_integer() const { return unsigned_integer_; }
  const std::optional<HeightRange>& file_mapping() const { return file_mapping_; }

  // File row r (0 = the northern one) into `out` (width() values).
  void read(int r, std::span<double> out) {
    const std::size_t row_bytes = static_cast<std::size_t>(width_) * type_size_;
    if (raw_.is_open()) {
      raw_.seekg(static_cast<std::streamoff>(r) * static_cast<std::streamoff>(row_bytes));
      raw_.read(reinterpret_cast<char*>(band_.data()), static_cast<std::streamsize>(row_bytes));
      if (!raw_) throw FileError("cannot read '" + path_.string() + "'");
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = (band_[2 * k] | (band_[2 * k + 1] << 8)) / 65535.0;
      return;
    }
    if (band_start_ < 0 || r < band_start_ || r >= band_start_ + band_rows_) {
      band_start_ = r - r % band_rows_;
      const int y0 = in_->info().y + band_start_;
      const int y1 = in_->info().y + std::min(band_start_ + band_rows_, height_);
      // Native reads: read_scanlines converting the format would allocate a 64 MB chunk whatever the band.
      const bool read = in_->info().tile_width > 0
                            ? read_tile_row(y0, y1)
                            : in_->read_native_scanlines(y0, y1, channel_, channel_ + 1, band_.data());
      if (!read) throw FileError("cannot read the pixels of '" + path_.string() + "': " + in_->error());
    }
    const unsigned char* row = band_.data() + static_cast<std::size_t>(r - band_start_) * row_bytes;
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = native_value(row + k * type_size_, type_);
  }

 private:
  // The channel's rows [y0, y1) of a tiled image into band_, a tile at a time (a tile holds every channel,
  // padded to the tile's size at the image's edges).
  bool read_tile_row(int y0, int y1) {
    const ImageInfo& spec = in_->info();
    std::size_t offset = 0;  // of the channel within a native pixel
    for (int c = 0; c < channel_; ++c) offset += spec.channel_sizes[static_cast<std::size_t>(c)];
    const std::size_t pixel = spec.native_pixel_bytes, value = type_size_;
    tile_.resize(spec.native_tile_bytes);
    for (int x0 = spec.x; x0 < spec.x + width_; x0 += spec.tile_width) {
      if (!in_->read_native_tile(x0, y0, tile_.data())) return false;
      const int columns = std::min(spec.tile_width, spec.x + width_ - x0);
      for (int y = y0; y < y1; ++y)
        for (int i = 0; i < columns; ++i) {
          const std::size_t from = (static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(spec.tile_width) +
                                    static_cast<std::size_t>(i)) *
                                       pixel +
                                   offset;
          const std::size_t to = (static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width_) +
                                  static_cast<std::size_t>(x0 - spec.x + i)) *
                                 value;
          std::memcpy(band_.data() + to, tile_.data() + from, value);
        }
    }
    return true;
  }

  fs::path path_;
  std::vector<unsigned char> tile_;
  std::unique_ptr<ImageReader> in_;
  std::ifstream raw_;
  int width_ = 0, height_ = 0, channel_ = 0, band_rows_ = 1, band_start_ = -1;
  PixelType type_ = PixelType::Other;
  std::size_t type_size_ = 0;
  bool unsigned_integer_ = false;
  std::optional<HeightRange> file_mapping_;
  std::vector<unsigned char> band_;
};

}  // namespace

HeightRasterShape probe_height_raster(const fs::path& path, int channel) {
  check_readable_file(path);
  const std::string ext = lower_extension(path);
  if (ext == ".raw" || ext == ".r16") {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (ec) throw FileError("cannot read '" + path.string() + "': " + ec.message());
    const auto side = static_cast<int>(std::llround(std::sqrt(static_cast<double>(bytes / 2))));
    return {side, side, 1, 2, 1};
  }
  const auto in = open_height_image(path, ext, channel);
  const ImageInfo& spec = in->info();
  return {spec.width, spec.height, spec.channels, spec.channel_sizes[static_cast<std::size_t>(channel)],
          band_rows_of(spec)};
}

std::uint64_t height_raster_read_bytes(const HeightRasterShape& shape) {
  const std::uint64_t pixels = static_cast<std::uint64_t>(shape.width) * static_cast<std::uint64_t>(shape.height);
  // The file's channel as stored, its values as doubles (HeightRaster), then as the float heightfield on the
  // image's own lattice (raster_to_heightfield).
  return pixels * (shape.bytes_per_value + sizeof(double) + sizeof(float));
}

std::uint64_t height_stream_read_bytes(const HeightRasterShape& shape) {
  const auto width = static_cast<std::uint64_t>(shape.width);
  // A band of every channel as decoded and of the channel read, a row of values, two rows of heights.
  const std::uint64_t band = static_cast<std::uint64_t>(shape.band_rows) * width * shape.bytes_per_value *
                             (static_cast<std::uint64_t>(shape.channels) + 1);
  return band + width * (sizeof(double) + 2 * sizeof(float));
}

HeightRaster read_height_raster(const fs::path& path, int channel) {
  check_readable_file(path);
  const std::string ext = lower_extension(path);
  if (ext == ".raw" || ext == ".r16") return read_raw16(path, channel);
  const auto in = open_height_image(path, ext, channel);
  const ImageInfo& spec = in->info();
  const PixelType type = spec.channel_types[static_cast<std::size_t>(channel)];
  const std::size_t type_size = pixel_type_size(type);

  HeightRaster r;
  r.width = spec.width;
  r.height = spec.height;
  r.channels = spec.channels;
  r.format = spec.channel_type_texts[static_cast<std::size_t>(channel)];
  r.unsigned_integer = is_unsigned_integer(type);
  r.file_mapping = mapping_from_spec(*in);
  const std::size_t n = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  std::vector<unsigned char> buffer(n * type_size);
  if (!in->read_image(channel, channel + 1, type, buffer.data()))
    throw FileError("cannot read the pixels of '" + path.string() + "': " + in->error());
  r.values.resize(n);
  for (std::size_t k = 0; k < n; ++k) r.values[k] = native_value(buffer.data() + k * type_size, type);
  return r;
}

Heightfield raster_to_heightfield(const HeightRaster& raster, const HeightfieldReadOptions& options) {
  if (!(options.size.x > 0) || !(options.size.y > 0)) throw FileError("the image rectangle must have a positive size");
  const HeightRange range = options.use_file_mapping && raster.file_mapping ? *raster.file_mapping : options.range;
  const bool map = raster.unsigned_integer || options.remap_float;
  Heightfield h(Domain::from_extent(options.origin, options.size, {raster.width, raster.height}));
  for (int r = 0; r < raster.height; ++r) {
    const int j = raster.height - 1 - r;  // the file's first row is the northern one
    for (int i = 0; i < raster.width; ++i) {
      const double v = raster.values[static_cast<std::size_t>(r) * static_cast<std::size_t>(raster.width) +
                                     static_cast<std::size_t>(i)];
      h.at(i, j) = static_cast<float>(map ? range.min + v * (range.max - range.min) : v);
    }
  }
  return h;
}

}  // namespace orogen

namespace orogen {

Heightfield read_heightfield_onto(const fs::path& path, int channel, const HeightfieldReadOptions& options,
                                  const Domain& target, const std::function<void(int)>& row_done) {
  if (!(options.size.x > 0) || !(options.size.y > 0)) throw FileError("the image rectangle must have a positive size");
  HeightRowReader reader(path, channel);
  const int w = reader.width(), h = reader.height();
  const Domain source = Domain::from_extent(options.origin, options.size, {w, h});
  // The mapping and rounding of raster_to_heightfield, row by row.
  const HeightRange range = options.use_file_mapping && reader.file_mapping() ? *reader.file_mapping() : options.range;
  const bool map = reader.unsigned_integer() || options.remap_float;
  std::vector<double> values(static_cast<std::size_t>(w));
  std::vector<float> rows[2] = {std::vector<float>(values.size()), std::vector<float>(values.size())};
  int held[2] = {-1, -1};  // the source row (0 = the southern one) in each slot: row k lives in slot k % 2
  const auto source_row = [&](int j) -> std::span<const float> {
    std::vector<float>& row = rows[j % 2];
    if (held[j % 2] != j) {
      reader.read(h - 1 - j, values);  // the file's first row is the northern one
      for (std::size_t i = 0; i < values.size(); ++i)
        row[i] = static_cast<float>(map ? range.min + values[i] * (range.max - range.min) : values[i]);
      held[j % 2] = j;
    }
    return row;
  };
  // The output zeroed like Heightfield(target), but in huge pages where the kernel gives them: the first-touch
  // faults of a 4096^2 grid in 4 KB pages cost more CPU than reading the file.
  Heightfield out;
  out.domain = target;
  out.data.reserve(target.sample_count());
  huge_pages::advise(out.data.data(), out.data.capacity() * sizeof(float));
  out.data.resize(target.sample_count());
  const BilinearColumns columns = bilinear_columns(source, target);
  // From the north down, so the file is read in its own order.
  for (int j = target.height() - 1, done = 1; j >= 0; --j, ++done) {
    const BilinearRows br = bilinear_rows(source, target, j);
    if (br.lower < 0) {
      resample_bilinear_row(columns, {}, {}, br, out.row(j));
    } else {
      const std::span<const float> upper = source_row(br.upper);  // the northern of the two: read first
      const std::span<const float> lower = source_row(br.lower);
      resample_bilinear_row(columns, lower, upper, br, out.row(j));
    }
    if (row_done) row_done(done);
  }
  return out;
}

}  // namespace orogen
