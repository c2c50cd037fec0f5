#pragma once
// The exact sum of doubles, rounded once to the nearest double: the same whatever the order of addition, so sums
// split over threads, tiles or ranks in any way agree bit for bit (WaterFlow across tiles). The double counterpart of
// nodes/common/exact_float_sum.h.
//
// Every finite double is an integer multiple of 2^-1074 below 2^1024: a fixed-point number of 32-bit limbs from
// 2^-1074 up holds it exactly (66 limbs span 2^-1074 .. 2^1038; a 67th takes carries and the sign). A double's 53-bit
// significand, shifted within its limb, spans at most three limbs; each limb is kept in an int64 with its carries
// deferred, so a limb takes in 2^31 doubles before it must be normalized (add() normalizes every 2^30 additions).
// Infinities and NaN are counted apart and give the IEEE sum's infinity or NaN.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

namespace orogen {

class ExactDoubleSum {
 public:
  static constexpr int kLimbs = 67;

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
    const std::int64_t neg = -static_cast<std::int64_t>(bits >> 63);  // 0 or -1
    std::int64_t* l = limb_.data() + (shift >> 5);
    const auto part = [&](int k) {
      return static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> (32 * k)) & 0xFFFFFFFFu);
    };
    l[0] += (part(0) ^ neg) - neg;
    l[1] += (part(1) ^ neg) - neg;
    l[2] += (part(2) ^ neg) - neg;
    if (++pending_ == kNormalizeEvery) normalize();
  }

  void add(const ExactDoubleSum& o) {
    ExactDoubleSum b = o;
    b.normalize();
    normalize();
    for (int i = 0; i < kLimbs; ++i) limb_[i] += b.limb_[i];
    pos_inf_ += b.pos_inf_, neg_inf_ += b.neg_inf_, nan_ += b.nan_;
    normalize();
  }

  // The exact sum rounded to the nearest double (ties to even; beyond the largest double, infinity).
  double value() const {
    if (nan_ || (pos_inf_ && neg_inf_)) return std::numeric_limits<double>::quiet_NaN();
    if (pos_inf_) return std::numeric_limits<double>::infinity();
    if (neg_inf_) return -std::numeric_limits<double>::infinity();
    ExactDoubleSum a = *this;
    a.normalize();
    const bool negative = a.limb_[kLimbs - 1] < 0;
    if (negative) {
      for (auto& l : a.limb_) l = -l;
      a.normalize();
    }
    int h = kLimbs - 1;
    while (h > 0 && a.limb_[h] == 0) --h;
    if (h < 2) h = 2;
    // The top three limbs (at most 96 bits: the top limb stays below 2^32 for any sum of fewer than 2^14 x 2^1024)
    // and whether anything lies below. A result of more than 53 bits is at least 2^-1021, a normal double, so it is
    // rounded here once.
    const unsigned __int128 top = (static_cast<unsigned __int128>(a.limb_[h]) << 64) |
                                  (static_cast<unsigned __int128>(a.limb_[h - 1]) << 32) |
                                  static_cast<unsigned __int128>(a.limb_[h - 2]);
    bool sticky = false;
    for (int i = 0; i < h - 2; ++i) sticky = sticky || a.limb_[i] != 0;
    const int exponent = 32 * (h - 2) - 1074;
    const std::uint64_t high = static_cast<std::uint64_t>(top >> 64), low = static_cast<std::uint64_t>(top);
    const int bits = high ? 128 - std::countl_zero(high) : (low ? 64 - std::countl_zero(low) : 0);
    double r;
    if (bits <= 53) {
      r = std::ldexp(static_cast<double>(low), exponent);
    } else {
      const int shift = bits - 53;
      std::uint64_t mant = static_cast<std::uint64_t>(top >> shift);
      const unsigned __int128 rem = top & ((static_cast<unsigned __int128>(1) << shift) - 1);
      const unsigned __int128 half = static_cast<unsigned __int128>(1) << (shift - 1);
      if (rem > half || (rem == half && (sticky || (mant & 1u)))) ++mant;
      r = std::ldexp(static_cast<double>(mant), exponent + shift);
    }
    return negative ? -r : r;
  }

  // Appends the sum's bytes (normalized, so equal sums give equal bytes) / takes them back.
  void put(std::string& out) const {
    ExactDoubleSum a = *this;
    a.normalize();
    out.append(reinterpret_cast<const char*>(a.limb_.data()), sizeof a.limb_);
    for (const std::int64_t* c : {&a.pos_inf_, &a.neg_inf_, &a.nan_})
      out.append(reinterpret_cast<const char*>(c), sizeof *c);
  }
  static constexpr std::size_t kBytes = sizeof(std::int64_t) * (kLimbs + 3);
  // Returns false if fewer than kBytes bytes remain.
  bool take(std::string_view& in) {
    if (in.size() < kBytes) return false;
    std::memcpy(limb_.data(), in.data(), sizeof limb_);
    in.remove_prefix(sizeof limb_);
    for (std::int64_t* c : {&pos_inf_, &neg_inf_, &nan_}) {
      std::memcpy(c, in.data(), sizeof *c);
      in.remove_prefix(sizeof *c);
    }
    pending_ = 0;
    return true;
  }

 private:
  static constexpr std::int64_t kNormalizeEvery = std::int64_t{1} << 30;

  void add_special(double v) {
    if (std::isnan(v))
      ++nan_;
    else if (v > 0)
      ++pos_inf_;
    else
      ++neg_inf_;
  }

  // Limbs 0 .. kLimbs-2 into [0, 2^32), their carries moved up; the top limb keeps the sign.
  void normalize() {
    for (int i = 0; i + 1 < kLimbs; ++i) {
      const std::int64_t carry = limb_[i] >> 32;  // arithmetic shift: floor division by 2^32
      limb_[i] -= carry * (std::int64_t{1} << 32);
      limb_[i + 1] += carry;
    }
    pending_ = 0;
  }

  std::array<std::int64_t, kLimbs> limb_{};
  std::int64_t pending_ = 0;
  std::int64_t pos_inf_ = 0, neg_inf_ = 0, nan_ = 0;
};

}  // namespace orogen
