#include "nodes/io/image_file.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/file_timestamp.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "nodes/io/block_rows.h"
#include "nodes/io/compression.h"
#include "nodes/io/checked_image_output.h"

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
    case 1:
      return {"Y"};
    case 2:
      return {"Y", "A"};
    case 3:
      return {"R", "G", "B"};
    case 4:
      return {"R", "G", "B", "A"};
    default: {
      std::vector<std::string> names;
      for (int c = 0; c < n; ++c) names.push_back("channel" + std::to_string(c));
      return names;
    }
  }
}

// Index of the alpha channel of a PNG-able layout, or -1.
int alpha_channel(int channels) { return channels == 2 ? 1 : channels == 4 ? 3 : -1; }

// Writes in blocks of block_rows() scanlines, north row first: float files straight from the image (a negative
// row stride walks it north to south), integer files through a converted block.
template <class T>
void write_scanlines(const Image& image, const fs::path& path, const ImageWriteSpec& spec,
                     const WriteProgress& progress, bool encode_srgb) {
  CheckedImageSink sink(path);
  std::string error;
  auto out = create_checked_output(path, sink, spec, error);
  if (!out) throw FileError("cannot create '" + path.string() + "': " + error);
  const int n = image.channels;
  const int alpha = alpha_channel(n);
  const std::size_t row_samples = static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(n);
  std::vector<T> block;
  const int rows_per_block = block_rows(image.height());
  for (int r0 = 0; r0 < image.height(); r0 += rows_per_block) {
    const int r1 = std::min(r0 + rows_per_block, image.height());
    bool ok = false;
    if constexpr (std::is_same_v<T, float>) {
      ok = out->write_rows(r0, r1, image.pixel(0, image.height() - 1 - r0),
                           -static_cast<std::ptrdiff_t>(row_samples * sizeof(float)));
    } else {
      block.resize(static_cast<std::size_t>(r1 - r0) * row_samples);
      for (int r = r0; r < r1; ++r) {
        const float* src = image.pixel(0, image.height() - 1 - r);  // north row first
        T* line = block.data() + static_cast<std::size_t>(r - r0) * row_samples;
        for (std::size_t k = 0; k < row_samples; ++k) {
          const int c = static_cast<int>(k % static_cast<std::size_t>(n));
          const double v =
              encode_srgb && c != alpha ? linear_to_srgb(static_cast<double>(src[k])) : static_cast<double>(src[k]);
          line[k] = quantize<T>(v);
        }
      }
      ok = out->write_rows(r0, r1, block.data(), static_cast<std::ptrdiff_t>(row_samples * sizeof(T)));
    }
    if (!ok)
      throw FileError(sink.file().ok() ? "cannot write '" + path.string() + "': " + out->error() : sink.file().error());
    if (progress) progress(static_cast<double>(r1) / image.height());
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

}  // namespace

std::optional<ImageFormat> image_format_from_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return ImageFormat::Png8;
  if (ext == ".exr") return ImageFormat::Exr;
  if (ext == ".tif" || ext == ".tiff") return ImageFormat::Tiff;
  return std::nullopt;
}

ImageWriteSpec image_file_spec(int width, int height, int channels, const std::vector<std::string>& channel_names,
                               const ImageWriteOptions& options) {
  const bool png = options.format == ImageFormat::Png8 || options.format == ImageFormat::Png16;
  ImageWriteSpec spec;
  spec.width = width;
  spec.height = height;
  spec.channels = channels;
  spec.type = options.format == ImageFormat::Png8    ? PixelType::U8
              : options.format == ImageFormat::Png16 ? PixelType::U16
                                                     : PixelType::F32;
  spec.channel_names =
      static_cast<int>(channel_names.size()) == channels ? channel_names : default_channel_names(channels);
  spec.alpha_channel = png ? alpha_channel(channels) : -1;
  spec.set("Software", "Orogen");
  spec.set("DateTime", file_timestamp());  // never the time of writing: reproducible files
  spec.set("oiio:UnassociatedAlpha", 1);   // our alpha is straight: store it as is
  set_compression(spec,
                  png                                  ? "png"
                  : options.format == ImageFormat::Exr ? "openexr"
                                                       : "tiff",
                  options.compression_level);
  spec.set("oiio:ColorSpace", png && options.srgb ? "sRGB" : "Linear");
  return spec;
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
  const ImageWriteSpec spec = image_file_spec(image.width(), image.height(), n, image.channel_names, options);
  const bool srgb = png && options.srgb;
  switch (options.format) {
    case ImageFormat::Png8:
      return write_scanlines<std::uint8_t>(image, path, spec, options.progress, srgb);
    case ImageFormat::Png16:
      return write_scanlines<std::uint16_t>(image, path, spec, options.progress, srgb);
    case ImageFormat::Exr:
    case ImageFormat::Tiff:
      return write_scanlines<float>(image, path, spec, options.progress, false);
  }
}

}  // namespace orogen
