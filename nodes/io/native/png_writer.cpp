// PNG through libpng, the chunks as OpenImageIO's writer makes them (see native_image_writers.h): the same
// header, colour space chunks, offset, text chunks in the spec's order and zlib settings, so the same libpng writes
// the same bytes (tests/test_native_writers.cpp compares them with the codec's files).
#include <png.h>
#include <zlib.h>

#include <bit>
#include <csetjmp>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "nodes/io/native/native_image_writers.h"
#include "nodes/io/native/png_errors.h"
#include "nodes/io/native/row_order.h"

namespace orogen {
namespace {

// What the spec asks of libpng, or nothing when it holds what this writer does not map.
struct PngSettings {
  int bit_depth = 8, color_type = PNG_COLOR_TYPE_GRAY;
  enum class Space { None, Linear, Srgb } space = Space::None;
  std::optional<int> level, filter;
  std::vector<std::pair<std::string, std::string>> text;  // keyword, text
};

std::optional<PngSettings> png_settings(const ImageWriteSpec& spec) {
  if (spec.width < 1 || spec.height < 1 || spec.channels < 1 || spec.channels > 4) return std::nullopt;
  PngSettings s;
  if (spec.type == PixelType::U8)
    s.bit_depth = 8;
  else if (spec.type == PixelType::U16)
    s.bit_depth = 16;
  else
    return std::nullopt;
  static constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                        PNG_COLOR_TYPE_RGB_ALPHA};
  s.color_type = kColorTypes[spec.channels - 1];
  const int alpha = spec.channels == 2 ? 1 : spec.channels == 4 ? 3 : -1;
  if (spec.alpha_channel != alpha && spec.alpha_channel != -1) return std::nullopt;
  bool unassociated = false;
  for (const ImageAttribute& a : spec.attributes) {
    const std::string* text = std::get_if<std::string>(&a.value);
    const int* number = std::get_if<int>(&a.value);
    if (a.name == "png:compressionLevel" && number) {
      s.level = *number;
    } else if (a.name == "png:filter" && number) {
      s.filter = *number;
    } else if (a.name == "oiio:UnassociatedAlpha" && number) {
      unassociated = *number != 0;
    } else if (a.name == "oiio:ColorSpace" && text) {
      if (*text == "Linear")
        s.space = PngSettings::Space::Linear;
      else if (*text == "sRGB")
        s.space = PngSettings::Space::Srgb;
      else
        return std::nullopt;
      s.text.emplace_back(a.name, *text);
    } else if (a.name == "DateTime" && text && text->empty()) {
      // An empty time: no tIME chunk, no text.
    } else if (a.name == "ImageDescription" && text) {
      s.text.emplace_back("Description", *text);
    } else if ((a.name == "Software" || a.name.rfind("orogen:", 0) == 0) && text) {
      s.text.emplace_back(a.name, *text);
    } else {
      return std::nullopt;  // an attribute whose PNG form this writer does not know: the codec writes it
    }
  }
  // With alpha the codec would divide the colour by it unless told the alpha is straight.
  if (alpha >= 0 && spec.alpha_channel >= 0 && !unassociated) return std::nullopt;
  return s;
}

class PngWriter final : public ImageWriter {
 public:
  PngWriter(ImageByteSink& sink, const ImageWriteSpec& spec) : sink_(sink), spec_(spec), order_(spec.height) {}
  ~PngWriter() override {
    if (png_) png_destroy_write_struct(&png_, &info_);
  }

  bool open(const PngSettings& s) {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error_, png_errors::on_error, png_errors::on_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      error_ = "out of memory";
      return false;
    }
    text_ = s.text;  // kept alive until png_write_info has copied them
    std::vector<png_text> chunks(text_.size());
    for (std::size_t k = 0; k < text_.size(); ++k) {
      std::memset(&chunks[k], 0, sizeof(png_text));
      chunks[k].compression = PNG_TEXT_COMPRESSION_NONE;
      chunks[k].key = text_[k].first.data();
      chunks[k].text = text_[k].second.data();
      chunks[k].text_length = text_[k].second.size();
    }
    return start(s, chunks.data(), static_cast<int>(chunks.size()));
  }

  bool write_rows(int y0, int y1, const void* data, std::ptrdiff_t row_stride) override {
    if (error_ = order_.check(y0, y1); !error_.empty()) return false;
    if (!rows(y0, y1, static_cast<const unsigned char*>(data), row_stride)) return false;
    order_.written(y1);
    return true;
  }

  bool close() override {
    if (error_ = order_.close(); !error_.empty()) return false;
    return end();
  }

  std::string error() override { return error_; }

 private:
  bool start(const PngSettings& s, png_text* chunks, int count) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_set_write_fn(png_, this, on_write, on_flush);
    png_set_IHDR(png_, info_, static_cast<png_uint_32>(spec_.width), static_cast<png_uint_32>(spec_.height),
                 s.bit_depth, s.color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_oFFs(png_, info_, 0, 0, PNG_OFFSET_PIXEL);
    if (s.space == PngSettings::Space::Linear)
      png_set_gAMA(png_, info_, 1.0);
    else if (s.space == PngSettings::Space::Srgb)
      png_set_sRGB_gAMA_and_cHRM(png_, info_, PNG_sRGB_INTENT_ABSOLUTE);
    // OpenImageIO asks zlib for its default strategy; libpng's own default for filtered rows (Z_FILTERED) gives
    // other bytes.
    png_set_compression_strategy(png_, Z_DEFAULT_STRATEGY);
    if (s.level) png_set_compression_level(png_, *s.level);
    if (s.filter) png_set_filter(png_, 0, *s.filter);
    if (count > 0) png_set_text(png_, info_, chunks, count);
    png_write_info(png_, info_);
    if (s.bit_depth == 16 && std::endian::native == std::endian::little) png_set_swap(png_);
    return true;
  }

  bool rows(int y0, int y1, const unsigned char* first, std::ptrdiff_t row_stride) {
    if (setjmp(png_jmpbuf(png_))) return false;
    for (int y = y0; y < y1; ++y) png_write_row(png_, const_cast<png_bytep>(first + (y - y0) * row_stride));
    return true;
  }

  bool end() {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_write_end(png_, nullptr);
    return true;
  }

  static void on_write(png_structp png, png_bytep data, png_size_t size) {
    auto* self = static_cast<PngWriter*>(png_get_io_ptr(png));
    if (!self->sink_.pwrite(data, size, self->position_)) png_error(png, "cannot write the file");
    self->position_ += static_cast<std::int64_t>(size);
  }
  static void on_flush(png_structp) {}

  ImageByteSink& sink_;
  ImageWriteSpec spec_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  std::vector<std::pair<std::string, std::string>> text_;
  std::int64_t position_ = 0;
  RowOrder order_;
  std::string error_;
};

}  // namespace

std::unique_ptr<ImageWriter> create_native_png_writer(ImageByteSink& sink, const ImageWriteSpec& spec,
                                                      std::string& error) {
  const auto settings = png_settings(spec);
  if (!settings) return nullptr;
  auto writer = std::make_unique<PngWriter>(sink, spec);
  if (!writer->open(*settings)) {
    error = writer->error();
    return nullptr;
  }
  return writer;
}

}  // namespace orogen
