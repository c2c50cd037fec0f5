#pragma once
// The sRGB transfer function (IEC 61966-2-1): colors are stored linear in images and meshes, and typed,
// shown and written to 8/16-bit files as sRGB.
//
// Both directions clamp to [0, 1] (NaN gives 0) and compute at the precision of their argument: a float
// argument gives the float result earlier outputs were made with, a double one the double result, so callers
// holding floats that want double precision convert first.
#include <cmath>
#include <concepts>

namespace orogen {

// sRGB-encoded value in [0, 1] to linear light in [0, 1]. srgb_to_linear(0.5) = 0.21404114...
template <std::floating_point T>
T srgb_to_linear(T c) {
  if (!(c > T(0))) return T(0);
  if (c >= T(1)) return T(1);
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

// Linear light in [0, 1] to sRGB-encoded in [0, 1]. linear_to_srgb(0.5) = 0.73535698...
template <std::floating_point T>
T linear_to_srgb(T v) {
  if (!(v > T(0))) return T(0);
  if (v >= T(1)) return T(1);
  return v <= T(0.0031308) ? T(12.92) * v : T(1.055) * std::pow(v, T(1) / T(2.4)) - T(0.055);
}

}  // namespace orogen
