#pragma once
// Radial falloff: the island mask. With d the distance from `center` (plus an optional per-sample
// offset, so noise can roughen the coastline) and t = clamp(d / radius, 0, 1), the value is profile(t):
// the profile curve maps normalised distance to the mask. The default profile goes from 1 at the center
// to 0 at the radius and stays 0 beyond, with a broad plateau and a smooth shore.
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/param_value.h"

namespace orogen {

struct RadialFalloffParams {
  glm::dvec2 center{512.0, 512.0};  // m
  double radius = 480.0;            // m, > 0
  CurveValue profile;               // t in 0..1 -> mask
};

CurveValue default_falloff_profile();

double radial_falloff_value(glm::dvec2 position, double distance_offset, const RadialFalloffParams& p);

// distance_offset (metres, may be null) must lie on `domain`.
std::shared_ptr<Heightfield> radial_falloff(const Domain& domain, const RadialFalloffParams& p,
                                            const Heightfield* distance_offset = nullptr,
                                            const ExecContext* ctx = nullptr);

}  // namespace orogen
