#pragma once
// The 3D viewport: the previewed heightfield as a lit mesh (terrain colours or a draped image, or the colour
// map of its kind), points as markers, curves as ribbons of their width on the terrain, water depth as a
// flat translucent water surface on its terrain, mesh outputs in place; rendered into an offscreen framebuffer shown as an ImGui image. Orbit
// with the left mouse button, pan with the right or middle one, zoom with the wheel, F to frame.
#include <cstdint>
#include <string>

#include "editor/model/orbit_camera.h"
#include "editor/ui/preview_panel.h"

namespace orogen::editor {

class Viewport3D {
 public:
  Viewport3D() = default;
  ~Viewport3D();
  Viewport3D(const Viewport3D&) = delete;
  Viewport3D& operator=(const Viewport3D&) = delete;

  void draw(const PreviewContent& content);

 private:
  struct Buffers {
    unsigned vao = 0, vbo = 0, ebo = 0;
    int count = 0;  // indices (triangles) or vertices (points)
  };
  void ensure_gl();
  void resize_target(int width, int height);
  void update_geometry(const PreviewContent& content);
  void render(int width, int height);
  static void upload(Buffers& b, const std::vector<float>& vertices, const std::vector<std::uint32_t>& indices);
  static void release(Buffers& b);

  OrbitCamera camera_;
  bool framed_ = false;
  float vertical_scale_ = 1.0f;
  bool wireframe_ = false;
  std::string geometry_key_;
  PortValue shown_value_;  // held so their addresses in the key stay theirs
  HeightfieldPtr shown_field_;
  ImagePtr shown_drape_;
  glm::dvec3 bounds_min_{0.0}, bounds_max_{1.0};

  unsigned program_ = 0, points_program_ = 0;
  unsigned fbo_ = 0, color_ = 0, depth_ = 0;
  int target_w_ = 0, target_h_ = 0;
  Buffers terrain_, markers_, mesh_, ribbons_, water_;
  float marker_size_ = 6.0f;
};

}  // namespace orogen::editor
