#pragma once
// Blending two fields, optionally through a mask.
//
// Every mode computes a target m(a, b) and moves a towards it by the weight w = factor * mask:
//   out = a + (m(a, b) - a) * w
// lerp: m = b; add: m = a + b; screen: m = 1 - (1 - a)(1 - b) (for 0..1 masks: brightens, never exceeds 1);
// max: m = max(a, b). With w = 1 the modes give exactly b, a + b, screen(a, b), max(a, b); with w = 0, a.
#include <algorithm>

namespace orogen {

enum class BlendMode { Lerp, Add, Screen, Max };

inline double blend_value(BlendMode mode, double a, double b, double w) {
  double m = b;
  switch (mode) {
    case BlendMode::Lerp:
      m = b;
      break;
    case BlendMode::Add:
      m = a + b;
      break;
    case BlendMode::Screen:
      m = 1.0 - (1.0 - a) * (1.0 - b);
      break;
    case BlendMode::Max:
      m = std::max(a, b);
      break;
  }
  return w == 1.0 ? m : a + (m - a) * w;
}

}  // namespace orogen
