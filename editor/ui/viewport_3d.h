#pragma once
// The 3D viewport: the previewed heightfield as a lit mesh (terrain colours or a draped image, or the colour
// map of its kind), points as markers, curves as ribbons of their width on the terrain, water depth as a
// flat translucent water surface on its terrain, mesh outputs in place, and a scene writer's scene (its
// terrain mesh, or the ground its points were placed on, with every class mesh drawn at its points by GPU
// instancing: one glDrawElementsInstanced per class); rendered into an offscreen framebuffer shown as an ImGui image.
// Orbit with the left mouse button, pan with the right or middle one, zoom with the wheel, F to frame.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

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
  // Camera direction (degrees) for the next framing, then `zoom_notches` of wheel zoom (screenshots).
  void set_view(double yaw_deg, double pitch_deg, double zoom_notches);

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
  // A class mesh and the model matrices of its instances (per-instance attributes, drawn in one call).
  struct Instanced {
    Buffers mesh;
    unsigned instance_vbo = 0;
    int instances = 0;
  };
  static void upload_instances(Instanced& b, const std::vector<glm::mat4>& transforms);
  static void release(Instanced& b);

  OrbitCamera camera_;
  bool framed_ = false;
  double pending_zoom_ = 0.0;  // applied after the next framing
  float vertical_scale_ = 1.0f;
  bool wireframe_ = false;
  std::string geometry_key_;
  PortValue shown_value_;  // held so their addresses in the key stay theirs
  HeightfieldPtr shown_field_;
  ImagePtr shown_drape_;
  glm::dvec3 bounds_min_{0.0}, bounds_max_{1.0};

  std::optional<ScenePreview> shown_scene_;  // held, as shown_value_
  std::vector<Instanced> instanced_;         // per class
  std::string scene_info_;                   // "1234 instances of 3 classes"

  unsigned program_ = 0, points_program_ = 0, instanced_program_ = 0;
  unsigned fbo_ = 0, color_ = 0, depth_ = 0;
  int target_w_ = 0, target_h_ = 0;
  Buffers terrain_, markers_, mesh_, ribbons_, water_;
  float marker_size_ = 6.0f;
};

}  // namespace orogen::editor
