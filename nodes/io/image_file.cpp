#include "nodes/io/image_file.h"
#include "nodes/io/file_timestamp.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

namespace orogen {
namespace {

namespace fs = std::filesystem;

// Clamped, rounded integer code of a 0..1 value; NaN becomes 0.
template <class T>
T quantize(double v) {
  constexpr double full = static_cast<double>(std::numeric_limits<T>::max());
  if (!(v > 0.0)) return 0;  // also NaN
  if (v >= 1.0) return std::numeric_limits<T>::max();
  return static_cast<T>(std::lround(v * full));
}

std::vector<std::string> default_channel_names(int n) {
  switch (n) {
    case 1: return {"Y"};
    case 2: return {"Y", "A"};
    case 3: return {"R", "G", "B"};
    case 4: return {"R", "G", "B", "A"};
    default: {
      std::vector<std::string> names;
      for (int c = 0; c < n; ++c) names.push_back("channel" + std::to_string(c));
      return names;
    }
  }
}

// Index of the alpha channel of a PNG-able layout, or -1.
int alpha_channel(int channels) { return channels == 2 ? 1 : channels == 4 ? 3 : -1; }

template <class T>
void write_scanlines(const Image& image, const fs::path& path, const OIIO::ImageSpec& spec,
                     const WriteProgress& progress, bool encode_srgb) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw FileError("cannot write '" + path.string() + "': " + OIIO::geterror());
  if (!out->open(path.string(), spec)) throw FileError("cannot create '" + path.string() + "': " + out->geterror());
  const int n = image.channels;
  const int alpha = alpha_channel(n);
  std::vector<T> line(static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(n));
  for (int r = 0; r < image.height(); ++r) {
    const float* src = image.pixel(0, image.height() - 1 - r);  // north row first
    for (std::size_t k = 0; k < line.size(); ++k) {
      if constexpr (std::is_same_v<T, float>) {
        line[k] = src[k];
      } else {
        const int c = static_cast<int>(k % static_cast<std::size_t>(n));
        const double v = encode_srgb && c != alpha ? linear_to_srgb(src[k]) : static_cast<double>(src[k]);
        line[k] = quantize<T>(v);
      }
    }
    if (!out->write_scanline(r, 0, spec.format, line.data()))
      throw FileError("cannot write '" + path.string() + "': " + out->geterror());
    if (progress) progress(static_cast<double>(r + 1) / image.height());
  }
  if (!out->close()) throw FileError("cannot finish '" + path.string() + "': " + out->geterror());
}

}  // namespace

double linear_to_srgb(double v) {
  if (!(v > 0.0)) return 0.0;
  if (v >= 1.0) return 1.0;
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgb_to_linear(double v) {
  if (!(v > 0.0)) return 0.0;
  if (v >= 1.0) return 1.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

std::optional<ImageFormat> image_format_from_path(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return ImageFormat::Png8;
  if (ext == ".exr") return ImageFormat::Exr;
  if (ext == ".tif" || ext == ".tiff") return ImageFormat::Tiff;
  return std::nullopt;
}

void write_image_file(const Image& image, const fs::path& path, const ImageWriteOptions& options) {
  const int n = image.channels;
  if (n < 1 || image.width() < 1 || image.height() < 1 ||
      image.data.size() != image.domain.sample_count() * static_cast<std::size_t>(n))
    throw FileError("cannot write '" + path.string() + "': the image is empty or inconsistent");
  const bool png = options.format == ImageFormat::Png8 || options.format == ImageFormat::Png16;
  if (png && n > 4)
    throw FileError("cannot write '" + path.string() + "': PNG holds 1 to 4 channels, the image has " +
                    std::to_string(n) + " (use EXR or TIFF)");
  const OIIO::TypeDesc type = options.format == ImageFormat::Png8    ? OIIO::TypeDesc::UINT8
                              : options.format == ImageFormat::Png16 ? OIIO::TypeDesc::UINT16
                                                                     : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(image.width(), image.height(), n, type);
  spec.channelnames = static_cast<int>(image.channel_names.size()) == n ? image.channel_names : default_channel_names(n);
  spec.alpha_channel = png ? alpha_channel(n) : -1;
  spec.attribute("Software", "Orogen");
  spec.attribute("DateTime", file_timestamp());  // never the time of writing: reproducible files
  spec.attribute("oiio:UnassociatedAlpha", 1);  // our alpha is straight: store it as is
  if (png) {
    spec.attribute("oiio:ColorSpace", options.srgb ? "sRGB" : "Linear");
  } else {
    spec.attribute("compression", "zip");
    spec.attribute("oiio:ColorSpace", "Linear");
  }
  const bool srgb = png && options.srgb;
  switch (options.format) {
    case ImageFormat::Png8: return write_scanlines<std::uint8_t>(image, path, spec, options.progress, srgb);
    case ImageFormat::Png16: return write_scanlines<std::uint16_t>(image, path, spec, options.progress, srgb);
    case ImageFormat::Exr:
    case ImageFormat::Tiff: return write_scanlines<float>(image, path, spec, options.progress, false);
  }
}

}  // namespace orogen
