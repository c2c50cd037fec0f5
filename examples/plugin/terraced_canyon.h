#pragma once
// A terraced canyon carved into a heightfield along a meandering center line: the algorithm alone, callable
// and testable without a graph (terraced_canyon.cpp declares the node around it).
#include <orogen/node.h>

namespace canyon {

struct CanyonParams {
  double center_y = 0.0;      // m: the center line's mean y
  double amplitude = 100.0;   // m: how far the center line meanders to each side
  double wavelength = 800.0;  // m: length of one meander along x
  double width = 200.0;       // m: rim to rim, across the center line
  double depth = 60.0;        // m: cut at the center line
  double terrace = 10.0;      // m: height of one terrace step of the walls; 0 for smooth walls
  double floor = 0.2;         // fraction of the half width that is flat floor
};

// The cut (m, >= 0) at world position (x, y): depth on the floor, falling along a smoothstep wall to 0 at
// the rim, rounded up to whole terrace steps (so every wall is a staircase of flat benches).
double canyon_cut(double x, double y, const CanyonParams& p);

// `in` with the canyon cut out of it, sample by sample (point-wise: a tile gives the same samples).
orogen::HeightfieldPtr carve_canyon(const orogen::Heightfield& in, const CanyonParams& p,
                                    const orogen::ExecContext* ctx = nullptr);

}  // namespace canyon
