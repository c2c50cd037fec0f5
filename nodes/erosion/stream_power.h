#pragma once
// Stream-power landscape evolution: dz/dt = U - K A^m S^n + D laplacian(z), the detachment-limited model of
// fluvial incision (Howard 1994; Whipple and Tucker 1999), solved with the implicit O(N) scheme of Braun and
// Willett 2013 ("A very efficient O(n), implicit and parallel method to solve the stream power equation
// governing fluvial incision and landscape evolution") for n = 1 and a per-node Newton iteration for n != 1.
// Each step: uplift, explicit hillslope diffusion in stable sub-steps, routing: D8 steepest-descent
// receivers, closed depressions crossed through the basin graph of Cordonnier, Bovy & Braun 2019
// (nodes/hydrology/basin_graph.h; only the pits' basins are rerouted, nothing beyond D8 and the stack when
// there is no pit) and filled with sediment to their spill level (the deposition map records it), the stack
// order and the drainage area, then the implicit incision sweep from the outlets upstream, one outlet tree
// per task (results identical for any thread count). Depressions::PriorityFlood instead fills the whole grid
// by Priority-Flood every step (nodes/hydrology/flow_routing.h).
//
// Units: K in m^(1-2m)/yr, U in m/yr, D in m^2/yr, time in years, lengths in metres. Border cells are base
// level (held fixed); cells below sea level after the step's uplift are outlets too (they take no fluvial
// erosion; uplift may raise them into land).
#include <cstdint>
#include <vector>

#include "nodes/erosion/erosion_common.h"

namespace orogen::erosion {

struct StreamPowerParams {
  double k = 2e-5;            // erodibility K, m^(1-2m)/yr
  double m = 0.45;            // drainage-area exponent
  double n = 1.0;             // slope exponent
  double uplift = 1e-3;       // m/yr (times the uplift field if given)
  double diffusion = 0.01;    // hillslope diffusivity D, m^2/yr
  double dt = 10000.0;        // years per step
  double duration = 1e6;      // years
  double sea_level = -1e9;    // metres: cells below are base level
  double channel_area = 0.0;  // m^2: fluvial incision only where the drainage area reaches this (0: everywhere)
  // How closed depressions are crossed each step (library option; the node uses the default). Both fill a
  // depression with sediment up to its spill level and route its water over the pass to the outlet.
  enum class Depressions {
    BasinGraph,     // local D8, then only the pits' basins rerouted through the basin graph's minimum spanning
                    // tree (Cordonnier, Bovy & Braun 2019; nodes/hydrology/basin_graph.h): no priority queue,
                    // nothing beyond one D8 pass and the stack when the surface has no pit; trees in parallel
    PriorityFlood,  // Priority-Flood+epsilon fill of the whole grid every step, then D8 (Barnes et al. 2014)
  };
  Depressions depressions = Depressions::BasinGraph;
};

struct StreamPowerStats {
  int steps = 0;
  double max_change_last_step = 0.0;   // m/yr: largest |dz/dt| of the last step (0 at steady state)
  double mean_change_last_step = 0.0;  // m/yr: mean |dz/dt| over the cells that are not base level
};

// `uplift`: factor (>= 0) on p.uplift per cell; `mask` (0..1) scales K and D per cell. Either may be null.
// `outlets` (optional, one byte per cell) replaces the default base level (border and sea cells).
ErosionMaps stream_power(const Heightfield& in, const StreamPowerParams& p, const Heightfield* uplift = nullptr,
                         const Heightfield* mask = nullptr, const ExecContext* ctx = nullptr,
                         StreamPowerStats* stats = nullptr, const std::vector<unsigned char>* outlets = nullptr,
                         std::shared_ptr<Heightfield>* accumulation = nullptr);

}  // namespace orogen::erosion
