#pragma once
// RiverExtract: channels where the contributing area exceeds a threshold, as polylines per reach with
// discharge, Strahler order and hydraulic-geometry width, plus a raster river mask drawn with that width.
#include <functional>
#include <memory>
#include <vector>

#include "graph/curves.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/hydrology/channels.h"

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
// one sample: max over segments, in [0, 1]. `whole`: the domain the river network lies on, when `mask` is a part of
// it (a tile): half-widths are capped at its diagonal, so each sample is covered as on the whole domain.
void draw_curves(const Curves& curves, Heightfield& mask, const Domain* whole = nullptr);

// What the curves of a channel cell need: its position, its height on the filled terrain (m), its contributing area
// (m^2), and whether it lies in a lake (a filled depression).
struct RiverCell {
  double x = 0.0, y = 0.0;
  float z = 0.0f;
  double area = 0.0;
  bool lake = false;
};

// The curves of a channel network's reaches (extract_reaches: downstream first, cells upstream to downstream, by
// whatever cell numbering `cell` reads): cut at lakes when p.split_at_lakes, smoothed, with their attributes. The
// part of extract_rivers after the routing, shared with RiverExtract across tiles.
std::shared_ptr<Curves> reach_curves(const std::vector<Reach>& reaches,
                                     const std::function<RiverCell(std::int32_t)>& cell, const RiverParams& p);

}  // namespace orogen::hydrology
