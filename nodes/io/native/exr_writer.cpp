// Scanline EXR through OpenEXR, the header as OpenImageIO's writer makes it (see native_image_writers.h): the
// same attributes under the same names, so the same OpenEXR library writes the same bytes
// (tests/test_native_writers.cpp compares them with the codec's files).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <exception>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <vector>

#include "nodes/io/native/native_image_writers.h"
#include "nodes/io/native/row_order.h"

namespace orogen {
namespace {

std::optional<Imf::PixelType> exr_pixel_type(PixelType t) {
  switch (t) {
    case PixelType::Half:
      return Imf::HALF;
    case PixelType::F32:
      return Imf::FLOAT;
    case PixelType::U32:
      return Imf::UINT;
    default:
      return std::nullopt;
  }
}

// The codec's "compression" value: a codec name, for zip and zips optionally ":level" (1 to 9).
struct ExrCompression {
  Imf::Compression codec = Imf::ZIP_COMPRESSION;
  int zip_level = -1;  // -1: OpenEXR's default
};

std::optional<ExrCompression> parse_compression(std::string_view text) {
  std::string_view name = text;
  int level = -1;
  if (const auto colon = text.find(':'); colon != std::string_view::npos) {
    name = text.substr(0, colon);
    const std::string_view digits = text.substr(colon + 1);
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), level);
    if (ec != std::errc() || end != digits.data() + digits.size() || level < 1 || level > 9) return std::nullopt;
    if (name != "zip" && name != "zips") return std::nullopt;
  }
  static constexpr std::pair<std::string_view, Imf::Compression> kCodecs[] = {
      {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},  {"zips", Imf::ZIPS_COMPRESSION},
      {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION},  {"pxr24", Imf::PXR24_COMPRESSION},
      {"b44", Imf::B44_COMPRESSION}, {"b44a", Imf::B44A_COMPRESSION}};
  for (const auto& [codec_name, codec] : kCodecs)
    if (name == codec_name) return ExrCompression{codec, level};
  return std::nullopt;
}

// The header OpenImageIO writes for `spec`, or nothing when the spec holds what this writer does not map.
std::optional<Imf::Header> exr_header(const ImageWriteSpec& spec) {
  const auto type = exr_pixel_type(spec.type);
  if (!type || spec.width < 1 || spec.height < 1 || spec.channels < 1) return std::nullopt;
  if (static_cast<int>(spec.channel_names.size()) != spec.channels) return std::nullopt;
  std::set<std::string> names;
  for (const std::string& name : spec.channel_names)
    if (name.empty() || !names.insert(name).second) return std::nullopt;

  Imf::Header header(spec.width, spec.height);
  // OpenImageIO's default when the spec names none (the codec's writer is given one by every Orogen writer).
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const std::string& name : spec.channel_names) header.channels().insert(name, Imf::Channel(*type));
  for (const ImageAttribute& a : spec.attributes) {
    const std::string* text = std::get_if<std::string>(&a.value);
    if (a.name == "compression" && text) {
      const auto compression = parse_compression(*text);
      if (!compression) return std::nullopt;
      header.compression() = compression->codec;
      if (compression->zip_level > 0) header.zipCompressionLevel() = compression->zip_level;
    } else if (a.name == "Software" && text) {
      header.insert("Software", Imf::StringAttribute(*text));
    } else if (a.name == "DateTime" && text) {
      header.insert("capDate", Imf::StringAttribute(*text));
    } else if (a.name == "ImageDescription" && text) {
      header.insert("comments", Imf::StringAttribute(*text));
    } else if (a.name != "oiio:ColorSpace" && a.name != "oiio:UnassociatedAlpha") {
      return std::nullopt;  // an attribute whose EXR form this writer does not know: the codec writes it
    }
  }
  return header;
}

// OpenEXR's output into the host's checked sink. A failed write throws (OpenEXR's writers stop on it); the
// sink's file keeps the reason.
class SinkStream final : public Imf::OStream {
 public:
  SinkStream(const std::string& name, ImageByteSink& sink) : Imf::OStream(name.c_str()), sink_(sink) {}
  void write(const char c[], int n) override {
    if (n < 0 || !sink_.pwrite(c, static_cast<std::size_t>(n), static_cast<std::int64_t>(position_))) {
      failed_ = true;
      throw std::runtime_error("cannot write the file");
    }
    position_ += static_cast<std::uint64_t>(n);
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = position; }
  bool failed() const { return failed_; }

 private:
  ImageByteSink& sink_;
  std::uint64_t position_ = 0;
  bool failed_ = false;
};

// OpenImageIO runs OpenEXR's compression on as many threads as the machine has; so does this writer for
// compressed files (the bytes are the same whatever the count). Uncompressed rows are only copied: handing each
// to a thread cost a tiled build's 16 writes 7% of its CPU in wake-ups.
void use_every_core_once() {
  static std::once_flag once;
  std::call_once(
      once, [] { Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))); });
}

class ExrWriter final : public ImageWriter {
 public:
  ExrWriter(ImageByteSink& sink, const ImageWriteSpec& spec) : stream_("exr", sink), spec_(spec), order_(spec.height) {}

  bool open(const Imf::Header& header) {
    try {
      int threads = 0;
      if (header.compression() != Imf::NO_COMPRESSION) {
        use_every_core_once();
        threads = Imf::globalThreadCount();
      }
      file_.emplace(stream_, header, threads);
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }

  bool write_rows(int y0, int y1, const void* data, std::ptrdiff_t row_stride) override {
    if (error_ = order_.check(y0, y1); !error_.empty()) return false;
    const std::size_t sample = pixel_type_size(spec_.type);
    const std::size_t pixel = sample * static_cast<std::size_t>(spec_.channels);
    const std::size_t row_bytes = pixel * static_cast<std::size_t>(spec_.width);
    const auto* first = static_cast<const char*>(data);
    // OpenEXR's slices step forward by a size_t: rows given backwards (or with gaps) are packed first.
    if (row_stride != static_cast<std::ptrdiff_t>(row_bytes)) {
      packed_.resize(row_bytes * static_cast<std::size_t>(y1 - y0));
      for (int y = y0; y < y1; ++y)
        std::memcpy(packed_.data() + static_cast<std::size_t>(y - y0) * row_bytes, first + (y - y0) * row_stride,
                    row_bytes);
      first = packed_.data();
    }
    try {
      Imf::FrameBuffer frame;
      for (int c = 0; c < spec_.channels; ++c)
        frame.insert(spec_.channel_names[static_cast<std::size_t>(c)],
                     Imf::Slice::Make(*exr_pixel_type(spec_.type), first + static_cast<std::size_t>(c) * sample,
                                      Imath::V2i(0, y0), spec_.width, y1 - y0, pixel, row_bytes));
      file_->setFrameBuffer(frame);
      file_->writePixels(y1 - y0);
      order_.written(y1);
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }

  bool close() override {
    const bool open = !order_.closed();
    error_ = order_.close();  // "the file is closed" when it was
    if (!open) return false;
    // OpenEXR writes the table of chunk offsets when the file is destroyed, and swallows a failure there.
    file_.reset();
    if (stream_.failed()) error_ = "cannot write the table of chunk offsets";
    return error_.empty();
  }

  std::string error() override { return error_; }

 private:
  SinkStream stream_;
  ImageWriteSpec spec_;
  std::optional<Imf::OutputFile> file_;  // destroyed before stream_ (declared after)
  std::vector<char> packed_;
  RowOrder order_;
  std::string error_;
};

}  // namespace

std::unique_ptr<ImageWriter> create_native_exr_writer(ImageByteSink& sink, const ImageWriteSpec& spec,
                                                      std::string& error) {
  const auto header = exr_header(spec);
  if (!header) return nullptr;
  auto writer = std::make_unique<ExrWriter>(sink, spec);
  if (!writer->open(*header)) {
    error = writer->error();
    return nullptr;
  }
  return writer;
}

}  // namespace orogen
