#pragma once
// The sRGB transfer function (IEC 61966-2-1): colors are stored linear in images and meshes, and typed,
// shown and written to 8/16-bit files as sRGB.
//
// Both directions clamp to [0, 1] (NaN gives 0) and compute at the precision of their argument: a float
// argument gives the float result earlier outputs were made with, a double one the double result, so callers
// holding floats that want double precision convert first.
#include <array>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstdint>

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

// The 8-bit sRGB code of a linear value as mesh files store it: the double-precision encoding rounded to
// float, then to a byte as OpenMesh's color_cast rounds (c * 255 + 0.5, truncated). That chain is monotonic in
// `linear`, so the byte is found among the 255 smallest floats reaching each code (a table made once, by
// bisection over the floats' bit patterns): the same byte without a pow per channel.
inline unsigned char srgb_byte_reference(float linear) {
  return static_cast<unsigned char>(static_cast<float>(linear_to_srgb(static_cast<double>(linear))) * 255.0f + 0.5f);
}
inline unsigned char srgb_byte(float linear) {
  static const std::array<float, 256> first = [] {
    std::array<float, 256> t{};
    for (int b = 1; b < 256; ++b) {
      // Bit patterns of non-negative floats order like the floats: the smallest in (0, 1] giving >= b.
      std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);
      while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (srgb_byte_reference(std::bit_cast<float>(mid)) >= b)
          hi = mid;
        else
          lo = mid + 1;
      }
      t[b] = std::bit_cast<float>(lo);
    }
    return t;
  }();
  if (!(linear > 0.0f)) return 0;  // NaN too
  int b = 0;
  for (int step = 128; step > 0; step >>= 1)
    if (b + step < 256 && first[b + step] <= linear) b += step;
  return static_cast<unsigned char>(b);
}

}  // namespace orogen
