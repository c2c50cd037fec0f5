#pragma once
// Power: sign-preserving exponent about a pivot, out = pivot + scale * sign(t) * |t|^p with
// t = (h - pivot) / scale. With pivot 0 and scale 1 this is Weiss 2015's Eq 3, h <- sign(h)|h|^p (p = 1.5 there):
// p > 1 flattens values near the pivot and sharpens those far from it (lowlands flatter, peaks steeper),
// p < 1 does the opposite. Odd-symmetric about the pivot. `scale` sets which distance from the pivot is a
// fixed point (|t| = 1), so the operation is unit-aware: heights in metres, scale in metres.
#include <cmath>

namespace orogen {

struct PowerParams {
  double exponent = 1.5;
  double pivot = 0.0;  // m
  double scale = 1.0;  // m, > 0
};

inline double power_value(double h, const PowerParams& p) {
  const double t = (h - p.pivot) / p.scale;
  return p.pivot + p.scale * std::copysign(std::pow(std::abs(t), p.exponent), t);
}

}  // namespace orogen
