#pragma once
// printf's "%.{P}g" of a float (what an ostream of precision P writes, and std::to_chars with
// chars_format::general and precision P), several times faster than either: the text formats of big meshes
// (OBJ, ASCII PLY and STL) spend most of their time here.
//
// The float's exact value times 10^k (k <= 22: the power is exact in double) is split by an fma into the
// rounded product and its exact error, which is enough to round to an integer exactly (ties to even, as
// printf). Values the fast path does not cover (zero, |v| < 1e-12, large ones where k < 0, NaN, infinities)
// go to std::to_chars, which is exact.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace orogen {

// Writes the text at `out`, which has room for at least 48 characters; returns the end.
template <int P>
char* format_float_g(char* out, float value) {
  static_assert(P >= 1 && P <= 15);
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  static constexpr std::uint64_t kLow = [] {
    std::uint64_t r = 1;
    for (int i = 1; i < P; ++i) r *= 10;
    return r;
  }();
  static constexpr std::uint64_t kHigh = kLow * 10;
  const auto fallback = [&] { return std::to_chars(out, out + 48, value, std::chars_format::general, P).ptr; };
  const double a = std::fabs(static_cast<double>(value));
  if (!(a >= 1e-12 && a < 1e15)) return fallback();
  // The decimal exponent from the binary one: a in [2^b, 2^(b+1)) puts log10(a) in [b log10 2, (b+1) log10 2),
  // so the guess is exact or one short (raised below when the scaled value reaches 10^P).
  const int b = static_cast<int>((std::bit_cast<std::uint32_t>(value) >> 23) & 255) - 127;
  int e = (b * 78913) >> 18;  // floor(b log10 2) for |b| < 1000 (the shift floors negatives too)
  double p = 0.0, err = 0.0;
  const auto scale = [&](int exponent) {
    const int k = P - 1 - exponent;
    if (k < 0 || k > 22) return false;
    p = a * kPow10[k];
    err = std::fma(a, kPow10[k], -p);  // the product's exact rounding error
    return true;
  };
  if (!scale(e)) return fallback();
  if (p < static_cast<double>(kLow)) {
    if (!scale(--e)) return fallback();
  } else if (p >= static_cast<double>(kHigh)) {
    if (!scale(++e)) return fallback();
  }
  // Round p + err to an integer. frac and 0.5 are multiples of ulp(p) (p < 2^52), so a nonzero difference
  // outweighs err (at most half an ulp); at an exact half err decides, and with no error the tie goes to even.
  const double whole = static_cast<double>(static_cast<std::int64_t>(p));  // floor: p > 0
  const double d = (p - whole) - 0.5;
  std::uint64_t r = static_cast<std::uint64_t>(whole);
  if (d > 0 || (d == 0 && (err > 0 || (err == 0 && (r & 1))))) ++r;
  if (r == kHigh) r = kLow, ++e;
  if (r < kLow || r >= kHigh) return fallback();

  static constexpr char kPairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  char digits[P + 1];
  int i = P;
  for (; i >= 2; i -= 2, r /= 100) std::memcpy(digits + i - 2, kPairs + 2 * (r % 100), 2);
  if (i == 1) digits[0] = static_cast<char>('0' + r);
  int n = P;  // significant digits left after trailing zeros go
  while (n > 1 && digits[n - 1] == '0') --n;
  char* o = out;
  if (value < 0) *o++ = '-';
  if (e >= -4 && e < P) {
    if (e >= 0) {
      std::memcpy(o, digits, static_cast<std::size_t>(e) + 1);
      o += e + 1;
      if (n > e + 1) {
        *o++ = '.';
        std::memcpy(o, digits + e + 1, static_cast<std::size_t>(n - e - 1));
        o += n - e - 1;
      }
    } else {
      *o++ = '0';
      *o++ = '.';
      for (int i = 0; i < -e - 1; ++i) *o++ = '0';
      std::memcpy(o, digits, static_cast<std::size_t>(n));
      o += n;
    }
  } else {
    *o++ = digits[0];
    if (n > 1) {
      *o++ = '.';
      std::memcpy(o, digits + 1, static_cast<std::size_t>(n - 1));
      o += n - 1;
    }
    *o++ = 'e';
    *o++ = e < 0 ? '-' : '+';
    const int x = e < 0 ? -e : e;
    if (x >= 100) *o++ = static_cast<char>('0' + x / 100);
    *o++ = static_cast<char>('0' + x / 10 % 10);
    *o++ = static_cast<char>('0' + x % 10);
  }
  return o;
}

// The precision chosen at run time (the writers' 6, 9 and 10).
inline char* format_float_g(char* out, float value, int precision) {
  switch (precision) {
    case 6:
      return format_float_g<6>(out, value);
    case 9:
      return format_float_g<9>(out, value);
    case 10:
      return format_float_g<10>(out, value);
    default:
      return std::to_chars(out, out + 48, value, std::chars_format::general, precision).ptr;
  }
}

}  // namespace orogen
