#include "editor/model/canvas_view.h"

#include <algorithm>

namespace orogen::editor {

void CanvasView::set(glm::dvec2 scroll, double zoom) {
  scroll_ = scroll;
  zoom_ = std::clamp(zoom, kMinZoom, kMaxZoom);
}

void CanvasView::pan(glm::dvec2 screen_delta) { scroll_ -= screen_delta / zoom_; }

void CanvasView::zoom_at(glm::dvec2 screen_point, double factor) {
  const glm::dvec2 anchor = to_world(screen_point);
  zoom_ = std::clamp(zoom_ * factor, kMinZoom, kMaxZoom);
  scroll_ = anchor - (screen_point - origin_) / zoom_;
}

void CanvasView::frame(const Rect& world, double margin) {
  const glm::dvec2 avail = glm::max(size_ - 2.0 * margin, glm::dvec2(1.0));
  const glm::dvec2 extent = glm::max(world.size(), glm::dvec2(1.0));
  zoom_ = std::clamp(std::min(avail.x / extent.x, avail.y / extent.y), kMinZoom, 1.5);
  scroll_ = world.center() - size_ * 0.5 / zoom_;
}

}  // namespace orogen::editor
