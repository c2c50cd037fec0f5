#pragma once
// The arithmetic of SunIllumination (nodes/climate/sun.cpp) that its run across tiles
// (nodes/climate/sun_across_tiles.cpp) repeats on each tile: the sun positions over the day, the test that a sun
// is above every possible horizon, the horizon sweep's lines, samples, hull and gather, and what a lit cell adds.
// Both runs call these same functions, so a tile computes its cells with the very operations the whole-domain run
// does, bit for bit.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "graph/heightfield.h"
#include "graph/image.h"
#include "nodes/climate/sun.h"

namespace orogen::climate::sweep {

inline constexpr float kNone = -std::numeric_limits<float>::infinity();     // nothing ahead: no horizon
inline constexpr float kOutside = std::numeric_limits<float>::quiet_NaN();  // no line sample there

// Throws NodeError on parameters out of range.
void check_params(const SunParams& p);

// The distinct declinations of `months`, in the order the months first name them (months sharing a declination
// share the computation).
std::vector<double> declinations(std::span<const int> months);

// An image of `d` with a channel per month of `months`, named "jan" ...
std::shared_ptr<Image> month_image(const Domain& d, std::span<const int> months);

// Intervals of the day: ceil(24 / time_step).
int day_steps(const SunParams& p);

// A sun position over the day: the direction toward the sun and the hours it stands for.
struct SunPosition {
  glm::dvec3 s;
  double weight = 0.0;
};
// Interval k of the day at declination `decl`, clipped to sunrise and sunset; nullopt when the sun is down all of it.
std::optional<SunPosition> day_position(const SunParams& p, double decl, int k);

// The largest |dz| between neighboring samples along x and along y (infinity for both when a height is NaN). Over
// tiles sharing their border samples, the largest of the tiles' values is the whole domain's.
glm::dvec2 largest_steps(const Heightfield& z);

// Whether the sun in direction s (s.z > 0) can be below the horizon anywhere: no horizon tangent toward a unit
// direction d can exceed gx |d.x| + gy |d.y| (every chord of the interpolated lines is an average of steps bounded
// so; g = largest_steps / spacing), so a sun higher than that lights every cell and needs no sweep.
inline bool casts_shadows(glm::dvec2 max_grad, glm::dvec3 s) {
  const double horiz = std::hypot(s.x, s.y);
  const double bound = (max_grad.x * std::abs(s.x) + max_grad.y * std::abs(s.y)) / std::max(horiz, 1e-300);
  return !(horiz < 1e-12 || s.z / std::max(horiz, 1e-300) > bound * (1.0 + 1e-6) + 1e-9);
}
// The tangent of the sun's elevation, compared with the horizon tangents.
inline float sun_tangent(glm::dvec3 s) { return static_cast<float>(s.z / std::hypot(s.x, s.y)); }

// What a lit cell adds: `weight` hours, and weight x irradiance x cos(incidence) where the slope faces the sun.
struct Light {
  float w = 0.0f, wi = 0.0f;
  glm::vec3 sf{0.0f};
  Light(glm::dvec3 s, double weight, double irradiance)
      : w(static_cast<float>(weight)), wi(static_cast<float>(weight * irradiance)), sf(s) {}
  void add(const glm::vec3& normal, float* hours, float* irr) const {
    if (hours) *hours += w;
    if (irr) {
      const float cosi = glm::dot(normal, sf);
      if (cosi > 0.0f) *irr += wi * cosi;
    }
  }
};

// The unit surface normal at sample (i, j) of z (central differences, one-sided on z's borders).
glm::vec3 normal_at(const Heightfield& z, int i, int j);

// The lines of a sweep: straight, parallel to the sun's azimuth, one sample apart across the major axis (the one
// the direction changes faster along in index space), indexed by a = the major index and b = the minor one. Line l
// holds the points b = l + s m at steps s = 0..A-1 away from the sun.
struct Geometry {
  bool major_x = true;        // the major axis is x
  bool a_descending = false;  // the sun lies toward larger a: step 0 is a = A - 1
  int A = 0, B = 0;           // samples along the major and minor axes
  double m = 0.0;             // minor-index change per step away from the sun, |m| <= 1
  double ea = 0.0, eb = 0.0;  // metres toward the sun per index along a and b
  int column(int s) const { return a_descending ? A - 1 - s : s; }  // also the step of column s
};

// The sweep toward the horizontal direction `toward` on a grid of `resolution` samples `spacing` apart; nullopt when
// `toward` is zero or not finite.
inline std::optional<Geometry> geometry(glm::ivec2 resolution, glm::dvec2 spacing, glm::dvec2 toward) {
  const double sx = std::abs(spacing.x), sy = std::abs(spacing.y);
  const double len = std::hypot(toward.x, toward.y);
  if (!(len > 0.0) || !std::isfinite(len)) return std::nullopt;
  const glm::dvec2 d = toward / len;
  const double gx = d.x / sx, gy = d.y / sy;  // direction in index space
  Geometry g;
  g.major_x = std::abs(gx) >= std::abs(gy);
  g.A = g.major_x ? resolution.x : resolution.y;
  g.B = g.major_x ? resolution.y : resolution.x;
  const double ga = g.major_x ? gx : gy, gb = g.major_x ? gy : gx;
  g.m = -gb / std::abs(ga);
  g.a_descending = ga > 0.0;
  g.ea = g.major_x ? sx * d.x : sy * d.y;
  g.eb = g.major_x ? sy * d.y : sx * d.x;
  return g;
}

// Where every line crosses the column of step s: at b = l + boff + f, the same fraction f of a sample for all.
struct Crossing {
  int a = 0;  // the column
  double sm = 0.0, f = 0.0;
  int boff = 0;
  double u_s = 0.0;  // distance away from the sun of line 0's point
};
inline Crossing crossing(const Geometry& g, int s) {
  Crossing c;
  c.a = g.column(s);
  c.sm = s * g.m;
  const double fsm = std::floor(c.sm);
  c.f = c.sm - fsm;
  c.boff = static_cast<int>(fsm);
  c.u_s = -(c.a * g.ea + c.sm * g.eb);
  return c;
}
// Whether the line whose point at this crossing lies between minor samples b0 and b0 + 1 (at b0 when f = 0) is on
// the grid there.
inline bool on_grid(const Geometry& g, const Crossing& c, int b0) {
  return !(b0 < 0 || b0 > g.B - 1 || (b0 == g.B - 1 && c.f > 0.0));
}
// The line's height there from the heights z0 at b0 and z1 at b0 + 1 (unread when f = 0).
inline double line_height(const Crossing& c, float z0, float z1) {
  return c.f == 0.0 ? z0 : (1.0 - c.f) * z0 + c.f * z1;
}
// Line l's distance away from the sun there.
inline double line_distance(const Geometry& g, const Crossing& c, int l) { return c.u_s - l * g.eb; }

// Takes the sample (u, zp) into the upper hull of the samples ahead (n points in U, Z, room for one more) and
// returns its horizon tangent (kNone when nothing lies ahead).
inline float hull_step(double* U, double* Z, std::size_t& n, double u, double zp) {
  while (n >= 2 && (Z[n - 1] - Z[n - 2]) * (u - U[n - 2]) <= (zp - Z[n - 2]) * (U[n - 1] - U[n - 2])) --n;
  const float t = n ? static_cast<float>((Z[n - 1] - zp) / (u - U[n - 1])) : kNone;
  U[n] = u;
  Z[n] = zp;
  ++n;
  return t;
}

// How the cells of column a read the lines: cell (a, b) lies between lines b + below and b + below + 1 at the
// fraction frac (the same for the whole column); it reads the second only when frac > 0.
struct ColumnRead {
  int below = 0;
  float frac = 0.0f;
};
inline ColumnRead column_read(const Geometry& g, int a) {
  const int s = g.column(a);
  const double ms = -s * g.m, fl = std::floor(ms);
  return {static_cast<int>(fl), static_cast<float>(ms - fl)};
}
// A cell's horizon tangent from the two lines either side of it.
inline float blend(float t0, float t1, float f) {
  if (!(f > 0.0f)) return t0;
  if (std::isnan(t0)) return t1;  // the line below runs outside the grid here
  if (std::isnan(t1)) return t0;
  return (std::isinf(t0) || std::isinf(t1)) ? std::max(t0, t1) : (1.0f - f) * t0 + f * t1;
}

}  // namespace orogen::climate::sweep
