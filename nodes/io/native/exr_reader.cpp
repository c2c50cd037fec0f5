// One-channel EXR through OpenEXR: the first part's data window as OpenImageIO presents it (x, y of its
// corner), the channel's half, float or uint samples as stored, string attributes ("comments" is
// ImageDescription). Tiled files are read through OpenEXR's scanline interface.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <bit>
#include <cstring>
#include <exception>
#include <memory>
#include <string>

#include "nodes/io/native/native_image_readers.h"

namespace orogen {
namespace {

class ExrReader final : public ImageReader {
 public:
  bool open(const std::string& path) override {
    try {
      file_ = std::make_unique<Imf::InputFile>(path.c_str());
      const Imf::Header& header = file_->header();
      const Imf::ChannelList& channels = header.channels();
      auto it = channels.begin();
      if (it == channels.end()) return false;
      auto second = it;
      if (++second != channels.end()) return false;  // one channel only
      name_ = it.name();
      const Imf::Channel& channel = it.channel();
      if (channel.xSampling != 1 || channel.ySampling != 1) return false;
      const Imath::Box2i window = header.dataWindow();
      info_ = {};
      info_.x = window.min.x;
      info_.y = window.min.y;
      info_.width = window.max.x - window.min.x + 1;
      info_.height = window.max.y - window.min.y + 1;
      if (info_.width < 1 || info_.height < 1) return false;
      info_.channels = 1;
      switch (channel.type) {
        case Imf::HALF:
          info_.format = PixelType::Half;
          info_.format_text = "half";
          break;
        case Imf::FLOAT:
          info_.format = PixelType::F32;
          info_.format_text = "float";
          break;
        case Imf::UINT:
          info_.format = PixelType::U32;
          info_.format_text = "uint";
          break;
        default:
          return false;
      }
      type_ = channel.type;
      // Uncompressed scanlines (Orogen's writer's default) hold each row as the channel's little-endian samples,
      // one row a chunk: on a little-endian machine they are copied as they are. OpenEXR's own path assembles
      // every sample from its bytes, a third of the CPU time of reading a 4096^2 height file.
      raw_rows_ = header.compression() == Imf::NO_COMPRESSION && !header.hasTileDescription() &&
                  std::endian::native == std::endian::little;
      info_.channel_types = {info_.format};
      info_.channel_type_texts = {info_.format_text};
      info_.channel_sizes = {pixel_type_size(info_.format)};
      info_.native_pixel_bytes = info_.channel_sizes[0];
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }

  std::string format_name() const override { return "openexr"; }
  const ImageInfo& info() const override { return info_; }
  std::string string_attribute(const std::string& name) const override {
    const auto* a = file_->header().findTypedAttribute<Imf::StringAttribute>(name == "ImageDescription" ? "comments"
                                                                                                        : name.c_str());
    return a ? a->value() : std::string();
  }

  bool read_native_scanlines(int y0, int y1, int c0, int c1, void* data) override {
    if (c0 != 0 || c1 != 1 || y0 < info_.y || y1 > info_.y + info_.height || y0 >= y1) {
      error_ = "rows or channels out of range";
      return false;
    }
    try {
      const std::size_t size = info_.native_pixel_bytes;
      if (raw_rows_ && read_raw_rows(y0, y1, static_cast<unsigned char*>(data))) return true;
      Imf::FrameBuffer frame;
      // The buffer holds rows [y0, y1) of the data window: its origin is the window's corner at row y0.
      frame.insert(name_, Imf::Slice::Make(type_, data, Imath::V2i(info_.x, y0), info_.width, y1 - y0, size,
                                           size * static_cast<std::size_t>(info_.width)));
      file_->setFrameBuffer(frame);
      file_->readPixels(y0, y1 - 1);
      return true;
    } catch (const std::exception& e) {
      error_ = e.what();
      return false;
    }
  }

  bool read_native_tile(int, int, void*) override {
    error_ = "tiles are read as scanlines";
    return false;
  }

  bool read_image(int c0, int c1, PixelType type, void* data) override {
    if (type != info_.format) {
      error_ = "only the file's own sample type is read";
      return false;
    }
    return read_native_scanlines(info_.y, info_.y + info_.height, c0, c1, data);
  }

  std::string error() override { return error_; }

 private:
  // Rows [y0, y1) of an uncompressed scanline file, chunk by chunk; false (nothing promised about `data`) when a
  // chunk is not exactly one row, so the caller reads through OpenEXR instead.
  bool read_raw_rows(int y0, int y1, unsigned char* data) {
    const std::size_t row = info_.native_pixel_bytes * static_cast<std::size_t>(info_.width);
    for (int y = y0; y < y1; ++y) {
      const char* bytes = nullptr;
      int count = 0;
      file_->rawPixelData(y, bytes, count);
      if (!bytes || count < 0 || static_cast<std::size_t>(count) != row) {
        raw_rows_ = false;
        return false;
      }
      std::memcpy(data + static_cast<std::size_t>(y - y0) * row, bytes, row);
    }
    return true;
  }

  std::unique_ptr<Imf::InputFile> file_;
  bool raw_rows_ = false;
  std::string name_, error_;
  Imf::PixelType type_ = Imf::FLOAT;
  ImageInfo info_;
};

}  // namespace

std::unique_ptr<ImageReader> open_native_exr(const std::string& path) {
  auto reader = std::make_unique<ExrReader>();
  if (!reader->open(path)) return nullptr;
  return reader;
}

}  // namespace orogen
