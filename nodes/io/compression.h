#pragma once
// The zlib (deflate) level of the compressed image formats, set on an image file's spec.
#include <string>
#include <string_view>

#include "nodes/io/image_codec.h"

namespace orogen {

// Levels run from 0 (stored, no compression) through 1 (fastest) to 9 (smallest); -1 keeps each library's
// default (zlib's 6 for PNG and TIFF, OpenEXR's own for EXR). Heightfields gain about 1% from the slow
// levels at about three times the time (WriteHeightfield defaults to 1); 8-bit color maps gain more
// (WriteImage defaults to 6). Measured by bench/bench_writers.cpp.

// `format`: "openexr", "tiff" (zip/deflate) or "png". For OpenEXR, `exr_codec` names the codec ("zip",
// "none", "piz", "pxr24", ...); the level applies to zip, and level 0 stores whatever the codec.
inline void set_compression(ImageWriteSpec& spec, std::string_view format, int level,
                            std::string_view exr_codec = "zip") {
  if (format == "png") {
    if (level >= 0) spec.set("png:compressionLevel", level);
    // 16-bit heights at the fast levels: libpng's adaptive choice among the five row filters costs more than
    // the deflate itself, and the "up" filter alone gives the same size (terrain is smooth from row to row).
    // 8-bit color keeps the adaptive choice (the "up" filter alone made a color map 40% larger).
    if (level >= 1 && level <= 3 && spec.type == PixelType::U16) spec.set("png:filter", 32 /* PNG_FILTER_UP */);
  } else if (format == "tiff") {
    spec.set("compression", level == 0 ? "none" : "zip");
    if (level > 0) spec.set("tiff:zipquality", level);
  } else if (level == 0 || exr_codec != "zip") {
    spec.set("compression", level == 0 ? std::string("none") : std::string(exr_codec));
  } else {
    spec.set("compression", level > 0 ? "zip:" + std::to_string(level) : std::string("zip"));
  }
}

}  // namespace orogen
