#include "evaluator/domain_crop.h"

#include <algorithm>

#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/points.h"

namespace orogen {

bool domain_contains(const Domain& outer, const Domain& inner) {
  if (outer.origin != inner.origin || outer.spacing != inner.spacing) return false;
  const glm::ivec2 lo = inner.first - outer.first;
  return lo.x >= 0 && lo.y >= 0 && lo.x + inner.resolution.x <= outer.resolution.x &&
         lo.y + inner.resolution.y <= outer.resolution.y;
}

PortValue crop_to_domain(const PortValue& value, const Domain& target) {
  if (const auto* h = std::get_if<HeightfieldPtr>(&value); h && *h) {
    const Heightfield& src = **h;
    if (src.domain == target || !domain_contains(src.domain, target)) return value;
    const glm::ivec2 lo = target.first - src.domain.first;
    auto out = std::make_shared<Heightfield>(target);
    for (int j = 0; j < target.height(); ++j) {
      const auto row = src.row(lo.y + j);
      std::copy_n(row.begin() + lo.x, target.width(), out->row(j).begin());
    }
    return HeightfieldPtr(std::move(out));
  }
  if (const auto* im = std::get_if<ImagePtr>(&value); im && *im) {
    const Image& src = **im;
    if (src.domain == target || !domain_contains(src.domain, target)) return value;
    const glm::ivec2 lo = target.first - src.domain.first;
    auto out = std::make_shared<Image>(target, src.channels);
    out->channel_names = src.channel_names;
    out->color = src.color;
    const auto row_floats = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(src.channels);
    for (int j = 0; j < target.height(); ++j) std::copy_n(src.pixel(lo.x, lo.y + j), row_floats, out->pixel(0, j));
    return ImagePtr(std::move(out));
  }
  return value;
}

PortValue crop_points_to_domain(const PortValue& value, const Domain& source, const Domain& target) {
  const auto* p = std::get_if<PointsPtr>(&value);
  if (!p || !*p || source == target || !domain_contains(source, target)) return value;
  const Points& src = **p;
  const glm::dvec2 lo = target.min_corner(), hi = target.max_corner();
  const auto inside = [&](std::size_t k) {
    const glm::dvec2 at(src.position[k].x, src.position[k].y);
    return at.x >= lo.x && at.x <= hi.x && at.y >= lo.y && at.y <= hi.y;
  };
  std::size_t kept = 0;
  for (std::size_t k = 0; k < src.size(); ++k) kept += inside(k);
  if (kept == src.size()) return value;
  return PointsPtr(std::make_shared<Points>(src.subset(inside)));
}

PortValue crop_input(const PortValue& value, const Domain& source, const Domain& target) {
  return std::holds_alternative<PointsPtr>(value) ? crop_points_to_domain(value, source, target)
                                                  : crop_to_domain(value, target);
}

}  // namespace orogen
