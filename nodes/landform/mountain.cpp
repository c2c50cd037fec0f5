#include "nodes/landform/mountain.h"

#include <cmath>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

void check_mountain(const MountainParams& p) {
  require(p.radius > 0.0, "Mountain", "radius (" + num(p.radius) + " m) must be positive");
  require(p.roughness >= 0.0, "Mountain", "roughness (" + num(p.roughness) + " m) must be at least 0");
  require(p.feature_size > 0.0, "Mountain", "feature_size (" + num(p.feature_size) + " m) must be positive");
  require(p.octaves >= 1 && p.octaves <= 12, "Mountain", "octaves (" + num(p.octaves) + ") must be 1..12");
}

std::shared_ptr<Heightfield> mountain_field(const Domain& domain, const MountainParams& p, const ExecContext* ctx) {
  check_mountain(p);
  Heightfield noise;
  double at_center = 0.0;
  if (p.roughness > 0.0) {
    noise = landform::unit_noise(domain, p.feature_size, p.octaves, true, p.seed, ctx);
    // From the scalar reference: one constant for every tile, whatever lattice it is on.
    at_center = landform::unit_noise_at(p.position.x, p.position.y, p.feature_size, p.octaves, true, p.seed);
  }
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) {
      const double u = std::hypot(domain.x(i) - p.position.x, y - p.position.y) / p.radius;
      double h = 0.0;
      if (u < 1.0) {
        const double e = (1.0 - u) * (1.0 - u) * (1.0 + u);
        const double n = p.roughness > 0.0 ? static_cast<double>(noise.at(i, j)) - at_center : 0.0;
        h = e * (p.height + p.roughness * n);
      }
      o[static_cast<std::size_t>(i)] = static_cast<float>(h);
    }
  });
  return out;
}

OROGEN_NODE(Mountain) {
  b.reach_pointwise();
  // The noise fields held beside the output while it is filled.
  b.extra_bytes(
      [](const CostQuery& q) { return per_sample_bytes(q, q.params.get<double>("roughness") > 0.0 ? 4.0 : 0.0); });
  b.category("landform")
      .description(
          "A mountain massif: the envelope e = (1 - u)^2 (1 + u), u = distance / radius, times height plus "
          "roughness x a seeded ridged multifractal (F. K. Musgrave (1994), \"Methods for realistic landscape "
          "imaging\", in Texturing and Modeling: A Procedural Approach) taken relative to its value at the "
          "summit: the summit is exactly `height`, ridges and gullies fade toward the base, 0 beyond `radius`.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("position", {512.0, 512.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the summit");
  b.param_float("radius", 450.0)
      .range(1e-3, 1e7)
      .soft_range(50.0, 20000.0)
      .unit(Unit::Metre)
      .description("Base radius of the massif");
  b.param_float("height", 350.0)
      .range(-1e5, 1e5)
      .soft_range(0.0, 5000.0)
      .unit(Unit::Metre)
      .description("Height of the summit");
  b.param_float("roughness", 250.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 3000.0)
      .unit(Unit::Metre)
      .description("Amplitude of the ridged noise at the summit, fading with the envelope toward the base");
  b.param_float("feature_size", 300.0)
      .range(1e-3, 1e7)
      .soft_range(20.0, 5000.0)
      .unit(Unit::Metre)
      .description("Size of the largest ridges and valleys");
  b.param_int("octaves", 6).range(1, 12).unit(Unit::Count).description("Octaves of the ridged noise, 1..12");
  b.param_seed("seed", 0).description("Random seed of the ridges");
  b.execute([](ExecContext& ctx) {
    MountainParams p;
    p.position = ctx.param<glm::dvec2>("position");
    p.radius = ctx.param<double>("radius");
    p.height = ctx.param<double>("height");
    p.roughness = ctx.param<double>("roughness");
    p.feature_size = ctx.param<double>("feature_size");
    p.octaves = static_cast<int>(ctx.param<std::int64_t>("octaves"));
    p.seed = ctx.param<std::uint64_t>("seed");
    ctx.set_output("out", mountain_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
