#pragma once
// The pipe model (nodes/erosion/pipe.h) on a window of the whole domain: the kernel of both the whole-domain run
// (pipe_erosion) and the run across tiles (pipe_across_tiles.cpp). A time step updates each sample from the fields
// within 2 samples of it (the new fluxes from the water surface within 1, the new water, sediment and terrain from
// those fluxes within 1), by the same expression whatever the window: a sample at the grid's edge takes the domain
// border's rule, which is right where the grid's edge is the domain's and wrong by at most 2 samples a step
// elsewhere. So a tile grown by a 2-sample halo, refreshed every step, computes its own samples bit for bit.
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/erosion/pipe.h"

namespace orogen::erosion {

// Where a grid lies in the whole domain. Only the Drops rain needs it: its draws hash the whole domain's row and
// follow that row from the domain's first column, so a grid starting past column 0 replays the draws of the columns
// before it. A candidate drop takes one draw to be placed and, on land with moisture below 1, a second one:
// `draws_before` holds that bit for the first.x columns before the grid on each grid row (row after row, 64 bits a
// word; pipe_drop_draws).
struct PipeWindow {
  glm::ivec2 first{0, 0};  // the grid's first sample in the whole domain
  glm::ivec2 whole{0, 0};  // the whole domain's samples (0: the grid is the whole domain)
  std::vector<std::uint64_t> draws_before;
};

// Whether a candidate drop on a sample of height `height` and moisture `moisture` (1 when no moisture field is
// linked) takes a second draw.
inline bool pipe_drop_draws(const PipeParams& p, float height, float moisture) {
  return !(height < p.sea_level) && (moisture < 0.0f ? 0.0f : moisture) < 1.0f;
}

// The CFL time step (s) after a step whose deepest water over the whole domain was `deepest` metres: the gravity
// wave speed sqrt(g d) bounds the stable step of the pipe model. (The flow speed is not added: in thin films the flux
// limiter already caps it at spacing / dt, and feeding that back would shrink the step without end.)
inline double pipe_time_step(const PipeParams& p, double spacing, double deepest) {
  return p.courant * spacing / std::sqrt(p.gravity * (deepest > p.depth_scale ? deepest : p.depth_scale));
}

// The `flow` map: log1p of the accumulated speed x depth x time per cell area (x 1000), over its largest value
// (`scale`, pipe_flow_scale of the largest accumulation over the whole domain).
inline double pipe_flow_scale(float most, float area) { return std::log1p(static_cast<double>(most) / area * 1e3); }
inline float pipe_flow(float accumulated, double scale, float area) {
  return scale > 0 ? static_cast<float>(std::log1p(static_cast<double>(accumulated) / area * 1e3) / scale) : 0.0f;
}

// Refuses (NodeError) a run on `domain` above the work ceiling, counted with the largest step the CFL condition allows.
void check_pipe_work(const PipeParams& p, const Domain& domain);

// Refuses (NodeError) a step of `dt` seconds at time `t` that cannot advance the simulated time (water `deepest` metres
// deep made it 0 or too small to add).
void check_pipe_step(double dt, double t, double deepest);

// Seconds: a run ends within this of its duration.
inline constexpr double kPipeTimeSlack = 1e-9;

// The step at simulated time `t` after a step whose deepest water over the whole domain was `deepest` metres: its
// length (the CFL step on a grid of `spacing` metres, cut at the duration; refused as check_pipe_step does) and
// whether it is the run's last.
struct PipeStepLength {
  double dt;
  bool last;
};
PipeStepLength pipe_step_length(const PipeParams& p, double spacing, double t, double deepest);

// A run of the pipe model on a grid: `in` and the optional fields (null if absent) on the grid, as pipe_erosion
// takes them. The grid keeps references to all of them and to `p`.
class PipeGrid {
 public:
  enum Field { Terrain, Water, Sediment, FluxLeft, FluxRight, FluxDown, FluxUp, Speed, Accumulated, kFields };
  PipeGrid(const Heightfield& in, const PipeParams& p, const Heightfield* mask, const Heightfield* rainfall,
           const Heightfield* moisture, const Heightfield* temperature, const Heightfield* hardness, PipeWindow window);
  ~PipeGrid();
  // One time step of `dt` seconds, the run's step number `step` (the Drops hash); `last` writes the speed.
  void step(double dt, std::uint64_t step, bool last);
  // A field's samples, row-major on the grid (the first seven are what a step reads of the last one).
  std::vector<float>& field(Field f);
  float cell_area() const;

 private:
  struct Run;
  std::unique_ptr<Run> run_;
};

}  // namespace orogen::erosion
