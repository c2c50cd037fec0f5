#include "nodes/scatter/project_to_terrain.h"

#include <cmath>

#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

namespace orogen {

Points project_to_terrain(const Points& in, const Heightfield& h, const ProjectParams& p, const ExecContext* ctx) {
  Points out = in;
  const auto sp = h.domain.spacing;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (ctx && i % 65536 == 0) ctx->check_cancelled();
    auto& q = out.position[i];
    const double z = h.sample_world(q.x, q.y);
    q.z = std::isfinite(z) ? static_cast<float>(z + p.offset) : q.z;
    if (p.align > 0.0) {
      const double gx = (h.sample_world(q.x + sp.x, q.y) - h.sample_world(q.x - sp.x, q.y)) / (2.0 * sp.x);
      const double gy = (h.sample_world(q.x, q.y + sp.y) - h.sample_world(q.x, q.y - sp.y)) / (2.0 * sp.y);
      glm::dvec3 n(-gx, -gy, 1.0);
      if (!std::isfinite(n.x) || !std::isfinite(n.y)) continue;
      n = glm::normalize(n);
      const glm::dquat tilt = glm::rotation(glm::dvec3(0, 0, 1), n);
      const glm::dquat blended = glm::slerp(glm::dquat(1, 0, 0, 0), tilt, p.align);
      out.rotation[i] = glm::quat(glm::normalize(blended * glm::dquat(out.rotation[i])));
    }
  }
  return out;
}

}  // namespace orogen
