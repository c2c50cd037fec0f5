#pragma once
// Sun position, day length and terrain self-shadowing for the climate family.
//
// Conventions: world +x is east, +y is north (row j grows northwards), heights in metres. Months are 1..12
// (January..December). Angles in degrees unless a name says otherwise. A sun direction is a unit vector
// (east, north, up).
//
// Solar geometry (J. A. Duffie, W. A. Beckman (2013), Solar Engineering of Thermal Processes, ch. 1):
//   sin(elevation) = sin(phi) sin(delta) + cos(phi) cos(delta) cos(H),  H = 15 deg/h * (hour - 12)
//   sunset hour angle H0 = acos(-tan(phi) tan(delta)), clamped: polar night H0 = 0, polar day H0 = 180 deg,
//   day length = 2 H0 / 15 hours.
// Declination by month after H. Long (2016), Using procedural methods to generate realistic virtual rural
// worlds (eq. 3.3), with the sign chosen so June is the northern summer: delta(m) = 23.5 - |6 - m| * 23.5/3
// (June +23.5, March and September 0, December -23.5; months m and 12 - m share a declination).
//
// Shadows: a cell is lit when the sun's elevation exceeds the terrain horizon toward the sun's azimuth.
// The horizon is found for every cell at once by sweeping lines of cells parallel to the sun's azimuth,
// away from the sun, keeping the upper convex hull of the profile already seen: the horizon of a cell is
// the tangent from it to that hull (O(n) per direction: each cell enters and leaves the hull once). After
// V. Timonen, J. Westerholm (2010), Scalable height field self-shadowing, Computer Graphics Forum 29(2).
// Lines are straight, one cell apart, sampled where they cross each column (or row) by linear
// interpolation; a cell takes the horizons of the two lines either side of it, interpolated (exact on
// planes). Terrain outside the domain casts no shadow.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::climate {

inline constexpr double kMaxTilt = 23.5;  // degrees, Earth's obliquity as H. Long (2016) rounds it

extern const std::array<const char*, 12> kMonthNames;  // "jan" .. "dec"

// Declination in degrees for month 1..12.
double declination_deg(int month);
// Declination in degrees on day `day_of_year` (1 = January 1st; fractions allowed) by P. I. Cooper (1969),
// The absorption of radiation in solar stills, Solar Energy 12(3), as J. A. Duffie, W. A. Beckman (2013), eq.
// 1.6.1a, give it: delta = 23.45 sin(360 (284 + n) / 365) (about +23.45 on June 21st, -23.45 on December 21st).
double declination_for_day(double day_of_year);
// Sunset hour angle in degrees in [0, 180] (0: polar night, 180: polar day).
double sunset_hour_angle_deg(double latitude_deg, double declination_deg);
// Hours between sunrise and sunset on a flat horizon, in [0, 24].
double day_length_hours(double latitude_deg, double declination_deg);
// Unit vector toward the sun (east, north, up) at solar time `hour` (12 = solar noon).
glm::dvec3 sun_direction(double latitude_deg, double declination_deg, double hour);

// For each cell, the tangent of the terrain's horizon elevation looking along the horizontal direction
// `toward` (east, north; need not be normalised): max over cells c' ahead of (z' - z) / distance. -infinity
// where nothing lies ahead (the border facing the sun).
std::vector<float> horizon_tangent(const Heightfield& z, glm::dvec2 toward, const ExecContext* ctx = nullptr);

// Unit surface normals (east, north, up) from central differences in world units.
std::vector<glm::vec3> surface_normals(const Heightfield& z, const ExecContext* ctx = nullptr);

struct SunParams {
  double latitude = 45.0;      // degrees, -90..90 (north positive)
  double time_step = 1.0;      // hours between sun positions over the day, 0.1..6
  double irradiance = 1000.0;  // W/m^2, direct normal irradiance of the sun (1361 above the atmosphere)
};

// Daily figures per month: lit hours (h/day) and the 24-hour mean direct irradiance on the slope (W/m^2).
// The day is cut into intervals of time_step hours; each interval is clipped to the daylight window
// [12 - H0/15, 12 + H0/15] and the sun is tested at the middle of the clipped part, weighted by its length,
// so a flat terrain gets exactly the day length. One image channel per requested month, named "jan" ...
struct SunDaily {
  std::shared_ptr<Image> hours;
  std::shared_ptr<Image> irradiance;
};
SunDaily sun_daily(const Heightfield& z, const SunParams& p, std::span<const int> months,
                   const ExecContext* ctx = nullptr);

// The instant at (month, hour): lit mask (1 lit, 0 in shadow or at night) and direct irradiance on the
// slope (W/m^2).
struct SunInstant {
  std::shared_ptr<Heightfield> lit;
  std::shared_ptr<Heightfield> direct;
};
SunInstant sun_instant(const Heightfield& z, const SunParams& p, int month, double hour,
                       const ExecContext* ctx = nullptr);

}  // namespace orogen::climate
