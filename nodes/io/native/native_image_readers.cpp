#include "nodes/io/native/native_image_readers.h"

namespace orogen {

std::unique_ptr<ImageReader> open_native_image_reader(const std::string& extension, const std::string& path) {
  if (extension == "png") return open_native_png(path);
  if (extension == "exr") return open_native_exr(path);
  return nullptr;
}

}  // namespace orogen
