#pragma once
// A river network grown as a tree of quadratic Bézier curves before any terrain exists (S. Ekman et al.
// 2016, SeamScape, §2.2 and §3.6, after Génevaux et al. 2013), and its carving into a terrain.
//
// Growth (river_network):
//  - outlets (roots): `outlets` points on the rectangle's border, or on the coastline of a land mask (land
//    samples next to water); inner points: Poisson-disk points at `density` per km^2 (on land with a mask);
//  - the pool starts with the outlets. Repeatedly: pick a pool point at random (counter-based hash), connect it
//    to the nearest unused inner point within `max_length` whose curve crosses no existing curve (and, with a
//    mask, stays on land); the new point joins the pool. A pool point with no such candidate leaves the pool.
//    Inner points never connected are discarded;
//  - curves: quadratic Bézier B(t) = (1-t)^2 P0 + 2(1-t)t P1 + t^2 P2 (SeamScape prints (1 - t^2): fixed) from the
//    downstream point P0 to the new point P2. The first child of a point that lies within 75 degrees of the
//    incoming direction continues it: P1 = P0 + tangent * |P2 - P0| / 2, so tangents are continuous at the
//    join; other branches (and root curves) bend by a hashed offset of the chord's midpoint. Crossing tests use
//    the same sampled polylines as the output, so the output never crosses;
//  - sizes: a leaf has size 1, any other point the sum of its children's sizes;
//  - heights: roots h = 0, slope d = base_slope; child c of p: d_c = d_p - 4 (s_c/s_p)(s_c/s_p - 1) w and
//    h_c = h_p + |c - p| d_c (SeamScape §2.2.3 with d measured in m/m and w = slope_weight), so heights rise upstream.
//
// Output: one curve per tree edge, from the upstream point to the downstream one (z falling linearly in t from
// h_c to h_p), `samples` segments each; parent = the curve leaving the downstream point (-1 at an outlet).
// Per vertex: width = river_width * size^width_exponent (m), attributes size, slope (d of the edge).
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>

#include "graph/curves.h"
#include "graph/heightfield.h"

namespace orogen {
class ExecContext;
}

namespace orogen::island {

struct RiverNetworkParams {
  glm::dvec2 min_corner{0.0, 0.0};  // m
  glm::dvec2 size{4096.0, 4096.0};  // m
  int outlets = 5;
  double density = 40.0;       // inner points per km^2
  double max_length = 400.0;   // m, longest segment
  double base_slope = 0.02;    // m/m at the outlets
  double slope_weight = 0.02;  // w, m/m
  double river_width = 3.0;    // m, width of a size-1 river
  double width_exponent = 0.5;
  double meander = 0.25;  // offset of a free control point, fraction of the chord
  int samples = 8;        // polyline segments per Bézier curve
  std::uint64_t seed = 0;
};

// `mask` (optional): land where >= 0.5; outlets on its coastline and inner points on land.
Curves river_network(const RiverNetworkParams& p, const Heightfield* mask = nullptr, const ExecContext* ctx = nullptr);

// Carving (CarveRivers): within `radius` of the curves the terrain blends toward the river height with the
// smoothstep weight w = s(1 - d/r), s(t) = t^2 (3 - 2t) (SeamScape's printed weight goes negative for r > 1.5 and
// uses r - d unnormalised: fixed); the river height is SeamScape's blend (1 - d0/d1) z0 + (d0/d1) mean, with z0 the
// nearest curve's height at its nearest point, d0 <= d1 the distances to the nearest two curves and mean the
// w-weighted mean over the curves within the radius (SeamScape prints the ratio on the other term, which would put
// the mean, not the curve's own height, on the curve). Inside the channel (d < width/2) the bed is lowered by
// depth_ratio * width * (1 - (2d/width)^2). Works with any curves with per-vertex width and z (RiverNetwork,
// RiverExtract, VoronoiIsland rivers).
struct CarveParams {
  double radius = 150.0;     // m
  double depth_ratio = 0.1;  // channel depth per metre of width
  double strength = 1.0;     // 0..1, scales the blend weight
};

struct CarveResult {
  std::shared_ptr<Heightfield> terrain;  // carved heights, m
  std::shared_ptr<Heightfield> mask;     // channel coverage in [0, 1]
};

CarveResult carve_rivers(const Heightfield& in, const Curves& rivers, const CarveParams& p,
                         const ExecContext* ctx = nullptr);

}  // namespace orogen::island
