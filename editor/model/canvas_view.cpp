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

void CanvasView::frame_readable(const Rect& world, double min_zoom, double margin) {
  frame(world, margin);
  if (zoom_ >= min_zoom) return;
  zoom_ = std::clamp(min_zoom, kMinZoom, kMaxZoom);
  const glm::dvec2 shown = size_ / zoom_;  // world units across the viewport
  const glm::dvec2 pad = glm::dvec2(margin) / zoom_;
  for (int axis = 0; axis < 2; ++axis)
    scroll_[axis] = world.size()[axis] + 2.0 * pad[axis] <= shown[axis] ? world.center()[axis] - shown[axis] * 0.5
                                                                        : world.min[axis] - pad[axis];
}

}  // namespace orogen::editor
