#include "nodes/landform/dunes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kSinuosityOctaves = 3;

double lee_width(const DunesParams& p) {
  return std::max((1.0 - p.stoss_share) * p.wavelength, p.height / std::tan(p.repose_angle * kDeg));
}
}  // namespace

void check_dunes(const DunesParams& p) {
  require(p.wavelength > 0.0, "Dunes", "wavelength (" + num(p.wavelength) + " m) must be positive");
  require(p.height >= 0.0, "Dunes", "height (" + num(p.height) + " m) must be at least 0");
  require(p.stoss_share >= 0.5 && p.stoss_share <= 0.95, "Dunes",
          "stoss_share (" + num(p.stoss_share) + ") must be 0.5..0.95");
  require(p.repose_angle > 0.0 && p.repose_angle < 90.0, "Dunes",
          "repose_angle (" + num(p.repose_angle) + " deg) must be above 0 and below 90");
  require(p.sinuosity >= 0.0, "Dunes", "sinuosity (" + num(p.sinuosity) + " m) must be at least 0");
  require(p.sinuosity_feature_size > 0.0, "Dunes",
          "sinuosity_feature_size (" + num(p.sinuosity_feature_size) + " m) must be positive");
  // The slip face is the steep side: the stoss's steepest slope (pi/2 height / S) must stay below the lee's.
  const double lee = lee_width(p), stoss = p.wavelength - lee;
  require((stoss > 0.0 && 0.5 * std::numbers::pi * p.height / stoss <= p.height / lee) || p.height == 0.0, "Dunes",
          "height (" + num(p.height) + " m) is too tall for wavelength " + num(p.wavelength) +
              " m: the slip face at "
              "the repose angle (" +
              num(p.repose_angle) + " deg) needs " + num(lee) +
              " m, leaving too little for a gentler windward slope; lower height or raise wavelength");
}

double dune_profile(const DunesParams& p, double u) {
  const double lee = lee_width(p), stoss = p.wavelength - lee;
  const double phase = u / p.wavelength;
  const double along = (phase - std::floor(phase)) * p.wavelength;  // 0..wavelength within the period
  if (along < stoss) {
    const double s = std::sin(0.5 * std::numbers::pi * along / stoss);
    return p.height * s * s;
  }
  return p.height * std::max(0.0, 1.0 - (along - stoss) / lee);
}

std::shared_ptr<Heightfield> dunes_field(const Domain& domain, const DunesParams& p, const ExecContext* ctx) {
  check_dunes(p);
  Heightfield wander;
  if (p.sinuosity > 0.0)
    wander = landform::unit_noise(domain, p.sinuosity_feature_size, kSinuosityOctaves, false, p.seed, ctx);
  const double wx = std::sin(p.wind_azimuth * kDeg), wy = std::cos(p.wind_azimuth * kDeg);
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) {
      double u = domain.x(i) * wx + y * wy;
      if (p.sinuosity > 0.0) u += p.sinuosity * static_cast<double>(wander.at(i, j));
      o[static_cast<std::size_t>(i)] = static_cast<float>(dune_profile(p, u));
    }
  });
  return out;
}

OROGEN_NODE(Dunes) {
  b.reach_pointwise();
  // The noise fields held beside the output while it is filled.
  b.extra_bytes(
      [](const CostQuery& q) { return per_sample_bytes(q, q.params.get<double>("sinuosity") > 0.0 ? 4.0 : 0.0); });
  b.category("landform")
      .description(
          "A field of transverse dunes, crests across the wind every `wavelength`: a gentle convex stoss slope "
          "(height sin^2) on the windward stoss_share of each period and a planar slip face downwind at "
          "atan(height / lee width), widened if needed so it never exceeds repose_angle (about 34 degrees for "
          "dry sand, R. A. Bagnold (1941), \"The Physics of Blown Sand and Desert Dunes\"). Crest lines wander "
          "by up to `sinuosity` along the wind (seeded fBm, K. Perlin (2002), \"Improving noise\", SIGGRAPH). "
          "Multiply by a mask to limit the field.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_float("wavelength", 120.0)
      .range(1e-3, 1e7)
      .soft_range(5.0, 3000.0)
      .unit(Unit::Metre)
      .description("Spacing of the crests along the wind");
  b.param_float("height", 12.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 300.0)
      .unit(Unit::Metre)
      .description("Height of the crests above the troughs");
  b.param_float("wind_azimuth", 90.0)
      .range(-360.0, 360.0)
      .soft_range(0.0, 360.0)
      .unit(Unit::Degree)
      .description("Direction the wind blows toward, clockwise from north (+y); the slip faces face this way");
  b.param_float("stoss_share", 0.75)
      .range(0.5, 0.95)
      .unit(Unit::Unitless)
      .description("Share of each period taken by the gentle windward (stoss) slope; the rest is the slip face");
  b.param_float("repose_angle", 34.0)
      .range(5.0, 60.0)
      .unit(Unit::Degree)
      .description("Angle of repose: the steepest a slip face gets (about 34 for dry sand)");
  b.param_float("sinuosity", 25.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 500.0)
      .unit(Unit::Metre)
      .description("How far crest lines wander along the wind; 0 for straight crests");
  b.param_float("sinuosity_feature_size", 400.0)
      .range(1e-3, 1e7)
      .soft_range(20.0, 5000.0)
      .unit(Unit::Metre)
      .description("Length of the crests' largest bends");
  b.param_seed("seed", 0).description("Random seed of the crest lines' wander");
  b.execute([](ExecContext& ctx) {
    DunesParams p;
    p.wavelength = ctx.param<double>("wavelength");
    p.height = ctx.param<double>("height");
    p.wind_azimuth = ctx.param<double>("wind_azimuth");
    p.stoss_share = ctx.param<double>("stoss_share");
    p.repose_angle = ctx.param<double>("repose_angle");
    p.sinuosity = ctx.param<double>("sinuosity");
    p.sinuosity_feature_size = ctx.param<double>("sinuosity_feature_size");
    p.seed = ctx.param<std::uint64_t>("seed");
    ctx.set_output("out", dunes_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
