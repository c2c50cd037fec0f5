#include "editor/ui/screenshot.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "editor/ui/gl.h"
#include "graph/atomic_file.h"

namespace orogen::editor {

void save_framebuffer_png(const std::filesystem::path& path, int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // OpenGL's rows start at the bottom; image files start at the top.
  const auto row = static_cast<std::ptrdiff_t>(width) * 3;
  write_file_atomically(path, [&](const std::filesystem::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    if (!out->open(tmp.string(), spec))
      throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
    const bool ok = out->write_image(OIIO::TypeDesc::UINT8, pixels.data() + (height - 1) * row, OIIO::AutoStride, -row);
    out->close();
    if (!ok) throw std::runtime_error("cannot write " + path.string() + ": " + out->geterror());
  });
}

}  // namespace orogen::editor
