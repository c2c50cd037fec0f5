#pragma once
// Dunes: a field of transverse dunes, crests across the wind. With u the distance downwind (along
// wind_azimuth, clockwise from north = +y) of the sample displaced by `sinuosity` times a seeded fBm, the
// phase t = frac(u / wavelength), the lee (slip face) width
//   L = max((1 - stoss_share) wavelength, height / tan(repose_angle))
// and the stoss width S = wavelength - L, one period is
//   t < S / wavelength:  height sin^2(pi/2 t wavelength / S)                   (gentle, convex stoss slope)
//   otherwise:           height (1 - (t wavelength - S) / L)                   (planar slip face)
// The slip face's slope, atan(height / L), never exceeds the angle of repose; the stoss is gentler (its
// steepest slope, atan(pi/2 height / S), is refused if steeper than the lee).
#include <cstdint>
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct DunesParams {
  double wavelength = 120.0;              // m, > 0: crest spacing along the wind
  double height = 12.0;                   // m, >= 0
  double wind_azimuth = 90.0;             // deg, the direction the wind blows toward, clockwise from north (+y)
  double stoss_share = 0.75;              // share of the wavelength on the windward side, 0.5..0.95
  double repose_angle = 34.0;             // deg, the steepest the slip face gets
  double sinuosity = 25.0;                // m, how far crests wander along the wind
  double sinuosity_feature_size = 400.0;  // m, > 0
  std::uint64_t seed = 0;
};

void check_dunes(const DunesParams& p);  // NodeError naming "Dunes" and the parameter
// The height at downwind distance u (the profile of one crest line).
double dune_profile(const DunesParams& p, double u);
std::shared_ptr<Heightfield> dunes_field(const Domain& domain, const DunesParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen
