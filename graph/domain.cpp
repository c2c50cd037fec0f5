#include "graph/domain.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

std::string check_domain(const Domain& d) {
  std::ostringstream s;
  if (d.resolution.x < 1 || d.resolution.y < 1) {
    s << "the domain has " << d.resolution.x << "x" << d.resolution.y << " samples; it needs at least 1x1";
    return s.str();
  }
  for (int k = 0; k < 2; ++k) {
    const double sp = d.spacing[k];
    // A single sample along an axis has no neighbour: its spacing is nominal and only needs to be positive.
    const double min_spacing = d.resolution[k] == 1 ? std::numeric_limits<double>::min() : kMinSpacing;
    if (!std::isfinite(sp) || !(sp >= min_spacing)) {
      s << "the domain's sample spacing in " << (k == 0 ? "x" : "y") << " is " << sp << " m; it must be at least "
        << kMinSpacing << " m (make the world larger or the resolution smaller)";
      return s.str();
    }
  }
  const glm::dvec2 lo = d.min_corner(), hi = d.max_corner();
  for (double v : {lo.x, lo.y, hi.x, hi.y, d.origin.x, d.origin.y}) {
    if (!std::isfinite(v) || std::abs(v) > kMaxCoordinate) {
      s << "the domain reaches the coordinate " << v << " m; coordinates must be finite and within +/-"
        << kMaxCoordinate << " m";
      return s.str();
    }
  }
  return {};
}

Domain Domain::subdomain(int i0, int j0, int w, int h) const {
  Domain d = *this;
  d.first = first + glm::ivec2(i0, j0);
  d.resolution = {w, h};
  return d;
}

Domain Domain::resampled(glm::ivec2 new_resolution) const { return from_extent(min_corner(), size(), new_resolution); }

std::string Domain::describe() const {
  std::ostringstream s;
  const auto lo = min_corner();
  const auto sz = size();
  s << resolution.x << "x" << resolution.y << " samples over " << sz.x << " x " << sz.y << " m at (" << lo.x << ", "
    << lo.y << ")";
  return s.str();
}

}  // namespace orogen
