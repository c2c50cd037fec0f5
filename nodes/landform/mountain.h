#pragma once
// Mountain: a massif of base `radius` around `position`. With u = r / radius (r the distance from the
// center) and the envelope e(u) = (1 - u)^2 (1 + u) (1 at a blunt summit, concave lower flanks, 0 with zero slope at
// the base):
//   e(u) (height + roughness (n(x, y) - n(position)))      for u < 1, else 0
// where n is Musgrave's ridged multifractal of seeded Perlin noise in [0, 1] (`octaves` octaves, the largest
// of size feature_size). Subtracting its value at the center keeps the summit at exactly `height`; the
// roughness fades with the envelope so the massif meets the plain smoothly.
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct MountainParams {
  glm::dvec2 position{512.0, 512.0};  // m
  double radius = 450.0;              // m, > 0
  double height = 350.0;              // m at the summit
  double roughness = 250.0;           // m, ridged-noise amplitude at the summit
  double feature_size = 300.0;        // m, > 0
  int octaves = 6;                    // 1..12
  std::uint64_t seed = 0;
};

void check_mountain(const MountainParams& p);  // NodeError naming "Mountain" and the parameter
std::shared_ptr<Heightfield> mountain_field(const Domain& domain, const MountainParams& p,
                                            const ExecContext* ctx = nullptr);

}  // namespace orogen
