#include "nodes/rocks/rock_set.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace orogen::rocks {

void append_rock_set(TriMesh& mesh, Points& placements, const RockSetParams& p, const ExecContext* ctx) {
  double x = 0.0;
  for (int k = 0; k < p.count; ++k) {
    if (ctx) {
      ctx->check_cancelled();
      ctx->progress(static_cast<double>(k) / p.count);
    }
    HullRockOptions o = p.rock;
    o.variant = static_cast<std::uint64_t>(k);
    for (int a = 0; a < 3; ++a)
      o.radii[a] *= 1.0 + p.variation * (2.0 * variant_uniform(p.rock.seed, o.variant, a) - 1.0);
    const double half = std::max({o.radii.x, o.radii.y, o.radii.z}) + 3.0 * o.sigma + o.displacement;
    if (k > 0) x += half;
    const glm::dvec3 center(x, 0.0, 0.0);
    try {
      append_hull_rock(mesh, o, center, glm::dquat(1, 0, 0, 0), p.color, ctx);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("rock " + std::to_string(k) + ": " + e.what());
    }
    const auto i = placements.add(glm::vec3(center), k);
    placements.scale[i] = glm::vec3(o.radii);
    x += half + p.spacing;
  }
}

}  // namespace orogen::rocks
