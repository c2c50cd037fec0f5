#pragma once
// Flow direction, accumulation, flow map, wetness and watersheds of a heightfield (nodes FlowDirection,
// FlowAccumulation, Watersheds), over the routing core (flow_routing.h).
#include <memory>
#include <span>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

struct AccumulationParams {
  FlowMethod method = FlowMethod::D8;
  double exponent = 1.1;       // MFD
  bool fill = true;            // fill depressions (epsilon) before routing
  double flow_min_area = 0.0;  // m^2 mapped to 0 in the flow map (0: one cell)
  double flow_max_area = 0.0;  // m^2 mapped to 1 (0: the largest accumulation)
  double min_slope = 1e-3;     // tan beta floor of the wetness index
  bool flow_map = true;        // compute the flow map (false: left null)
  bool wetness = true;         // compute the wetness index and the slope behind it (false: left null)
};

struct AccumulationResult {
  std::shared_ptr<Heightfield> accumulation;  // m^2 (rainfall-weighted)
  std::shared_ptr<Heightfield> flow;          // 0..1
  std::shared_ptr<Heightfield> wetness;       // ln(a / tan beta), a in m
};

// `rainfall` (optional, same domain): relative weight per cell, 1 = nominal. D8 without rainfall: the number of
// cells upstream times the cell area (d8_area), one product per cell, so the tiles of a tiled or distributed build
// compute the same (nodes/hydrology/flow_across_tiles.cpp); every other case sums shares in a fixed order
// (nodes/hydrology/flow_shares.h), which tiles reproduce too.
AccumulationResult flow_accumulation(const Heightfield& in, const Heightfield* rainfall, const AccumulationParams& p,
                                     const ExecContext* ctx = nullptr);

// The normalised log flow map: ln(acc / lo) / ln(hi / lo) clamped to [0, 1].
float flow_map_value(double acc, double lo, double hi);
// The topographic wetness index ln(a / tan beta) of a cell with accumulation `acc` (m^2), contour `width` (m) and
// steepest slope `slope`, floored at `min_slope`.
float wetness_value(double acc, double width, float slope, double min_slope);

struct DirectionResult {
  std::shared_ptr<Heightfield> angle;   // degrees counter-clockwise from +x in [0, 360), -1 where nothing drains
  std::shared_ptr<Heightfield> dx, dy;  // unit flow vector (0 where nothing drains)
  std::shared_ptr<Heightfield> slope;   // tan beta of the steepest descent
};

// Which of flow_direction's maps to compute; the others are left null.
struct DirectionMaps {
  bool angle = true, vector = true, slope = true;
};

DirectionResult flow_direction(const Heightfield& in, FlowMethod method, double exponent, bool fill,
                               const ExecContext* ctx = nullptr, DirectionMaps maps = {});
// The maps of `maps` that are set (all of one size) from the routed heights `z` of grid `g`, for the window of `g`
// whose first cell is `first`: each map's value is a function of the cell's 3 x 3 heights alone, so a tile with a
// one-sample ring around it computes what the whole domain does (nodes/hydrology/flow_across_tiles.cpp).
void direction_maps(const FlowGrid& g, std::span<const float> z, glm::ivec2 first, const RoutingOptions& opt,
                    DirectionResult& maps, const ExecContext* ctx = nullptr);

struct WatershedResult {
  std::shared_ptr<Heightfield> id;    // 1..n by decreasing area; 0 for basins under the minimum area
  std::shared_ptr<Heightfield> area;  // area of the cell's basin, m^2
  int basins = 0;
};

WatershedResult watersheds(const Heightfield& in, bool fill, double min_area, const ExecContext* ctx = nullptr);

}  // namespace orogen::hydrology
