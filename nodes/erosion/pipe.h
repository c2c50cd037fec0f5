#pragma once
// Shallow-water hydraulic erosion on a grid of virtual pipes (Mei, Decaudin and Hu 2007, "Fast hydraulic
// erosion simulation and visualization on GPU"; O'Brien and Hodgins 1995 for the pipe model).
//
// Fields: terrain b, water depth d, suspended sediment s (a height, m), outflow fluxes f (L, R, B, T; m^3/s)
// and velocity (u, v; m/s). Per step: rain; fluxes accelerated by the head difference to each neighbour
// through a pipe whose cross-section is the cell width times the upstream depth (the shallow-water wave);
// outflow scaled so no cell's water goes negative; water volume change; velocity from the mean fluxes;
// sediment capacity C = Kc x sin(tilt) x |v| x depth (tilt clamped to [0.005, 0.5] as in the seed's model;
// the depth factor, absent in Mei et al., keeps thin films from carrying metres of sediment),
// dissolution Ks (C - s) or deposition Kd (s - C) per second; evaporation by the temperature.
//
// Sediment moves with the water through the same pipes (the concentration s/d times the volume leaving
// through each pipe) rather than by a backward semi-Lagrangian lookup: the same transfers, but each is
// computed once and subtracted and added exactly, so terrain + suspended sediment is conserved per step up
// to float rounding, except what leaves through the domain border or into sinks (cells under sea level),
// which is counted.
//
// Rain falls on land only: a sink (a cell under sea level) would lose it in the same step. In Drops mode each
// cell catches a drop of rate / drop_chance with probability moisture x drop_chance x dt per step.
//
// Time: the step follows a CFL condition on the cell size, dt = courant x spacing / sqrt(g x max depth), so a finer
// grid takes more, smaller steps of the same physical duration (seconds). Every pass is a gather over rows,
// bit-identical for any thread count; across the tiles of a tiled or distributed build too (pipe_step.h,
// pipe_across_tiles.cpp).
#include <cstdint>

#include "nodes/erosion/erosion_common.h"

namespace orogen::erosion {

enum class RainMode { Uniform, Drops };

struct PipeParams {
  double duration = 1800.0;  // seconds of simulated time
  double rain_rate = 50.0;   // mm/h (scaled by the rainfall field if given)
  RainMode rain_mode = RainMode::Uniform;
  double drop_chance = 0.1;    // Drops: per cell and second, scaled by the moisture field (0..1)
  double capacity = 1.0;       // Kc, s/m: capacity (m of sediment) per (sin tilt x speed m/s x depth m)
  double dissolving = 0.1;     // Ks, 1/s
  double depositing = 0.1;     // Kd, 1/s
  double evaporation = 0.001;  // Ke, 1/s at temperature factor 1
  double gravity = 9.81;       // m/s^2
  double courant = 0.25;       // CFL number, (0, 0.5]
  double depth_scale = 0.05;   // metres: depth used for the CFL step before water gathers
  double layer_depth = 0.0;    // metres: soil gets twice as hard every layer_depth eroded (0: off)
  double sea_level = -1e9;     // metres: cells below are sinks
  std::uint64_t seed = 0;      // Drops mode
};

struct PipeStats {
  int steps = 0;
  double dt = 0.0;                      // last step, seconds
  double sediment_out = 0.0;            // m^3 of sediment that left through the border or into sinks
  double water_out = 0.0;               // m^3 of water that left through the border or into sinks
  double max_conservation_error = 0.0;  // max over steps of |change of (b + s) volume + sediment_out step| (m^3)
  double total_volume = 0.0;            // initial sum of b over the grid x cell area (m^3), for scale
};

struct PipeMaps : ErosionMaps {
  std::shared_ptr<Heightfield> water;     // water depth at the end, m
  std::shared_ptr<Heightfield> velocity;  // speed at the end, m/s
};

// Optional fields (null if absent, on in.domain): mask (0..1) scales dissolution and deposition; rainfall
// (mm/h) replaces rain_rate; moisture (0..1) drives the drop probability in Drops mode; temperature (a
// factor, 1 = nominal) scales evaporation; hardness (0..1) slows dissolution by (1 - hardness).
// What tests ask of a run beyond its result.
struct PipeChecks {
  bool conservation = false;  // measure the per-step conservation error (extra passes)
  bool every_cell = false;    // compute every cell of every row, the sea far from land too (the sweep skips it)
  int chunk_rows = 0;         // rows per chunk of the sweep (0: the default); no result depends on it
};
PipeMaps pipe_erosion(const Heightfield& in, const PipeParams& p, const Heightfield* mask = nullptr,
                      const Heightfield* rainfall = nullptr, const Heightfield* moisture = nullptr,
                      const Heightfield* temperature = nullptr, const Heightfield* hardness = nullptr,
                      const ExecContext* ctx = nullptr, PipeStats* stats = nullptr, PipeChecks checks = {});

}  // namespace orogen::erosion
