#pragma once
// WaterFlow: rain redistributed over the terrain until it settles (after Long 2016, section 3.3, corrected:
// water moves on the water surface and never uphill).
#include <memory>
#include <string>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen::hydrology {

struct WaterFlowParams {
  double rainfall = 50.0;      // mm, when no rainfall field is given
  double infiltration = 10.0;  // mm soaked into the soil before any flow
  double threshold = 1e-3;     // stop when an iteration moves less than this fraction of all water moved so far
  int max_iterations = 1000;
};

struct WaterFlowResult {
  std::shared_ptr<Heightfield> depth;                          // m
  std::shared_ptr<Heightfield> flux;                           // m^3 that left each cell over the run
  double rain = 0.0, stored = 0.0, border = 0.0, sinks = 0.0;  // m^3: initial water, left on the terrain,
                                                               // drained at the border, drained in sinks
  int iterations = 0;
  std::string json() const;
};

// `rainfall` (mm per cell) and `sinks` (cells > 0.5 drain) are optional and must lie on `in`'s grid (the node resamples
// them onto it, nodes/common/match_domain.h).
WaterFlowResult water_flow(const Heightfield& in, const Heightfield* rainfall, const Heightfield* sinks,
                           const WaterFlowParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen::hydrology
