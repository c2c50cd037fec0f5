#pragma once
// PNG and EXR heights read through libpng and OpenEXR directly, without the image codec module
// (nodes/io/image_codec.h): loading OpenImageIO and its ~250 libraries cost ~0.6 s of CPU, more than decoding a
// 4097^2 heightmap. These readers give what the codec's would (the same channels, native sample types, values
// and the attributes heights need) for the files Orogen and the tools it exchanges heightmaps with write;
// anything else is left to the codec.
#include <memory>
#include <string>

#include "nodes/io/image_codec.h"

namespace orogen {

// `path` opened by a reader that needs no codec, or nullptr when the file is not one it reads, or cannot be
// opened (the codec then reads it, and reports a damaged file in its own words). `extension` is lower case
// without the dot. Read:
// - png: 8 or 16 bits per sample, gray, gray + alpha, RGB or RGBA, not interlaced, without a tRNS chunk
//   (OpenImageIO would turn it into an alpha channel);
// - exr: one channel (half, float or uint) of the file's first part, scanline or tiled.
// The readers read whole images (read_image) and scanlines (read_native_scanlines) in their native type only,
// and never tiles (tile_width is 0 for every file).
std::unique_ptr<ImageReader> open_native_image_reader(const std::string& extension, const std::string& path);

// The two, for tests: nullptr when the file is not one the reader reads.
std::unique_ptr<ImageReader> open_native_png(const std::string& path);
std::unique_ptr<ImageReader> open_native_exr(const std::string& path);

}  // namespace orogen
