#pragma once
// Saves the current OpenGL framebuffer (the window's back buffer before the swap) as an 8-bit RGB PNG.
#include <filesystem>

namespace orogen::editor {

// Throws std::runtime_error if the file cannot be written.
void save_framebuffer_png(const std::filesystem::path& path, int width, int height);

}  // namespace orogen::editor
