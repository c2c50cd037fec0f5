#pragma once
// RiverExtract: channels where the contributing area exceeds a threshold, as polylines per reach with
// discharge, Strahler order and hydraulic-geometry width, plus a raster river mask drawn with that width.
#include <memory>

#include "graph/curves.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen::hydrology {

struct RiverParams {
  double threshold = 1e5;          // m^2 of (rainfall-weighted) contributing area that starts a channel
  double runoff = 10.0;            // mm/h: discharge Q = area * runoff
  double width_coefficient = 4.0;  // k of w = k * Q^b (w in m, Q in m^3/s)
  double width_exponent = 0.5;     // b
  int smoothing = 2;               // Chaikin corner-cutting passes (ends kept)
  bool split_at_lakes = true;      // no polyline across filled depressions: a reach entering a lake ends at
                                   // its shore (parent: the reach leaving the lake), the outflow starts at the
                                   // lake's last cell
};

struct RiverResult {
  std::shared_ptr<Curves> curves;
  std::shared_ptr<Heightfield> mask;  // channel coverage in [0, 1]
};

RiverResult extract_rivers(const Heightfield& in, const Heightfield* rainfall, const RiverParams& p,
                           const ExecContext* ctx = nullptr);

// Coverage of capsules along every curve (radius width / 2, interpolated along segments), anti-aliased over
// one sample: max over segments, in [0, 1].
void draw_curves(const Curves& curves, Heightfield& mask);

}  // namespace orogen::hydrology
