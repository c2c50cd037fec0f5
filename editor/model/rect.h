#pragma once
// An axis-aligned rectangle in canvas world units or screen pixels.
#include <algorithm>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

namespace orogen::editor {

struct Rect {
  glm::dvec2 min{0.0}, max{0.0};

  static Rect spanning(glm::dvec2 a, glm::dvec2 b) { return {glm::min(a, b), glm::max(a, b)}; }
  glm::dvec2 size() const { return max - min; }
  glm::dvec2 center() const { return (min + max) * 0.5; }
  bool contains(glm::dvec2 p) const { return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y; }
  bool overlaps(const Rect& o) const {
    return min.x <= o.max.x && o.min.x <= max.x && min.y <= o.max.y && o.min.y <= max.y;
  }
  Rect united(const Rect& o) const { return {glm::min(min, o.min), glm::max(max, o.max)}; }
  Rect expanded(double d) const { return {min - d, max + d}; }
  bool operator==(const Rect&) const = default;
};

}  // namespace orogen::editor
