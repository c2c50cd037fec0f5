#include "nodes/climate/sun.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/calendar.h"
#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/climate/sun_sweep.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::climate {

const std::array<const char*, 12> kMonthNames = {"jan", "feb", "mar", "apr", "may", "jun",
                                                 "jul", "aug", "sep", "oct", "nov", "dec"};

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

double declination_deg(int month) { return kMaxTilt - std::abs(6 - month) * (kMaxTilt / 3.0); }

double declination_for_day(double day_of_year) {
  return 23.45 * std::sin(360.0 * (284.0 + day_of_year) / 365.0 * kDeg);
}

double sunset_hour_angle_deg(double latitude_deg, double declination_deg) {
  const double c = -std::tan(latitude_deg * kDeg) * std::tan(declination_deg * kDeg);
  if (!(c > -1.0)) return c <= -1.0 ? 180.0 : 0.0;  // polar day (NaN: treat as night)
  if (c >= 1.0) return 0.0;                         // polar night
  return std::acos(c) / kDeg;
}

double day_length_hours(double latitude_deg, double declination_deg) {
  return 2.0 * sunset_hour_angle_deg(latitude_deg, declination_deg) / 15.0;
}

glm::dvec3 sun_direction(double latitude_deg, double declination_deg, double hour) {
  const double phi = latitude_deg * kDeg, delta = declination_deg * kDeg, h = 15.0 * (hour - 12.0) * kDeg;
  return {-std::cos(delta) * std::sin(h),
          std::cos(phi) * std::sin(delta) - std::sin(phi) * std::cos(delta) * std::cos(h),
          std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(h)};
}

namespace {

// Calls fn(cell, tan_horizon) once for every cell (from parallel tasks; each cell from exactly one task).
// Straight lines parallel to the sun's azimuth, one cell apart across the major axis, are sampled where they
// cross each column (or row) by linear interpolation between the two cells there; the horizon of every line
// sample comes from the running upper hull of the samples ahead of it. A cell takes the horizon of the two
// lines passing either side of it in its column, interpolated linearly (exact on planes).
template <class Fn>
void sweep_horizon(const Heightfield& z, glm::dvec2 toward, const ExecContext* ctx, Fn&& fn) {
  using namespace sweep;
  const auto geo = geometry(z.domain.resolution, z.domain.spacing, toward);
  if (!geo) {
    for (std::size_t c = 0; c < z.data.size(); ++c) fn(c, kNone);
    return;
  }
  const Geometry& g = *geo;
  const bool major_x = g.major_x;
  const int A = g.A, B = g.B;
  // Lines l0..l1 bracket every cell.
  const double span = (A - 1) * g.m;
  const int l0 = static_cast<int>(std::floor(-std::max(0.0, span))) - 1;
  const int l1 = B + static_cast<int>(std::ceil(-std::min(0.0, span))) + 1;
  // T: the horizon tangent of line l at step s (NaN where the line is outside the grid), laid out so the
  // gather, which walks the cells of a grid row, reads it almost sequentially: line-major when the lines run
  // along x (a grid row crosses the lines slowly), step-major when they run along y.
  const std::size_t L = static_cast<std::size_t>(l1 - l0 + 1);
  const std::size_t line_stride = major_x ? static_cast<std::size_t>(A) : 1;
  const std::size_t step_stride = major_x ? 1 : L;
  std::vector<float> T(L * static_cast<std::size_t>(A), kOutside);
  auto height = [&](int a, int b) { return major_x ? z.at(a, b) : z.at(b, a); };
  constexpr int kLines = 16;  // lines swept together by one task

  tbb::parallel_for(tbb::blocked_range<int>(l0, l1 + 1, kLines), [&](const tbb::blocked_range<int>& range) {
    if (ctx) ctx->check_cancelled();
    const int nl = static_cast<int>(range.size());
    std::vector<double> hu(static_cast<std::size_t>(nl) * static_cast<std::size_t>(A));
    std::vector<double> hz(hu.size());
    std::vector<std::size_t> count(static_cast<std::size_t>(nl), 0);
    for (int s = 0; s < A; ++s) {
      const Crossing c = crossing(g, s);
      float* out = T.data() + static_cast<std::size_t>(s) * step_stride;
      for (int q = 0; q < nl; ++q) {
        const int l = range.begin() + q;
        const int b0 = l + c.boff;
        if (!on_grid(g, c, b0)) continue;  // outside the grid: no sample
        const double zp = line_height(c, height(c.a, b0), c.f == 0.0 ? 0.0f : height(c.a, b0 + 1));
        out[static_cast<std::size_t>(l - l0) * line_stride] =
            hull_step(hu.data() + static_cast<std::size_t>(q) * static_cast<std::size_t>(A),
                      hz.data() + static_cast<std::size_t>(q) * static_cast<std::size_t>(A),
                      count[static_cast<std::size_t>(q)], line_distance(g, c, l), zp);
      }
    }
  });
  if (ctx) ctx->check_cancelled();
  // Gather: cell (a, b) reads lines b + below(a) and the next at step s(a).
  std::vector<std::ptrdiff_t> base(static_cast<std::size_t>(A));  // per column: T offset of line b + below at b = 0
  std::vector<float> frac(static_cast<std::size_t>(A));
  for (int a = 0; a < A; ++a) {
    const ColumnRead r = column_read(g, a);
    base[static_cast<std::size_t>(a)] =
        static_cast<std::ptrdiff_t>(g.column(a)) * static_cast<std::ptrdiff_t>(step_stride) +
        static_cast<std::ptrdiff_t>(r.below - l0) * static_cast<std::ptrdiff_t>(line_stride);
    frac[static_cast<std::size_t>(a)] = r.frac;
  }
  const std::ptrdiff_t ls = static_cast<std::ptrdiff_t>(line_stride);
  if (major_x) {  // grid row b: cell (a, b) reads lines b + below(a) and the next at step s(a)
    tbb::parallel_for(tbb::blocked_range<int>(0, B, 4), [&](const tbb::blocked_range<int>& range) {
      for (int b = range.begin(); b != range.end(); ++b)
        for (int a = 0; a < A; ++a) {
          const float* t = T.data() + base[static_cast<std::size_t>(a)] + b * ls;
          const float f = frac[static_cast<std::size_t>(a)];
          fn(z.index(a, b), blend(t[0], f > 0.0f ? t[ls] : t[0], f));
        }
    });
  } else {  // grid row a: cells (b, a), b = 0.., read consecutive lines at step s(a)
    tbb::parallel_for(tbb::blocked_range<int>(0, A, 4), [&](const tbb::blocked_range<int>& range) {
      for (int a = range.begin(); a != range.end(); ++a) {
        const float* t = T.data() + base[static_cast<std::size_t>(a)];
        const float f = frac[static_cast<std::size_t>(a)];
        for (int b = 0; b < B; ++b) fn(z.index(b, a), blend(t[b], f > 0.0f ? t[b + 1] : t[b], f));
      }
    });
  }
}

}  // namespace

std::vector<float> horizon_tangent(const Heightfield& z, glm::dvec2 toward, const ExecContext* ctx) {
  std::vector<float> out(z.data.size(), std::numeric_limits<float>::quiet_NaN());
  sweep_horizon(z, toward, ctx, [&](std::size_t c, float t) { out[c] = t; });
  return out;
}

std::vector<glm::vec3> surface_normals(const Heightfield& z, const ExecContext* ctx) {
  std::vector<glm::vec3> n(z.data.size());
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) n[z.index(i, j)] = sweep::normal_at(z, i, j);
  });
  return n;
}

namespace sweep {

glm::vec3 normal_at(const Heightfield& z, int i, int j) {
  double p = 0.0, q = 0.0;
  if (z.width() > 1 || z.height() > 1) gradient_at(z, i, j, p, q);
  const double k = 1.0 / std::sqrt(1.0 + p * p + q * q);
  return glm::vec3(static_cast<float>(-p * k), static_cast<float>(-q * k), static_cast<float>(k));
}

void check_params(const SunParams& p) {
  if (!(std::abs(p.latitude) <= 90.0)) throw NodeError("latitude must be in [-90, 90] degrees");
  if (!(p.time_step >= 0.01 && p.time_step <= 24.0)) throw NodeError("time_step must be in [0.01, 24] hours");
}

std::vector<double> declinations(std::span<const int> months) {
  std::vector<double> decls;
  for (int m : months)
    if (std::find(decls.begin(), decls.end(), declination_deg(m)) == decls.end()) decls.push_back(declination_deg(m));
  return decls;
}

int day_steps(const SunParams& p) { return static_cast<int>(std::ceil(24.0 / p.time_step - 1e-9)); }

std::optional<SunPosition> day_position(const SunParams& p, double decl, int k) {
  const double h0 = sunset_hour_angle_deg(p.latitude, decl) / 15.0;
  const double rise = 12.0 - h0, set = 12.0 + h0;
  const double a = std::max(rise, k * p.time_step), b = std::min(set, std::min(24.0, (k + 1) * p.time_step));
  if (!(b > a)) return std::nullopt;
  return SunPosition{sun_direction(p.latitude, decl, 0.5 * (a + b)), b - a};
}

glm::dvec2 largest_steps(const Heightfield& z) {
  double gx = 0.0, gy = 0.0;
  for (int j = 0; j < z.height(); ++j)
    for (int i = 0; i < z.width(); ++i) {
      if (i + 1 < z.width()) gx = std::max(gx, std::abs(static_cast<double>(z.at(i + 1, j)) - z.at(i, j)));
      if (j + 1 < z.height()) gy = std::max(gy, std::abs(static_cast<double>(z.at(i, j + 1)) - z.at(i, j)));
      if (std::isnan(z.at(i, j)))
        return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    }
  return {gx, gy};
}

}  // namespace sweep

namespace {

// Largest |dz/dx| and |dz/dy| between neighbouring samples (sweep::casts_shadows).
glm::dvec2 max_gradient(const Heightfield& z) {
  const glm::dvec2 g = sweep::largest_steps(z);
  return {g.x / std::abs(z.domain.spacing.x), g.y / std::abs(z.domain.spacing.y)};
}

// Adds weight and weight * irradiance * cos(incidence) to every cell lit by the sun in direction s.
void accumulate_sun(const Heightfield& z, const std::vector<glm::vec3>& normals, glm::dvec2 max_grad, glm::dvec3 s,
                    double weight, double irradiance, float* hours, float* irr, const ExecContext* ctx) {
  if (!(s.z > 0.0)) return;
  const sweep::Light light(s, weight, irradiance);
  auto add = [&](std::size_t c) { light.add(normals[c], hours ? hours + c : nullptr, irr ? irr + c : nullptr); };
  if (!sweep::casts_shadows(max_grad, s)) {
    // Sun at the zenith or above every possible horizon: nothing casts a shadow.
    for_each_row(ctx, z.height(), [&](int j) {
      for (std::size_t c = z.index(0, j); c < z.index(0, j) + static_cast<std::size_t>(z.width()); ++c) add(c);
    });
    return;
  }
  const float tan_e = sweep::sun_tangent(s);
  sweep_horizon(z, {s.x, s.y}, ctx, [&](std::size_t c, float th) {
    if (tan_e > th) add(c);
  });
}

}  // namespace

std::shared_ptr<Image> sweep::month_image(const Domain& d, std::span<const int> months) {
  auto img = std::make_shared<Image>(d, static_cast<int>(months.size()));
  for (int m : months) img->channel_names.push_back(kMonthNames[static_cast<std::size_t>(m - 1)]);
  return img;
}

SunDaily sun_daily(const Heightfield& z, const SunParams& p, std::span<const int> months, const ExecContext* ctx) {
  sweep::check_params(p);
  SunDaily out{sweep::month_image(z.domain, months), sweep::month_image(z.domain, months)};
  const auto normals = surface_normals(z, ctx);
  const glm::dvec2 max_grad = max_gradient(z);
  const std::size_t n = z.data.size();
  const int nm = static_cast<int>(months.size());
  const std::vector<double> decls = sweep::declinations(months);
  const int steps = sweep::day_steps(p);
  std::vector<float> hours(n), irr(n);
  int done = 0;
  for (double decl : decls) {
    std::fill(hours.begin(), hours.end(), 0.0f);
    std::fill(irr.begin(), irr.end(), 0.0f);
    for (int k = 0; k < steps; ++k) {
      if (const auto sun = sweep::day_position(p, decl, k))
        accumulate_sun(z, normals, max_grad, sun->s, sun->weight, p.irradiance, hours.data(), irr.data(), ctx);
      if (ctx) {
        ctx->check_cancelled();
        ctx->progress((done * steps + k + 1.0) / (static_cast<double>(decls.size()) * steps));
      }
    }
    ++done;
    for (int c = 0; c < nm; ++c) {
      if (declination_deg(months[static_cast<std::size_t>(c)]) != decl) continue;
      for (std::size_t q = 0; q < n; ++q) {
        out.hours->data[q * static_cast<std::size_t>(nm) + static_cast<std::size_t>(c)] = hours[q];
        out.irradiance->data[q * static_cast<std::size_t>(nm) + static_cast<std::size_t>(c)] = irr[q] / 24.0f;
      }
    }
  }
  return out;
}

SunInstant sun_instant(const Heightfield& z, const SunParams& p, int month, double hour, const ExecContext* ctx) {
  sweep::check_params(p);
  SunInstant out{std::make_shared<Heightfield>(z.domain), std::make_shared<Heightfield>(z.domain)};
  const auto normals = surface_normals(z, ctx);
  accumulate_sun(z, normals, max_gradient(z), sun_direction(p.latitude, declination_deg(month), hour), 1.0,
                 p.irradiance, out.lit->data.data(), out.direct->data.data(), ctx);
  return out;
}

OROGEN_NODE(SunIllumination) {
  b.distribution(Distribution::TileGraph);  // nodes/climate/sun_across_tiles.cpp
  b.reach_global();                         // a shadow can fall from anywhere in the domain
  b.category("climate").description(
      "Direct sunlight with terrain shadows over the day, per month: lit hours per day and the 24-hour mean "
      "direct irradiance on the slope (irradiance x cosine of the incidence on the surface), plus the lit "
      "mask and direct irradiance at one instant. Sun position from latitude, declination by month and the "
      "hour angle 15 deg/h (J. A. Duffie, W. A. Beckman (2013), Solar Engineering of Thermal Processes); "
      "sunrise and sunset from acos(-tan(latitude) tan(declination)), clamped for polar day and night; "
      "monthly declination after H. Long (2016), Using procedural methods to generate realistic virtual "
      "rural worlds. Shadows by a horizon sweep per sun azimuth with a running convex hull, O(n) per "
      "direction (V. Timonen, J. Westerholm (2010), Scalable height field self-shadowing). +y is north, +x "
      "east; terrain outside the domain casts no shadow; no atmosphere or diffuse light. A tiled or distributed build "
      "runs it across the tiles with the untiled build's outputs bit for bit: each sun direction's sweep passes its "
      "lines' hulls from tile to tile along the sweep, all directions together in one wavefront of rounds (tiles "
      "across + tiles down + 1 rounds).");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Image).description("Lit hours per day, hours, one channel per month (jan..dec)");
  b.output("irradiance", PortType::Image)
      .description("24-hour mean direct irradiance on the slope, W/m^2, one channel per month");
  b.output("lit", PortType::Heightfield)
      .description("1 where the sun is visible at (day_of_year, hour), else 0")
      .kind(OutputKind::Mask);
  b.output("direct", PortType::Heightfield)
      .description("Direct irradiance on the slope at (day_of_year, hour), W/m^2")
      .kind(OutputKind::Scalar);
  b.param_float("latitude", 45.0)
      .range(-90.0, 90.0)
      .unit(Unit::Degree)
      .description("Latitude, degrees, -90..90, north positive");
  b.param_bool("all_months", true)
      .description("Daily outputs for all twelve months (else only for the month of day_of_year)");
  b.param_int("day_of_year", 166)
      .unit(Unit::DayOfYear)
      .range(1, 366)
      .description(
          "Date of the instant outputs (and of the daily outputs when all_months is off), 1 (January 1st) .. 366; "
          "the declination is the monthly one of the month holding the day (166 is June 15th)");
  b.param_float("hour", 15.0)
      .range(0.0, 24.0)
      .unit(Unit::Hour)
      .description("Solar time of the instant outputs, hours 0..24 (12 = solar noon)");
  b.param_float("time_step", 1.0)
      .range(0.1, 6.0)
      .unit(Unit::Hour)
      .description("Hours between sun positions over the day, 0.1..6 (each interval is clipped to sunrise and sunset)");
  b.param_float("irradiance", 1000.0)
      .range(0.0, 2000.0)
      .unit(Unit::WattPerSquareMetre)
      .description(
          "Direct normal irradiance of the sun, W/m^2, 0..2000 (1361 above the atmosphere, about 1000 at the ground on "
          "a clear day)");
  // Working memory beyond the outputs, 80 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 80); });
  b.execute([](ExecContext& ctx) {
    const auto z = ctx.require<Heightfield>("in");
    SunParams p;
    p.latitude = ctx.param<double>("latitude");
    p.time_step = ctx.param<double>("time_step");
    p.irradiance = ctx.param<double>("irradiance");
    const int month = calendar::month_of_day(static_cast<int>(ctx.param<std::int64_t>("day_of_year")));
    std::vector<int> months;
    if (ctx.param<bool>("all_months"))
      for (int m = 1; m <= 12; ++m) months.push_back(m);
    else
      months.push_back(month);
    auto daily = sun_daily(*z, p, months, &ctx);
    auto instant = sun_instant(*z, p, month, ctx.param<double>("hour"), &ctx);
    ctx.set_output("out", daily.hours);
    ctx.set_output("irradiance", daily.irradiance);
    ctx.set_output("lit", instant.lit);
    ctx.set_output("direct", instant.direct);
  });
}

}  // namespace orogen::climate
