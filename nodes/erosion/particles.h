#pragma once
// Particle hydraulic erosion after Beyer 2015 ("Implementation of a method for hydraulic erosion", TU
// Munich), with the corrections noted in the seeds: droplets follow the negative gradient, the capacity is
// max(slope, min_slope) x speed x water x capacity, and speed^2 grows by -dh x gravity going downhill.
// Deposits use the erosion's brush (not Beyer's bilinear 2 x 2 deposit), and a droplet moving uphill fills
// the hollow it leaves up to the next height on its path (its spill height) or with all it carries: bilinear
// deposits and fills left small closed hollows on fine grids (hundreds of pits per million cells at 10 m).
//
// World units: droplets per km^2 of the domain (not a count), step length, brush radius and lifetime in
// metres; sediment is a volume (m^3) that the brush spreads over its cells and divides by their area, so the
// same parameters remove the same volume per km^2 at any resolution.
//
// Determinism while parallel: a fixed tiled schedule. Droplets run in rounds of a fixed number (set by the
// grid size); a round bins its droplets by the tile of their origin, tiles at least twice a droplet's reach
// (lifetime + brush radius) across, and runs the four colours of a 2 x 2 checkerboard of tiles one after the
// other. Tiles of one colour never touch the same sample, so they run in parallel, each tile's droplets in
// index order, four at a time in the lanes of a vector (a lane freed by an ended droplet takes the next; on
// CPUs with AVX2, two tiles share the lanes of an 8-float vector, which changes nothing for either),
// changing the heights directly. Every sample gets the same changes in the same order for any thread count:
// bit-identical, no atomics, no change logs. Chosen over frozen batches with per-droplet change logs (the
// earlier scheme) because droplets see the changes of the droplets before them, as in Beyer's serial loop
// (those in flight together one step late), and a tile's samples stay in cache while its droplets run.
#include <cstdint>

#include "nodes/erosion/erosion_common.h"

namespace orogen::erosion {

struct ParticleParams {
  double droplets_per_km2 = 20000.0;  // droplets per km^2 of the domain
  double step_length = 10.0;          // metres a droplet moves per step
  double lifetime = 300.0;            // metres a droplet travels at most
  double radius = 30.0;               // metres: erosion brush radius
  double inertia = 0.05;              // 0..1: share of the old direction kept
  double capacity = 4.0;              // m^3 of sediment per unit (slope x speed x water)
  double min_slope = 0.01;            // slope floor of the capacity (m/m)
  double deposition = 0.3;            // 0..1 share of the surplus deposited per step
  double erosion = 0.3;               // 0..1 share of the free capacity eroded per step
  double evaporation = 0.01;          // 0..1 share of the water evaporated per step
  double gravity = 4.0;               // m/s^2 per metre of drop (speed^2 gain per metre)
  std::uint64_t seed = 0;
  bool change_maps = true;  // also the erosion and deposition maps (false: left null)
  bool flow_map = true;     // also the flow map and the visit counts behind it (false: left null)
};

struct ParticleStats {
  double eroded = 0.0;       // m^3 removed from the terrain
  double deposited = 0.0;    // m^3 laid down
  double carried_off = 0.0;  // m^3 of sediment that left the domain with its droplet
  std::uint64_t droplets = 0;
  std::uint64_t steps = 0;  // droplet steps simulated
};

ErosionMaps particle_erosion(const Heightfield& in, const ParticleParams& p, const Heightfield* mask = nullptr,
                             const ExecContext* ctx = nullptr, ParticleStats* stats = nullptr);

}  // namespace orogen::erosion
