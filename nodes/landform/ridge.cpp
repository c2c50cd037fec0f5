#include "nodes/landform/ridge.h"

#include <algorithm>
#include <cmath>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/hash.h"
#include "nodes/common/smoothstep.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

void check_ridge(const RidgeParams& p) {
  const double length = std::hypot(p.end.x - p.start.x, p.end.y - p.start.y);
  require(
      length > 0.0, "Ridge",
      "start and end are the same point (" + num(p.start.x) + ", " + num(p.start.y) + ") m; a ridge needs a length");
  require(p.half_width > 0.0, "Ridge", "half_width (" + num(p.half_width) + " m) must be positive");
  require(p.sharpness >= 0.0 && p.sharpness <= 1.0, "Ridge", "sharpness (" + num(p.sharpness) + ") must be 0..1");
  require(p.taper_length >= 0.0, "Ridge", "taper_length (" + num(p.taper_length) + " m) must be at least 0");
  require(p.meander >= 0.0, "Ridge", "meander (" + num(p.meander) + " m) must be at least 0");
  require(p.roughness >= 0.0, "Ridge", "roughness (" + num(p.roughness) + " m) must be at least 0");
  require(p.feature_size > 0.0, "Ridge", "feature_size (" + num(p.feature_size) + " m) must be positive");
}

namespace {
constexpr int kMeanderOctaves = 3;
constexpr int kRoughnessOctaves = 6;
}  // namespace

double ridge_height(const RidgeParams& p, double x, double y) {
  const double dx = p.end.x - p.start.x, dy = p.end.y - p.start.y;
  const double length = std::hypot(dx, dy);
  // Along-segment distance of the nearest point, clamped to the segment.
  const double s = std::clamp(((x - p.start.x) * dx + (y - p.start.y) * dy) / length, 0.0, length);
  const double nx = p.start.x + dx * (s / length), ny = p.start.y + dy * (s / length);
  const double u = std::hypot(x - nx, y - ny) / p.half_width;
  if (u >= 1.0) return 0.0;
  const double bell = 1.0 - u * u * (3.0 - 2.0 * u);
  const double knife = (1.0 - u) * (1.0 - u);
  const double c = (1.0 - p.sharpness) * bell + p.sharpness * knife;
  const double a = p.taper_length > 0.0 ? smoothstep01(std::min(s, length - s) / p.taper_length) : 1.0;
  return p.height * a * c;
}

std::shared_ptr<Heightfield> ridge_field(const Domain& domain, const RidgeParams& p, const ExecContext* ctx) {
  check_ridge(p);
  Heightfield wx, wy, rough;
  if (p.meander > 0.0) {
    wx = landform::unit_noise(domain, p.feature_size, kMeanderOctaves, false, p.seed, ctx);
    wy = landform::unit_noise(domain, p.feature_size, kMeanderOctaves, false, hash64(p.seed, 1), ctx);
  }
  if (p.roughness > 0.0) rough = landform::unit_noise(domain, p.feature_size, kRoughnessOctaves, true, p.seed, ctx);
  auto out = std::make_shared<Heightfield>(domain);
  // The envelope of ridge_height for a unit height, so the roughness rides on the same shape.
  RidgeParams unit = p;
  unit.height = 1.0;
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) {
      double qx = domain.x(i), qy = y;
      if (p.meander > 0.0) {
        qx += p.meander * static_cast<double>(wx.at(i, j));
        qy += p.meander * static_cast<double>(wy.at(i, j));
      }
      const double e = ridge_height(unit, qx, qy);
      const double n = p.roughness > 0.0 ? static_cast<double>(rough.at(i, j)) - 0.5 : 0.0;
      o[static_cast<std::size_t>(i)] = static_cast<float>(e * (p.height + p.roughness * n));
    }
  });
  return out;
}

OROGEN_NODE(Ridge) {
  b.reach_pointwise();
  // The noise fields held beside the output while it is filled.
  b.extra_bytes([](const CostQuery& q) {
    return per_sample_bytes(
        q, (q.params.get<double>("meander") > 0.0 ? 8.0 : 0.0) + (q.params.get<double>("roughness") > 0.0 ? 4.0 : 0.0));
  });
  b.category("landform")
      .description(
          "A ridge whose crest runs along the segment start-end at `height`, falling to 0 at half_width from it "
          "with the cross profile (1 - sharpness) (1 - 3u^2 + 2u^3) + sharpness (1 - u)^2, u = distance / "
          "half_width (a rounded bell blended with a knife-edge crest over concave flanks), and coming down to "
          "the ground over taper_length at each end (smoothstep of the distance to the nearer end). The crest bends by "
          "up to `meander` (the sample displaced by seeded fBm, K. Perlin (2002), \"Improving noise\", SIGGRAPH) and "
          "`roughness` x (a ridged multifractal - 1/2) (F. K. Musgrave (1994), in Texturing and Modeling: A "
          "Procedural Approach) carves spurs and gullies under the same profile.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("start", {200.0, 300.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of one end of the crest");
  b.param_vec2("end", {824.0, 724.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the other end of the crest");
  b.param_float("height", 200.0)
      .range(-1e5, 1e5)
      .soft_range(0.0, 3000.0)
      .unit(Unit::Metre)
      .description("Height of the crest");
  b.param_float("half_width", 150.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 5000.0)
      .unit(Unit::Metre)
      .description("Horizontal distance from the crest to the foot of either flank");
  b.param_float("sharpness", 0.6)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description("Cross profile: 0 a rounded bell, 1 a knife-edge crest with concave flanks");
  b.param_float("taper_length", 150.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 5000.0)
      .unit(Unit::Metre)
      .description("Length over which the crest comes down to the ground at each end; 0 for full-height ends");
  b.param_float("meander", 40.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 1000.0)
      .unit(Unit::Metre)
      .description("How far the crest bends away from the straight segment; 0 for a straight crest");
  b.param_float("roughness", 60.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 1000.0)
      .unit(Unit::Metre)
      .description("Amplitude of the ridged noise on the crest and flanks (the crest varies by half of it)");
  b.param_float("feature_size", 250.0)
      .range(1e-3, 1e7)
      .soft_range(20.0, 5000.0)
      .unit(Unit::Metre)
      .description("Size of the largest bends, spurs and gullies");
  b.param_seed("seed", 0).description("Random seed of the bends and the roughness");
  b.execute([](ExecContext& ctx) {
    RidgeParams p;
    p.start = ctx.param<glm::dvec2>("start");
    p.end = ctx.param<glm::dvec2>("end");
    p.height = ctx.param<double>("height");
    p.half_width = ctx.param<double>("half_width");
    p.sharpness = ctx.param<double>("sharpness");
    p.taper_length = ctx.param<double>("taper_length");
    p.meander = ctx.param<double>("meander");
    p.roughness = ctx.param<double>("roughness");
    p.feature_size = ctx.param<double>("feature_size");
    p.seed = ctx.param<std::uint64_t>("seed");
    ctx.set_output("out", ridge_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
