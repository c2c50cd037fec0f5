#pragma once
// One Jacobi iteration of thermal erosion (nodes/erosion/thermal.h) over a window of padded grids: the kernel of
// both the whole-domain run (thermal.cpp) and the run across tiles (thermal_across_tiles.cpp). Every sample's
// update is the same expression of the heights within 2 samples whatever the window, so a tile that holds the
// right 2-sample halo computes its samples bit for bit as the whole-domain run does.
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/erosion/thermal.h"

namespace orogen::erosion {

// Height outside the domain: never lower than a cell, so nothing flows out of the grid.
inline constexpr float kThermalWall = 1e30f;

// What every iteration of a run uses.
struct ThermalStencil {
  double tan_t = 0.0;  // tangent of the talus angle
  float tal[8] = {};   // talus height difference toward each neighbor (tan_t x distance)
  int iterations = 0;  // ceil(2 x travel_distance / spacing)
};

// The stencil of `p` on a grid of `spacing`, with `resolution` samples: the iteration count is checked against
// the per-node limits (a NodeError says which parameter to change).
ThermalStencil thermal_stencil(const ThermalParams& p, glm::dvec2 spacing, glm::ivec2 resolution);

// A cell's movement rate (strength x mask; mask 1 when absent) and its talus tangent (hardness steepens it).
float thermal_rate(const ThermalParams& p, float mask);
float thermal_tangent(const ThermalParams& p, float hardness);

// A half-open window [x0, x1) x [y0, y1) of grid cells.
struct GridWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Row-major grids of `pitch` x `rows` cells, a domain's samples surrounded by walls (z = kThermalWall, rate 0).
struct ThermalGrids {
  int pitch = 0;
  std::vector<float> z, z2;     // heights now and after the iteration
  std::vector<float> rate;      // strength x mask
  std::vector<float> tan_cell;  // per-cell talus tangent; empty without hardness
  std::vector<float> ratio;     // pass 1: each cell's outflow ratio
  std::vector<float> moved;     // material each cell sent, summed over the iterations
  ThermalGrids(int pitch, int rows, bool hardness);
  std::size_t at(int x, int y) const { return static_cast<std::size_t>(y) * pitch + static_cast<std::size_t>(x); }
};

// One iteration: pass 1 gives the cells of `ratios` their outflow ratio (from z within 1 cell), pass 2 gives the
// cells of `heights` their new height (from z and ratio within 1 cell) and adds what they sent to `moved`; then z
// holds the new heights (outside `heights`, what z2 held). `ratios` must hold `heights` grown by 1 cell wherever
// that is not a wall, and z must be right within 2 cells of `heights`. Returns the largest amount any cell of
// `heights` sent or received.
float thermal_iteration(ThermalGrids& g, const ThermalStencil& s, GridWindow heights, GridWindow ratios);

// The `flow` output of a cell: what it sent over the run relative to the most any cell of the domain sent.
inline float thermal_flow(float moved, float most_moved) { return most_moved > 0.0f ? moved / most_moved : 0.0f; }

}  // namespace orogen::erosion
