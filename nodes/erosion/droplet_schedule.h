#pragma once
// The fixed schedule of particle erosion (particles.h), shared by the whole-domain run (particle_erosion) and the
// run across the tiles of a tiled or distributed build (particles_across_tiles.cpp), so both run the same droplets
// in the same order on every sample.
//
// Droplets run in rounds of a fixed number; a round bins its droplets by the block of the whole domain's grid their
// origin falls in (blocks at least twice a droplet's reach across), and runs the four colors of a 2 x 2
// checkerboard of blocks one after the other: a phase per color. The droplets of two blocks of one color never
// touch the same sample, and a block's droplets read and change samples within margin() of the block only. All of
// it is a function of the parameters and the whole domain, never of threads, tiles or ranks.
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "nodes/erosion/particles.h"

namespace orogen::erosion {

// A window of the whole domain's samples that droplets run on: sample (x, y) of the whole domain lies at
// z[(y - y0) * pitch + x - x0]; the window must hold the blocks run on it grown by DropletSchedule::margin().
struct DropletGrid {
  float* z = nullptr;               // heights
  std::uint32_t* visits = nullptr;  // visit counts in the same layout, or nullptr: none counted
  const float* mask = nullptr;      // mask, sample (x, y) at (y - y0) * mask_pitch + x - x0, or nullptr: none
  int x0 = 0, y0 = 0, pitch = 0, mask_pitch = 0;
};

// What a block's droplets did, summed over the rounds in round order (the report's figures add these up in block
// order).
struct DropletBlockStats {
  double eroded = 0.0, deposited = 0.0, carried_off = 0.0;  // m^3
  std::uint64_t steps = 0;
};

// A round's droplets by block: block b runs the droplets first + order[start[b] .. start[b + 1]) in that order.
struct DropletBins {
  std::uint64_t first = 0;
  std::vector<std::uint32_t> start, order;
  std::vector<std::uint32_t> block_of;  // (scratch)
};

// The flow output of a sample visited `visits` times, lmax = log1p(the most visits of any sample) > 0.
inline float droplet_flow(std::uint32_t visits, double lmax) {
  return static_cast<float>(std::log1p(static_cast<double>(visits)) / lmax);
}

class DropletSchedule {
 public:
  // Throws NodeError as the node does for counts and work beyond its limits.
  DropletSchedule(const ParticleParams& p, const Domain& whole);
  ~DropletSchedule();
  DropletSchedule(const DropletSchedule&) = delete;
  DropletSchedule& operator=(const DropletSchedule&) = delete;

  glm::ivec2 size() const;  // the whole domain's samples
  std::uint64_t droplets() const;
  std::uint64_t rounds() const;
  glm::ivec2 blocks() const;  // along x and y; block b = by * blocks().x + bx
  int block_count() const { return blocks().x * blocks().y; }
  // Block b's first and last samples (both included).
  glm::ivec2 block_lo(int b) const;
  glm::ivec2 block_hi(int b) const;
  // The blocks of color c (0 to 3; the phases run the colors in this order), in block order.
  const std::vector<int>& color_blocks(int c) const;
  // Samples beyond its block, on each side, within which a block's droplets read and change heights.
  glm::ivec2 margin() const;
  // Row pitch (floats) for a window `width` samples wide: wider where rows would alias in the cache (no value
  // changes).
  static int pitch_for(int width);

  // Round `round`'s droplets into `bins` (reusing its memory).
  void bin(std::uint64_t round, DropletBins& bins) const;
  // Runs the droplets of `bins` of the blocks `blocks` (all of one color) on `grid`, blocks side by side on the
  // threads, adding to stats[b] for block b (stats indexed by block). `ctx` (nullable) is polled for cancellation.
  void run(const DropletGrid& grid, const DropletBins& bins, const std::vector<int>& blocks, DropletBlockStats* stats,
           const ExecContext* ctx) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace orogen::erosion
