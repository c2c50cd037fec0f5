#include "graph/domain.h"

#include <algorithm>
#include <sstream>

namespace orogen {

Domain Domain::from_extent(glm::dvec2 origin, glm::dvec2 size, glm::ivec2 resolution) {
  Domain d;
  d.origin = origin;
  d.resolution = resolution;
  d.spacing = {resolution.x > 1 ? size.x / (resolution.x - 1) : std::max(size.x, 1e-9),
               resolution.y > 1 ? size.y / (resolution.y - 1) : std::max(size.y, 1e-9)};
  return d;
}

Domain Domain::subdomain(int i0, int j0, int w, int h) const {
  Domain d = *this;
  d.first = first + glm::ivec2(i0, j0);
  d.resolution = {w, h};
  return d;
}

Domain Domain::resampled(glm::ivec2 new_resolution) const {
  return from_extent(min_corner(), size(), new_resolution);
}

std::string Domain::describe() const {
  std::ostringstream s;
  const auto lo = min_corner();
  const auto sz = size();
  s << resolution.x << "x" << resolution.y << " samples over " << sz.x << " x " << sz.y << " m at (" << lo.x
    << ", " << lo.y << ")";
  return s.str();
}

}  // namespace orogen
