#pragma once
// The exact sum of floats, rounded once to the nearest double: the same whatever the order of addition, so sums
// split over threads, tiles or ranks in any way agree bit for bit (KMeansClusters across tiles).
//
// Every finite float is an integer multiple of 2^-149 below 2^128: a fixed-point number of 32-bit limbs from 2^-149
// up holds it exactly (nodes/common/exact_limb_sum.h). A float's 24-bit significand, shifted within its limb, spans at
// most two limbs. Infinities and NaN are counted apart and give the IEEE sum's infinity or NaN.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

#include "nodes/common/exact_limb_sum.h"

namespace orogen {

class ExactFloatSum : public ExactLimbSum<10, 149> {  // 9 limbs span 2^-149 .. 2^139; the tenth takes carries and sign
 public:
  void add(float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    const std::uint32_t e = (u >> 23) & 0xFFu;
    if (e == 0xFFu) {
      add_special(v);
      return;
    }
    const std::uint64_t m = (u & 0x7FFFFFu) | (e ? 0x800000u : 0u);
    const std::uint32_t s = e ? e - 1 : 0;  // v = m 2^(s - 149)
    const std::uint64_t w = m << (s & 31u);
    const std::int64_t parts[2] = {static_cast<std::int64_t>(w & 0xFFFFFFFFu), static_cast<std::int64_t>(w >> 32)};
    add_parts(s >> 5, parts, 2, (u >> 31) != 0);
  }

  // Adds a double that is itself an exact sum of floats: a multiple of 2^-149 below 2^159 in magnitude (FloatBuckets'
  // sums stay below 2^142, those of up to 2^count_bits floats at or above exact_double_floor below 2^140). Its 53-bit
  // significand, shifted within its lowest limb, spans limbs i .. i+2, and i + 2 <= kLimbs - 1 holds for |d| < 2^159
  // only; throws std::out_of_range above.
  void add_exact(double d) {
    if (!std::isfinite(d)) {
      add_special(d);
      return;
    }
    if (d == 0.0) return;
    if (!(std::abs(d) < 0x1p159)) throw std::out_of_range("ExactFloatSum::add_exact: a sum of 2^159 or more");
    std::uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    const int biased = static_cast<int>((bits >> 52) & 0x7FF);
    std::uint64_t m = (bits & ((std::uint64_t{1} << 52) - 1)) | (biased ? std::uint64_t{1} << 52 : 0);
    int shift = (biased ? biased : 1) - 1075 + 149;  // |d| = m 2^(shift - 149)
    if (shift < 0) {                                 // m's low bits are zero: d is a multiple of 2^-149
      m >>= -shift;
      shift = 0;
    }
    const unsigned __int128 w = static_cast<unsigned __int128>(m) << (shift & 31);
    const std::int64_t parts[3] = {static_cast<std::int64_t>(static_cast<std::uint64_t>(w) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 32) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 64))};
    add_parts(static_cast<std::size_t>(shift >> 5), parts, 3, d < 0.0);
  }

  void add(const ExactFloatSum& o) { add_sum(o); }
};

// The least float T (0 or a power of two) such that any 2^count_bits floats whose magnitudes lie in [T, largest] add up
// exactly in a double, in any order (then a plain double sums them, and only the rest needs an ExactFloatSum).
// Proof: let e >= 1 be the biased exponent of largest and f = e - (29 - count_bits). Every float of magnitude at least
// T = 2^(f - 127) has a biased exponent of at least f, so it is an integer multiple of u = 2^(f - 150); below
// 2^(e - 126) = 2^(53 - count_bits) u, it is a multiple of u below 2^(53 - count_bits) u. A sum of up to 2^count_bits
// of them, and every partial sum, is a multiple of u below 2^53 u: a double holds it, so every addition is exact. For
// f <= 1 every float is a multiple of 2^-149 and largest < 2^(e - 126) <= 2^(53 - count_bits) 2^-149: T = 0 (all).
// An infinite (or NaN) largest gives T = infinity: only infinities, which a double adds as IEEE addition does.
inline float exact_double_floor(float largest, int count_bits) {
  std::uint32_t bits;
  std::memcpy(&bits, &largest, sizeof bits);
  const int e = static_cast<int>((bits >> 23) & 0xFFu);
  if (e == 0xFF) return std::numeric_limits<float>::infinity();
  const int f = e - (29 - count_bits);
  if (f <= 1) return 0.0f;
  const std::uint32_t t = static_cast<std::uint32_t>(f) << 23;
  float r;
  std::memcpy(&r, &t, sizeof r);
  return r;
}

// A fast front for ExactFloatSum: up to kMaxAdds floats summed exactly in 16 doubles, one per range of 16 binary
// exponents, then moved into an ExactFloatSum. The floats of one range are multiples of its least ulp and below 2^39
// of them, so 2^14 of them and every partial sum fit a double's 53 bits: each addition is exact, in any order. A
// float costs a bit shift and a double addition.
struct FloatBuckets {
  static constexpr int kMaxAdds = 1 << 14;
  std::array<double, 16> bucket{};

  void add(float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    bucket[(u >> 27) & 15u] += v;  // the exponent's top four bits (specials land in the top bucket)
  }
  // Moves the sums into `into` and empties the buckets.
  void move_into(ExactFloatSum& into) {
    for (double& b : bucket) {
      if (b != 0.0 || std::isnan(b)) into.add_exact(b);
      b = 0.0;
    }
  }
};

}  // namespace orogen
