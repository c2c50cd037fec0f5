#pragma once
// The exact sum of floats, rounded once to the nearest double: the same whatever the order of addition, so sums
// split over threads, tiles or ranks in any way agree bit for bit (KMeansClusters across tiles).
//
// Every finite float is an integer multiple of 2^-149 below 2^128: a fixed-point number of 32-bit limbs from 2^-149
// up holds it exactly. A float's 24-bit significand, shifted within its limb, spans at most two limbs; each limb is
// kept in an int64 with its carries deferred, so a limb takes in 2^31 floats before it must be normalized (add()
// normalizes every 2^30 additions). Infinities and NaN are counted apart and give the IEEE sum's infinity or NaN.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

namespace orogen {

class ExactFloatSum {
 public:
  static constexpr int kLimbs = 10;  // 9 limbs span 2^-149 .. 2^139; the tenth takes carries and the sign

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
    const std::int64_t neg = -static_cast<std::int64_t>(u >> 31);  // 0 or -1
    const std::int64_t lo = static_cast<std::int64_t>(w & 0xFFFFFFFFu), hi = static_cast<std::int64_t>(w >> 32);
    limb_[s >> 5] += (lo ^ neg) - neg;
    limb_[(s >> 5) + 1] += (hi ^ neg) - neg;
    if (++pending_ == kNormalizeEvery) normalize();
  }

  // Adds a double that is itself an exact sum of floats: a multiple of 2^-149 below 2^159 in magnitude (FloatBuckets'
  // sums stay below 2^142, those of up to 2^count_bits floats at or above exact_double_floor below 2^140). Its 53-bit
  // significand, shifted within its lowest limb, spans limbs i .. i+2, and i + 2 <= kLimbs - 1 holds for |d| < 2^159
  // only; throws std::out_of_range above.
  void add_exact(double d) {
    if (!std::isfinite(d)) {
      add_special(static_cast<float>(d));
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
    const std::int64_t neg = d < 0.0 ? -1 : 0;
    const std::size_t i = static_cast<std::size_t>(shift >> 5);
    const std::int64_t parts[3] = {static_cast<std::int64_t>(static_cast<std::uint64_t>(w) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 32) & 0xFFFFFFFFu),
                                   static_cast<std::int64_t>(static_cast<std::uint64_t>(w >> 64))};
    for (std::size_t k = 0; k < 3; ++k) limb_[i + k] += (parts[k] ^ neg) - neg;
    if (++pending_ == kNormalizeEvery) normalize();
  }

  void add(const ExactFloatSum& o) {
    ExactFloatSum b = o;
    b.normalize();
    normalize();
    for (int i = 0; i < kLimbs; ++i) limb_[i] += b.limb_[i];
    pos_inf_ += b.pos_inf_, neg_inf_ += b.neg_inf_, nan_ += b.nan_;
    normalize();
  }

  // The exact sum rounded to the nearest double (ties to even).
  double value() const {
    if (nan_ || (pos_inf_ && neg_inf_)) return std::numeric_limits<double>::quiet_NaN();
    if (pos_inf_) return std::numeric_limits<double>::infinity();
    if (neg_inf_) return -std::numeric_limits<double>::infinity();
    ExactFloatSum a = *this;
    a.normalize();
    const bool negative = a.limb_[kLimbs - 1] < 0;
    if (negative) {
      for (auto& l : a.limb_) l = -l;
      a.normalize();
    }
    int h = kLimbs - 1;
    while (h > 0 && a.limb_[h] == 0) --h;
    if (h < 2) h = 2;
    // The top three limbs (at most 96 bits: the top limb stays below 2^32 here) and whether anything lies below.
    const unsigned __int128 top = (static_cast<unsigned __int128>(a.limb_[h]) << 64) |
                                  (static_cast<unsigned __int128>(a.limb_[h - 1]) << 32) |
                                  static_cast<unsigned __int128>(a.limb_[h - 2]);
    bool sticky = false;
    for (int i = 0; i < h - 2; ++i) sticky = sticky || a.limb_[i] != 0;
    const int exponent = 32 * (h - 2) - 149;
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
    ExactFloatSum a = *this;
    a.normalize();
    out.append(reinterpret_cast<const char*>(a.limb_.data()), sizeof a.limb_);
    out.append(reinterpret_cast<const char*>(&a.pos_inf_), sizeof a.pos_inf_);
    out.append(reinterpret_cast<const char*>(&a.neg_inf_), sizeof a.neg_inf_);
    out.append(reinterpret_cast<const char*>(&a.nan_), sizeof a.nan_);
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

  void add_special(float v) {
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
