#pragma once
// Thermal erosion (talus slumping): material above the angle of repose slides to lower neighbours until
// every slope is at most the talus angle (Musgrave, Kolb and Mace 1989, "The synthesis and rendering of
// eroded fractal terrains"; Olsen 2004, "Realtime procedural terrain generation").
//
// World units: the talus is an angle, compared with height differences over the true distance to each of
// the 8 neighbours, so the same angle gives the same slopes at any resolution. Each iteration is a Jacobi
// step in two passes (every cell's outflow from the current heights, then every cell gathers what its
// neighbours send it), so the result is bit-identical for any thread count, and each transfer is computed by
// the same expression on both sides (volume is conserved up to float rounding of the heights).
#include "nodes/erosion/erosion_common.h"

namespace orogen::erosion {

struct ThermalParams {
  double talus_angle = 35.0;       // degrees, (0, 89]: angle of repose
  double strength = 0.5;           // fraction of the excess over the talus moved per iteration, (0, 1]
  double travel_distance = 500.0;  // metres: how far material may travel; iterations = ceil(2 x distance / spacing)
  double tolerance = 1e-4;         // metres: stop early when no cell moves more than this in an iteration
};

// `mask` (0..1) scales the movement per cell; `hardness` (0..1) raises the talus angle of a cell toward 90
// degrees (1: a cliff that never slumps). Either may be null; both lie on in.domain.
ErosionMaps thermal_erosion(const Heightfield& in, const ThermalParams& p, const Heightfield* mask = nullptr,
                            const Heightfield* hardness = nullptr, const ExecContext* ctx = nullptr,
                            int* iterations_run = nullptr);

}  // namespace orogen::erosion
