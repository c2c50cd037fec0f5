#include "nodes/texture/shading.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::texture {
namespace {

struct Tap {
  int di, dj;    // integer sample offset
  float fx, fy;  // bilinear fractions
  float inv_r;   // 1 / distance, 1/m
};

}  // namespace

HorizonMaps horizon_maps(const Heightfield& z, double radius, int directions, const ExecContext* ctx) {
  if (!(radius > 0.0)) throw NodeError("radius must be > 0");
  if (directions < 1) throw NodeError("directions must be >= 1");
  const double sx = std::abs(z.domain.spacing.x), sy = std::abs(z.domain.spacing.y);
  const double step = std::min(sx, sy);
  // Distances: one sample apart up to 4 samples, then growing by 30 %; at most 64 per direction.
  std::vector<double> dist;
  for (double r = step; dist.size() < 64; r = std::max(r + step, r * (r >= 4.0 * step ? 1.3 : 1.0))) {
    if (r >= radius) {
      dist.push_back(radius);
      break;
    }
    dist.push_back(r);
  }
  // Taps per direction, split into integer and fractional sample offsets once, so every cell computes
  // the same arithmetic (results do not depend on where the domain starts).
  std::vector<std::vector<Tap>> taps(static_cast<std::size_t>(directions));
  for (int k = 0; k < directions; ++k) {
    const double a = 2.0 * std::numbers::pi * k / directions;
    for (double r : dist) {
      const double u = r * std::cos(a) / sx, v = r * std::sin(a) / sy;
      const double fu = std::floor(u), fv = std::floor(v);
      if (std::abs(fu) > 1e7 || std::abs(fv) > 1e7) break;
      taps[static_cast<std::size_t>(k)].push_back({static_cast<int>(fu), static_cast<int>(fv),
                                                   static_cast<float>(u - fu), static_cast<float>(v - fv),
                                                   static_cast<float>(1.0 / r)});
    }
  }
  HorizonMaps out{std::make_shared<Heightfield>(z.domain), std::make_shared<Heightfield>(z.domain)};
  const int W = z.width(), H = z.height();
  for_each_row(ctx, H, [&](int j) {
    for (int i = 0; i < W; ++i) {
      const float z0 = z.at(i, j);
      double ao = 0.0, cav = 0.0;
      for (const auto& dir : taps) {
        float best = -std::numeric_limits<float>::infinity();
        for (const Tap& t : dir) {
          const int i0 = std::clamp(i + t.di, 0, W - 1), i1 = std::clamp(i + t.di + 1, 0, W - 1);
          const int j0 = std::clamp(j + t.dj, 0, H - 1), j1 = std::clamp(j + t.dj + 1, 0, H - 1);
          const float a = z.at(i0, j0) + t.fx * (z.at(i1, j0) - z.at(i0, j0));
          const float b = z.at(i0, j1) + t.fx * (z.at(i1, j1) - z.at(i0, j1));
          best = std::max(best, (a + t.fy * (b - a) - z0) * t.inv_r);
        }
        if (dir.empty()) best = 0.0f;
        const double s = best / std::sqrt(1.0 + static_cast<double>(best) * best);  // sin(atan(best))
        ao += 1.0 - std::max(0.0, s);
        cav += s;
      }
      out.ao->at(i, j) = static_cast<float>(ao / directions);
      out.cavity->at(i, j) = static_cast<float>(std::clamp(0.5 - 0.5 * cav / directions, 0.0, 1.0));
    }
  });
  return out;
}

std::shared_ptr<Heightfield> hillshade(const Heightfield& z, double azimuth_deg, double elevation_deg, double z_factor,
                                       const ExecContext* ctx) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double az = azimuth_deg * kDeg, alt = elevation_deg * kDeg;
  const double lx = std::sin(az) * std::cos(alt), ly = std::cos(az) * std::cos(alt), lz = std::sin(alt);
  auto out = std::make_shared<Heightfield>(z.domain);
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double p = 0.0, q = 0.0;
      if (z.width() > 1 || z.height() > 1) gradient_at(z, i, j, p, q);
      p *= z_factor;
      q *= z_factor;
      const double v = (-p * lx - q * ly + lz) / std::sqrt(1.0 + p * p + q * q);
      out->at(i, j) = static_cast<float>(std::max(0.0, v));
    }
  });
  return out;
}

std::shared_ptr<Image> gray_image(const Heightfield& value, const ExecContext* ctx) {
  auto img = std::make_shared<Image>(value.domain, 4, 1.0f);
  img->channel_names = {"R", "G", "B", "A"};
  img->color = true;
  const int W = value.width();
  for_each_row(ctx, value.height(), [&](int j) {
    for (int i = 0; i < W; ++i) {
      float* px = img->pixel(i, j);
      px[0] = px[1] = px[2] = value.at(i, j);
    }
  });
  return img;
}

OROGEN_NODE(AmbientOcclusion) {
  b.distribution(Distribution::PerTile);  // the reach function is always local
  b.reach([](const ParamView& p) { return Reach::local(p.get<double>("radius"), 2); }, "local: radius + 2 samples");
  b.category("texture").description(
      "Ambient occlusion of the terrain: the open sky seen from each cell, 1 - mean over azimuths of the "
      "sine of the horizon angle within the radius (horizon-based ambient occlusion after L. Bavoil, M. "
      "Sainz, R. Dimitrov (2008), Image-space horizon-based ambient occlusion). 1 on flat ground and peaks, "
      "lower in valleys and at the foot of cliffs. Multiply it into a color map.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield)
      .description("Occlusion factor in [0, 1] (1 = open sky)")
      .kind(OutputKind::Mask);
  b.param_float("radius", 100.0)
      .range(0.01, 1e4)
      .soft_range(1.0, 1000.0)
      .unit(Unit::Metre)
      .description("Search radius, metres");
  b.param_int("directions", 16).unit(Unit::Count).range(1, 64).description("Number of azimuths scanned, 1..64");
  b.execute([](ExecContext& ctx) {
    const auto r = horizon_maps(*ctx.require<Heightfield>("in"), ctx.param<double>("radius"),
                                static_cast<int>(ctx.param<std::int64_t>("directions")), &ctx);
    ctx.set_output("out", r.ao);
  });
}

OROGEN_NODE(Cavity) {
  b.distribution(Distribution::PerTile);  // the reach function is always local
  b.reach([](const ParamView& p) { return Reach::local(p.get<double>("radius"), 2); }, "local: radius + 2 samples");
  b.category("texture").description(
      "Cavity map: 0.5 - 0.5 x the mean sine of the signed horizon angle over azimuths within the radius "
      "(after L. Bavoil, M. Sainz, R. Dimitrov (2008), Image-space horizon-based ambient occlusion): 0.5 on a "
      "plane, darker in crevices and hollows, brighter on ridges and peaks. A small radius picks out "
      "detail.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield).description("Cavity in [0, 1] (0.5 = plane)").kind(OutputKind::Mask);
  b.param_float("radius", 20.0)
      .range(0.01, 1e4)
      .soft_range(1.0, 200.0)
      .unit(Unit::Metre)
      .description("Search radius, metres");
  b.param_int("directions", 8).unit(Unit::Count).range(1, 64).description("Number of azimuths scanned, 1..64");
  b.execute([](ExecContext& ctx) {
    const auto r = horizon_maps(*ctx.require<Heightfield>("in"), ctx.param<double>("radius"),
                                static_cast<int>(ctx.param<std::int64_t>("directions")), &ctx);
    ctx.set_output("out", r.cavity);
  });
}

OROGEN_NODE(Hillshade) {
  b.reach_local(0.0, 1);  // central differences
  b.category("texture").description(
      "Hillshade: Lambert shading max(0, n . l) of the surface under a distant light from an azimuth "
      "(clockwise from north) and elevation, the cartographic relief shading of B. K. P. Horn (1981), Hill "
      "shading and the reflectance map. No cast shadows (see SunIllumination).");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield).description("Shade in [0, 1]").kind(OutputKind::Mask);
  b.output("color", PortType::Image).description("The shade as a gray linear RGBA image");
  b.param_float("sun_azimuth", 315.0)
      .range(0.0, 360.0)
      .unit(Unit::Degree)
      .description("Light azimuth, degrees clockwise from north, 0..360");
  b.param_float("sun_elevation", 45.0)
      .range(0.0, 90.0)
      .unit(Unit::Degree)
      .description("Sun elevation above the horizon, degrees 0..90");
  b.param_float("z_factor", 1.0)
      .unit(Unit::Factor)
      .range(0.0, 100.0)
      .description("Vertical exaggeration, unitless 0..100");
  b.execute([](ExecContext& ctx) {
    auto h = hillshade(*ctx.require<Heightfield>("in"), ctx.param<double>("sun_azimuth"),
                       ctx.param<double>("sun_elevation"), ctx.param<double>("z_factor"), &ctx);
    ctx.set_output("color", gray_image(*h, &ctx));
    ctx.set_output("out", h);
  });
}

}  // namespace orogen::texture
