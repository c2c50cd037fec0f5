#pragma once
// An RGBA8 OpenGL texture owned by one object (moves, never copies), shown with ImGui::Image.
#include <cstdint>
#include <vector>

#include <imgui.h>

namespace orogen::editor {

class GlTexture {
 public:
  GlTexture() = default;
  ~GlTexture();
  GlTexture(GlTexture&& o) noexcept;
  GlTexture& operator=(GlTexture&& o) noexcept;
  GlTexture(const GlTexture&) = delete;
  GlTexture& operator=(const GlTexture&) = delete;

  // (Re)allocates as needed and uploads rows top first; linear filtering, clamped edges.
  void upload(int width, int height, const std::uint8_t* rgba);
  bool valid() const { return id_ != 0; }
  unsigned id() const { return id_; }
  int width() const { return width_; }
  int height() const { return height_; }
  ImTextureID imgui_id() const { return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(id_)); }

 private:
  unsigned id_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace orogen::editor
