// The image codec module (see nodes/io/image_codec.h): OpenImageIO behind the plain interface. Built as a
// MODULE linking only OpenImageIO, with hidden symbols but the entry point; it calls nothing of the host.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "nodes/io/image_codec.h"

namespace orogen {
namespace {

OIIO::TypeDesc to_oiio(PixelType t) {
  switch (t) {
    case PixelType::U8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::I8:
      return OIIO::TypeDesc::INT8;
    case PixelType::U16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::I16:
      return OIIO::TypeDesc::INT16;
    case PixelType::U32:
      return OIIO::TypeDesc::UINT32;
    case PixelType::I32:
      return OIIO::TypeDesc::INT32;
    case PixelType::Half:
      return OIIO::TypeDesc::HALF;
    case PixelType::F32:
      return OIIO::TypeDesc::FLOAT;
    case PixelType::F64:
      return OIIO::TypeDesc::DOUBLE;
    case PixelType::Other:
      break;
  }
  return OIIO::TypeDesc::UNKNOWN;
}

PixelType from_oiio(OIIO::TypeDesc t) {
  if (t.aggregate != OIIO::TypeDesc::SCALAR || t.arraylen != 0) return PixelType::Other;
  using B = OIIO::TypeDesc::BASETYPE;
  switch (t.basetype) {
    case B::UINT8:
      return PixelType::U8;
    case B::INT8:
      return PixelType::I8;
    case B::UINT16:
      return PixelType::U16;
    case B::INT16:
      return PixelType::I16;
    case B::UINT32:
      return PixelType::U32;
    case B::INT32:
      return PixelType::I32;
    case B::HALF:
      return PixelType::Half;
    case B::FLOAT:
      return PixelType::F32;
    case B::DOUBLE:
      return PixelType::F64;
    default:
      return PixelType::Other;
  }
}

// OpenImageIO's writers write through this proxy into the host's sink, so every byte is checked there (its own
// file proxy ignores short writes of the PNG plugin and close errors).
class SinkProxy final : public OIIO::Filesystem::IOProxy {
 public:
  SinkProxy(const std::string& filename, ImageByteSink& sink) : IOProxy(filename, Write), sink_(sink) {}
  const char* proxytype() const override { return "orogen-checked"; }
  void close() override {}
  bool seek(int64_t offset) override {
    if (offset < 0) return false;
    m_pos = offset;
    return true;
  }
  size_t write(const void* buf, size_t size) override {
    if (!sink_.pwrite(buf, size, m_pos)) return 0;
    m_pos += static_cast<int64_t>(size);
    return size;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    return sink_.pwrite(buf, size, offset) ? size : 0;
  }
  size_t read(void*, size_t) override { return 0; }
  size_t pread(void*, size_t, int64_t) override { return 0; }
  size_t size() const override { return static_cast<size_t>(sink_.size()); }

 private:
  ImageByteSink& sink_;
};

class OiioWriter final : public ImageWriter {
 public:
  OiioWriter(const std::string& filename, ImageByteSink& sink, std::unique_ptr<OIIO::ImageOutput> out,
             OIIO::TypeDesc type)
      : proxy_(filename, sink), out_(std::move(out)), type_(type) {}
  bool open(const OIIO::ImageSpec& spec) {
    out_->set_ioproxy(&proxy_);
    return out_->open(proxy_.filename(), spec);
  }
  bool write_rows(int y0, int y1, const void* data, std::ptrdiff_t row_stride) override {
    return out_->write_scanlines(y0, y1, 0, type_, data, OIIO::AutoStride, static_cast<OIIO::stride_t>(row_stride));
  }
  bool close() override { return out_->close(); }
  std::string error() override { return out_->geterror(); }

 private:
  SinkProxy proxy_;  // outlives out_'s use of it: out_ is destroyed first (declared after)
  std::unique_ptr<OIIO::ImageOutput> out_;
  OIIO::TypeDesc type_;
};

class OiioReader final : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {}
  bool open(const std::string& path) override {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // never premultiply a channel by alpha
    OIIO::ImageSpec opened;
    if (!in_->open(path, opened, config)) return false;
    describe();
    return true;
  }
  std::string format_name() const override { return in_->format_name(); }
  const ImageInfo& info() const override { return info_; }
  std::string string_attribute(const std::string& name) const override {
    return in_->spec().get_string_attribute(name);
  }
  bool read_native_scanlines(int y0, int y1, int c0, int c1, void* data) override {
    return in_->read_native_scanlines(0, 0, y0, y1, in_->spec().z, c0, c1, data);
  }
  bool read_native_tile(int x, int y, void* data) override {
    return in_->read_native_tile(0, 0, x, y, in_->spec().z, data);
  }
  bool read_image(int c0, int c1, PixelType type, void* data) override {
    return in_->read_image(0, 0, c0, c1, to_oiio(type), data);
  }
  std::string error() override { return in_->geterror(); }

  void describe() {
    const OIIO::ImageSpec& spec = in_->spec();
    info_.x = spec.x;
    info_.y = spec.y;
    info_.z = spec.z;
    info_.width = spec.width;
    info_.height = spec.height;
    info_.depth = spec.depth;
    info_.channels = spec.nchannels;
    info_.tile_width = spec.tile_width;
    info_.tile_height = spec.tile_height;
    info_.format = from_oiio(spec.format);
    info_.format_text = spec.format.c_str();
    for (int c = 0; c < spec.nchannels; ++c) {
      const OIIO::TypeDesc t = spec.channelformat(c);
      info_.channel_types.push_back(from_oiio(t));
      info_.channel_type_texts.push_back(t.c_str());
      info_.channel_sizes.push_back(t.size());
      info_.channel_names.push_back(spec.channel_name(c));
    }
    info_.native_pixel_bytes = spec.pixel_bytes(true);
    info_.native_tile_bytes = spec.tile_width > 0 ? static_cast<std::size_t>(spec.tile_bytes(true)) : 0;
  }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageInfo info_;
};

class OiioCodec final : public ImageCodec {
 public:
  std::unique_ptr<ImageWriter> create_writer(const std::string& filename, ImageByteSink& sink, const ImageWriteSpec& s,
                                             std::string& error) const override {
    auto out = OIIO::ImageOutput::create(filename);
    if (!out) {
      error = OIIO::geterror();
      return nullptr;
    }
    if (!out->supports("ioproxy")) {
      error = std::string("the ") + out->format_name() + " writer cannot write through a checked file";
      return nullptr;
    }
    const OIIO::TypeDesc type = to_oiio(s.type);
    OIIO::ImageSpec spec(s.width, s.height, s.channels, type);
    if (!s.channel_names.empty()) spec.channelnames = s.channel_names;
    spec.alpha_channel = s.alpha_channel;
    for (const ImageAttribute& a : s.attributes) {
      if (const int* i = std::get_if<int>(&a.value))
        spec.attribute(a.name, *i);
      else if (const float* f = std::get_if<float>(&a.value))
        spec.attribute(a.name, *f);
      else
        spec.attribute(a.name, std::get<std::string>(a.value));
    }
    auto writer = std::make_unique<OiioWriter>(filename, sink, std::move(out), type);
    if (!writer->open(spec)) {
      error = writer->error();
      return nullptr;
    }
    return writer;
  }

  std::unique_ptr<ImageReader> create_reader(const std::string& format) const override {
    auto in = OIIO::ImageInput::create(format, /*do_open=*/false);
    if (!in) {
      OIIO::geterror();  // clear the thread's error
      return nullptr;
    }
    return std::make_unique<OiioReader>(std::move(in));
  }

  std::unique_ptr<ImageReader> open_reader(const std::string& path, std::string& error) const override {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      error = OIIO::geterror();
      return nullptr;
    }
    auto reader = std::make_unique<OiioReader>(std::move(in));
    reader->describe();
    return reader;
  }
};

}  // namespace
}  // namespace orogen

extern "C" __attribute__((visibility("default"))) const orogen::ImageCodec* orogen_image_codec_v2() {
  static const orogen::OiioCodec codec;
  return &codec;
}
