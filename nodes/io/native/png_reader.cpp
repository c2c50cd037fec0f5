// PNG through libpng, rows in file order, as OpenImageIO's PNG reader presents them: channels gray[, alpha] or
// R, G, B[, A], 16-bit samples in host order, text chunks as attributes ("Description" is ImageDescription).
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "nodes/io/native/native_image_readers.h"
#include "nodes/io/native/png_errors.h"

namespace orogen {
namespace {

class PngReader final : public ImageReader {
 public:
  ~PngReader() override { close(); }

  bool open(const std::string& path) override {
    close();
    path_ = path;
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) {
      error_ = "cannot open the file";
      return false;
    }
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error_, png_errors::on_error, png_errors::on_warning);
    if (png_) info_ptr_ = png_create_info_struct(png_);
    if (!png_ || !info_ptr_) {
      error_ = "out of memory";
      return false;
    }
    return read_header() && supported();
  }

  std::string format_name() const override { return "png"; }
  const ImageInfo& info() const override { return info_; }
  std::string string_attribute(const std::string& name) const override {
    const auto it = text_.find(name == "ImageDescription" ? "Description" : name);
    return it == text_.end() ? std::string() : it->second;
  }

  bool read_native_scanlines(int y0, int y1, int c0, int c1, void* data) override {
    if (y0 < 0 || y1 > info_.height || y0 > y1 || c0 < 0 || c1 > info_.channels || c0 >= c1) {
      error_ = "rows or channels out of range";
      return false;
    }
    if (y0 < next_row_ && !restart()) return false;  // rows come in order: start over for earlier ones
    row_.resize(static_cast<std::size_t>(info_.width) * info_.native_pixel_bytes);
    while (next_row_ < y0)
      if (!read_row(row_.data())) return false;
    const std::size_t sample = info_.channel_sizes[0], pixel = info_.native_pixel_bytes;
    const std::size_t wanted = static_cast<std::size_t>(c1 - c0) * sample;
    auto* out = static_cast<unsigned char*>(data);
    for (int y = y0; y < y1; ++y) {
      if (!read_row(row_.data())) return false;
      if (c0 == 0 && c1 == info_.channels) {
        std::memcpy(out, row_.data(), row_.size());
        out += row_.size();
        continue;
      }
      for (int i = 0; i < info_.width; ++i, out += wanted)
        std::memcpy(out, row_.data() + static_cast<std::size_t>(i) * pixel + static_cast<std::size_t>(c0) * sample,
                    wanted);
    }
    return true;
  }

  bool read_native_tile(int, int, void*) override {
    error_ = "not a tiled image";
    return false;
  }

  bool read_image(int c0, int c1, PixelType type, void* data) override {
    if (type != info_.format) {
      error_ = "only the file's own sample type is read";
      return false;
    }
    return read_native_scanlines(0, info_.height, c0, c1, data);
  }

  std::string error() override { return error_; }

 private:
  void close() {
    if (png_) png_destroy_read_struct(&png_, info_ptr_ ? &info_ptr_ : nullptr, nullptr);
    png_ = nullptr;
    info_ptr_ = nullptr;
    if (file_) std::fclose(file_);
    file_ = nullptr;
    next_row_ = 0;
  }

  bool restart() {
    const std::string path = path_;
    const bool reopened = open(path);
    if (!reopened && error_.empty()) error_ = "cannot read the file again";
    return reopened;
  }

  // IHDR and the text chunks before the image data; sets the transformations that give OpenImageIO's samples.
  bool read_header() {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_init_io(png_, file_);
    png_read_info(png_, info_ptr_);
    width_ = png_get_image_width(png_, info_ptr_);
    height_ = png_get_image_height(png_, info_ptr_);
    bit_depth_ = png_get_bit_depth(png_, info_ptr_);
    color_type_ = png_get_color_type(png_, info_ptr_);
    interlaced_ = png_get_interlace_type(png_, info_ptr_) != PNG_INTERLACE_NONE;
    transparency_ = png_get_valid(png_, info_ptr_, PNG_INFO_tRNS) != 0;
    png_textp text = nullptr;
    int count = 0;
    png_get_text(png_, info_ptr_, &text, &count);
    for (int k = 0; k < count; ++k)
      if (text[k].key) text_[text[k].key] = text[k].text ? std::string(text[k].text, text[k].text_length) : "";
    if (bit_depth_ == 16) png_set_swap(png_);  // PNG stores big-endian; OpenImageIO gives host order
    png_read_update_info(png_, info_ptr_);
    return true;
  }

  bool supported() {
    int channels = 0;
    switch (color_type_) {
      case PNG_COLOR_TYPE_GRAY:
        channels = 1;
        break;
      case PNG_COLOR_TYPE_GRAY_ALPHA:
        channels = 2;
        break;
      case PNG_COLOR_TYPE_RGB:
        channels = 3;
        break;
      case PNG_COLOR_TYPE_RGB_ALPHA:
        channels = 4;
        break;
      default:
        return false;  // palette: left to the codec
    }
    if ((bit_depth_ != 8 && bit_depth_ != 16) || interlaced_ || transparency_) return false;
    if (width_ < 1 || height_ < 1 || width_ > 1u << 20 || height_ > 1u << 20) return false;
    const PixelType type = bit_depth_ == 16 ? PixelType::U16 : PixelType::U8;
    const std::size_t size = bit_depth_ / 8;
    if (png_get_rowbytes(png_, info_ptr_) != static_cast<std::size_t>(width_) * channels * size) return false;
    info_ = {};
    info_.width = static_cast<int>(width_);
    info_.height = static_cast<int>(height_);
    info_.channels = channels;
    info_.format = type;
    info_.format_text = bit_depth_ == 16 ? "uint16" : "uint8";
    info_.channel_types.assign(static_cast<std::size_t>(channels), type);
    info_.channel_type_texts.assign(static_cast<std::size_t>(channels), info_.format_text);
    info_.channel_sizes.assign(static_cast<std::size_t>(channels), size);
    info_.native_pixel_bytes = static_cast<std::size_t>(channels) * size;
    return true;
  }

  bool read_row(unsigned char* row) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_read_row(png_, row, nullptr);
    ++next_row_;
    return true;
  }

  std::string path_, error_;
  std::FILE* file_ = nullptr;
  png_structp png_ = nullptr;
  png_infop info_ptr_ = nullptr;
  png_uint_32 width_ = 0, height_ = 0;
  int bit_depth_ = 0, color_type_ = 0;
  bool interlaced_ = false, transparency_ = false;
  int next_row_ = 0;
  std::vector<unsigned char> row_;
  std::map<std::string, std::string> text_;
  ImageInfo info_;
};

}  // namespace

std::unique_ptr<ImageReader> open_native_png(const std::string& path) {
  auto reader = std::make_unique<PngReader>();
  if (!reader->open(path)) return nullptr;
  return reader;
}

}  // namespace orogen
