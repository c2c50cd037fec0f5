#pragma once
// One WaterFlow iteration on a rectangular grid of samples: the whole domain (nodes/hydrology/water_flow.cpp) or a
// tile grown by a halo (nodes/hydrology/water_flow_across_tiles.cpp). Both run this code, so a sample computed from
// the same neighborhood gets the same bits in either.
//
// An iteration is two passes: the spread (each wet cell's outflow and its share per unit of drop, from the water
// surface within 1 sample) and the gather (each cell's new depth from what its neighbors send, from their spread:
// the water within 2 samples), then the drains empty. A neighbor outside the grid is outside the domain: a tile's
// grid stops at the domain's edge, and its cells next to the grid's inner edge are never read as results.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/common/exact_double_sum.h"

namespace orogen::hydrology {

enum WaterDrain : std::uint8_t { kNoDrain = 0, kBorderDrain = 1, kSinkDrain = 2 };

struct WaterFlowGrid {
  int nx = 0, ny = 0;
  double area = 1.0;                // m^2 per cell
  const float* z = nullptr;         // terrain height, m (nx x ny, row after row)
  std::vector<double> w, next;      // water depth, m; the next iteration's
  std::vector<double> out, scale;   // this iteration's outflow (m) and outflow per metre of drop
  std::vector<double> flux;         // m^3 that left each cell so far
  std::vector<std::uint8_t> drain;  // WaterDrain

  WaterFlowGrid(int width, int height, double cell_area, const float* heights);
  std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * nx + static_cast<std::size_t>(i); }
};

// The initial depth (m) of `rain_mm` of rain less `infiltration_mm`.
inline double water_initial_depth(double rain_mm, double infiltration_mm) {
  return (rain_mm - infiltration_mm > 0.0 ? rain_mm - infiltration_mm : 0.0) / 1000.0;
}

// Whether the run stops after an iteration that moved `moved` (m) of `total` moved so far (this one included).
inline bool water_flow_settled(double moved, double total, double threshold) { return moved < threshold * total; }

// The spread of row j over columns [x0, x1); adds the row's outflow on columns [s0, s1) to `moved` (m).
void water_spread_row(WaterFlowGrid& g, int j, int x0, int x1, int s0, int s1, ExactDoubleSum& moved);
// The gather of row j over columns [x0, x1) into `next`, and the outflow into `flux`.
void water_gather_row(WaterFlowGrid& g, int j, int x0, int x1);

}  // namespace orogen::hydrology
