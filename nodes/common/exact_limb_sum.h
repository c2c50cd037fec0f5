#pragma once
// The fixed-point number that ExactFloatSum and ExactDoubleSum (exact_float_sum.h, exact_double_sum.h) add into: Limbs
// signed 64-bit limbs of 32 bits each, limb i worth 2^(32 i - Scale), with their carries deferred (each limb takes in
// 2^31 additions of at most 32 bits before it must be normalized; count_addition() normalizes every 2^30), the top limb
// keeping the sign; infinities and NaN counted apart. What depends on the type added (how a value splits into limbs)
// is the derived classes'; the sum of sums, the rounding to a double and the bytes are here.
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

namespace orogen {

template <int Limbs, int Scale>
class ExactLimbSum {
 public:
  static constexpr int kLimbs = Limbs;

  // The exact sum rounded to the nearest double (ties to even; beyond the largest double, infinity).
  double value() const {
    if (nan_ || (pos_inf_ && neg_inf_)) return std::numeric_limits<double>::quiet_NaN();
    if (pos_inf_) return std::numeric_limits<double>::infinity();
    if (neg_inf_) return -std::numeric_limits<double>::infinity();
    ExactLimbSum a = *this;
    a.normalize();
    const bool negative = a.limb_[kLimbs - 1] < 0;
    if (negative) {
      for (auto& l : a.limb_) l = -l;
      a.normalize();
    }
    int h = kLimbs - 1;
    while (h > 0 && a.limb_[h] == 0) --h;
    if (h < 2) h = 2;
    // The top three limbs (at most 96 bits: the top limb stays below 2^32 for the sums the derived classes allow)
    // and whether anything lies below. A result of more than 53 bits is a normal double, so it is rounded here once.
    const unsigned __int128 top = (static_cast<unsigned __int128>(a.limb_[h]) << 64) |
                                  (static_cast<unsigned __int128>(a.limb_[h - 1]) << 32) |
                                  static_cast<unsigned __int128>(a.limb_[h - 2]);
    bool sticky = false;
    for (int i = 0; i < h - 2; ++i) sticky = sticky || a.limb_[i] != 0;
    const int exponent = 32 * (h - 2) - Scale;
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
    ExactLimbSum a = *this;
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

 protected:
  // Adds another sum of the same kind.
  void add_sum(const ExactLimbSum& o) {
    ExactLimbSum b = o;
    b.normalize();
    normalize();
    for (int i = 0; i < kLimbs; ++i) limb_[i] += b.limb_[i];
    pos_inf_ += b.pos_inf_, neg_inf_ += b.neg_inf_, nan_ += b.nan_;
    normalize();
  }

  // Adds (or with `negative`, subtracts) the 32-bit parts of a magnitude to the limbs from `first` up.
  void add_parts(std::size_t first, const std::int64_t* parts, std::size_t count, bool negative) {
    const std::int64_t neg = negative ? -1 : 0;
    for (std::size_t k = 0; k < count; ++k) limb_[first + k] += (parts[k] ^ neg) - neg;
    if (++pending_ == kNormalizeEvery) normalize();
  }

  void add_special(double v) {
    if (std::isnan(v))
      ++nan_;
    else if (v > 0)
      ++pos_inf_;
    else
      ++neg_inf_;
  }

  std::array<std::int64_t, Limbs> limb_{};

 private:
  static constexpr std::int64_t kNormalizeEvery = std::int64_t{1} << 30;

  // Limbs 0 .. kLimbs-2 into [0, 2^32), their carries moved up; the top limb keeps the sign.
  void normalize() {
    for (int i = 0; i + 1 < kLimbs; ++i) {
      const std::int64_t carry = limb_[i] >> 32;  // arithmetic shift: floor division by 2^32
      limb_[i] -= carry * (std::int64_t{1} << 32);
      limb_[i + 1] += carry;
    }
    pending_ = 0;
  }

  std::int64_t pending_ = 0;
  std::int64_t pos_inf_ = 0, neg_inf_ = 0, nan_ = 0;
};

}  // namespace orogen
