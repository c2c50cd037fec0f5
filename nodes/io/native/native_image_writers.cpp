#include "nodes/io/native/native_image_writers.h"

namespace orogen {

std::unique_ptr<ImageWriter> create_native_image_writer(const std::string& extension, ImageByteSink& sink,
                                                        const ImageWriteSpec& spec, std::string& error) {
  error.clear();
  if (extension == "exr") return create_native_exr_writer(sink, spec, error);
  if (extension == "png") return create_native_png_writer(sink, spec, error);
  return nullptr;
}

}  // namespace orogen
