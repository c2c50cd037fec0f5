#pragma once
// The node canvas's view transform: which part of the (infinite) canvas is shown and how large.
//   screen = origin + (world - scroll) * zoom
// Zooming keeps the point under the cursor fixed, as in every node editor.
#include <glm/vec2.hpp>

#include "editor/model/rect.h"

namespace orogen::editor {

class CanvasView {
 public:
  static constexpr double kMinZoom = 0.1;
  static constexpr double kMaxZoom = 3.0;
  // The least zoom at which node titles can be read (the canvas's 14 px text at 10.5 px).
  static constexpr double kReadableZoom = 0.75;

  // The canvas area on screen (pixels).
  void set_viewport(glm::dvec2 origin, glm::dvec2 size) {
    origin_ = origin;
    size_ = size;
  }
  glm::dvec2 origin() const { return origin_; }
  glm::dvec2 size() const { return size_; }
  Rect viewport() const { return {origin_, origin_ + size_}; }

  double zoom() const { return zoom_; }
  glm::dvec2 scroll() const { return scroll_; }
  void set(glm::dvec2 scroll, double zoom);

  glm::dvec2 to_screen(glm::dvec2 world) const { return origin_ + (world - scroll_) * zoom_; }
  glm::dvec2 to_world(glm::dvec2 screen) const { return scroll_ + (screen - origin_) / zoom_; }
  Rect to_screen(const Rect& world) const { return {to_screen(world.min), to_screen(world.max)}; }
  Rect to_world(const Rect& screen) const { return {to_world(screen.min), to_world(screen.max)}; }
  // The world rectangle currently visible.
  Rect visible() const { return to_world(viewport()); }

  // Moves the view by a mouse drag of `screen_delta` pixels (the canvas follows the mouse).
  void pan(glm::dvec2 screen_delta);
  // Multiplies the zoom by `factor` (clamped) keeping the world point under `screen_point` in place.
  void zoom_at(glm::dvec2 screen_point, double factor);
  // Fits `world` into the viewport with `margin` pixels around it, zoom clamped to [kMinZoom, 1.5].
  void frame(const Rect& world, double margin = 40.0);
  // The opening view of a graph: as frame(), but never below `min_zoom`, so that what is shown can be read. A
  // graph larger than the viewport at that zoom is shown from its top-left corner (where the flow starts),
  // centered along an axis where it fits; the rest is a pan or Home (frame everything) away.
  void frame_readable(const Rect& world, double min_zoom = kReadableZoom, double margin = 40.0);

 private:
  glm::dvec2 origin_{0.0}, size_{800.0, 600.0};
  glm::dvec2 scroll_{0.0};
  double zoom_ = 1.0;
};

}  // namespace orogen::editor
