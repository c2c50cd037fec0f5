#pragma once
// The zlib (deflate) level of the compressed image formats, set on an OpenImageIO spec.
#include <string>
#include <string_view>

#include <OpenImageIO/imageio.h>

namespace orogen {

// Levels run from 0 (stored, no compression) through 1 (fastest) to 9 (smallest); -1 keeps each library's
// default (zlib's 6 for PNG and TIFF, OpenEXR's own for EXR). Heightfields and colour maps gain a few per
// cent from the slow levels, at several times the time.
inline constexpr int kFastestCompression = 1;

// `format`: "openexr" (zip, or none at level 0), "tiff" (zip/deflate) or "png".
inline void set_compression(OIIO::ImageSpec& spec, std::string_view format, int level) {
  if (format == "png") {
    if (level >= 0) spec.attribute("png:compressionLevel", level);
    // At the fast levels, libpng's adaptive choice among the five row filters costs more than the deflate
    // itself; the "up" filter alone gives the same size on terrain (smooth from row to row).
    if (level >= 1 && level <= 3) spec.attribute("png:filter", 32 /* PNG_FILTER_UP */);
  } else if (format == "tiff") {
    spec.attribute("compression", level == 0 ? "none" : "zip");
    if (level > 0) spec.attribute("tiff:zipquality", level);
  } else {
    spec.attribute("compression", level == 0 ? std::string("none") : level > 0 ? "zip:" + std::to_string(level) : "zip");
  }
}

}  // namespace orogen
