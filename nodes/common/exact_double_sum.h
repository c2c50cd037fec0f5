#pragma once
// The exact sum of doubles, rounded once to the nearest double: the same whatever the order of addition, so sums
// split over threads, tiles or ranks in any way agree bit for bit (WaterFlow across tiles). The double counterpart of
// nodes/common/exact_float_sum.h.
//
// Every finite double is an integer multiple of 2^-1074 below 2^1024: a fixed-point number of 32-bit limbs from
// 2^-1074 up holds it exactly (nodes/common/exact_limb_sum.h; 66 limbs span 2^-1074 .. 2^1038, a 67th takes carries
// and the sign). A double's 53-bit significand, shifted within its limb, spans at most three limbs. Infinities and NaN
// are counted apart and give the IEEE sum's infinity or NaN.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "nodes/common/exact_limb_sum.h"

namespace orogen {

class ExactDoubleSum : public ExactLimbSum<67, 1074> {
 public:
  void add(double d) {
    std::uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    const int biased = static_cast<int>((bits >> 52) & 0x7FF);
    if (biased == 0x7FF) {
      add_special(d);
      return;
    }
    const std::uint64_t m = (bits & ((std::uint64_t{1} << 52) - 1)) | (biased ? std::uint64_t{1} << 52 : 0);
    if (m == 0) return;
    const int shift = biased ? biased - 1 : 0;  // |d| = m 2^(shift - 1074)
    const unsigned __int128 w = static_cast<unsigned __int128>(m) << (shift & 31);
    const std::int64_t parts[3] = {static_cast<std::int64_t>(static_cast<std::uint64_t>(w) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 32) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 64) & 0xFFFFFFFFu)};
    add_parts(static_cast<std::size_t>(shift >> 5), parts, 3, (bits >> 63) != 0);
  }

  void add(const ExactDoubleSum& o) { add_sum(o); }
};

}  // namespace orogen
