#pragma once
// EXR and PNG files written through OpenEXR and libpng directly, without the image codec module
// (nodes/io/image_codec.h): loading OpenImageIO and its ~250 libraries costs ~0.6 s of CPU and ~130 MB of resident
// memory (relocated pages and the libraries' own start-up), more than a tiled build's whole working set. The
// writers give the same file the codec writes, byte for byte, for the specs Orogen's writers make; anything else is
// left to the codec.
#include <memory>
#include <string>

#include "nodes/io/image_codec.h"

namespace orogen {

// A writer of `spec` into `sink` that needs no codec, or nullptr (with `error` empty) when the extension or the
// spec is not one it writes exactly as the codec would; nullptr with `error` set when it is one but the file
// cannot be started (a full disk: the host's sink says why). `extension` is lower case without the dot. Writes:
// - exr: scanline files of half, float or uint samples, any number of uniquely named channels, compressed
//   none, rle, zips, zip (with a zlib level, "zip:N"), piz, pxr24, b44 or b44a; the attributes Software,
//   DateTime (the EXR's capDate), ImageDescription (its comments) and the codec's own oiio:ColorSpace and
//   oiio:UnassociatedAlpha, which OpenImageIO does not store in EXR files either;
// - png: 8 or 16 bits, gray, gray + alpha, RGB or RGBA (straight alpha: oiio:UnassociatedAlpha set); the
//   attributes png:compressionLevel, png:filter, oiio:ColorSpace (Linear: a gAMA of 1; sRGB: the sRGB, gAMA and
//   cHRM chunks; a text chunk either way), Software, ImageDescription (the Description text) and orogen:* texts,
//   and an empty DateTime.
std::unique_ptr<ImageWriter> create_native_image_writer(const std::string& extension, ImageByteSink& sink,
                                                        const ImageWriteSpec& spec, std::string& error);

// The two, for tests: nullptr (error empty) when the spec is not one the writer writes as the codec does.
std::unique_ptr<ImageWriter> create_native_exr_writer(ImageByteSink& sink, const ImageWriteSpec& spec,
                                                      std::string& error);
std::unique_ptr<ImageWriter> create_native_png_writer(ImageByteSink& sink, const ImageWriteSpec& spec,
                                                      std::string& error);

}  // namespace orogen
