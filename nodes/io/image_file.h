#pragma once
// Images (N float channels, linear) to PNG 8/16-bit, EXR and TIFF through OpenImageIO.
// Rows are stored north (largest y) first, like heightfields (see heightfield_file.h).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "graph/image.h"
#include "nodes/common/color_space.h"  // linear_to_srgb for PNG encoding
#include "nodes/io/file_error.h"

namespace orogen {

struct ImageWriteSpec;  // nodes/io/image_codec.h

enum class ImageFormat { Png8, Png16, Exr, Tiff };

struct ImageWriteOptions {
  ImageFormat format = ImageFormat::Png8;
  // PNG only: encode colour channels with the sRGB transfer curve (alpha stays linear). EXR and TIFF store
  // the linear floats as they are.
  bool srgb = true;
  int compression_level = -1;  // see HeightfieldWriteOptions::compression_level
  WriteProgress progress;      // optional
};

// The image header write_image_file gives an image of `width` x `height` samples of `channels` channels named
// `channel_names` (default names when their count differs): also what a merge of a tiled build's files writes
// (cli/merge_tiles.h), so that the merged file equals the untiled build's.
ImageWriteSpec image_file_spec(int width, int height, int channels, const std::vector<std::string>& channel_names,
                               const ImageWriteOptions& options);

// Writes `image` to `path`. PNG takes 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA) channels; values are
// clamped to 0..1 and rounded to the nearest code (NaN stores 0). Alpha, when present, is straight (not
// premultiplied). EXR and TIFF store any channel count as float32, with the image's channel names if it has
// them. Not atomic by itself (writer nodes use write_file_atomically). Throws FileError on failure.
void write_image_file(const Image& image, const std::filesystem::path& path, const ImageWriteOptions& options);

// The format designated by a file name's extension (.png -> Png8, .exr, .tif/.tiff), or nullopt.
std::optional<ImageFormat> image_format_from_path(const std::filesystem::path& path);

}  // namespace orogen
