#pragma once
// The arithmetic of one StreamPower step that the whole-domain run (stream_power.cpp) and the run across tiles
// (stream_power_across_tiles.cpp) share, so both compute every sample with the same operations in the same order:
// the step schedule, a hillslope-diffusion update and the implicit incision of a cell towards its receiver.
#include <cmath>
#include <cstddef>
#include <vector>

#include "nodes/erosion/stream_power.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::erosion {

// Time steps, their length and the explicit diffusion sub-steps per step. Throws NodeError (checked_count,
// check_work) for counts the run cannot do.
struct StreamPowerSchedule {
  int steps = 1;
  double dt = 0.0;     // years per step: duration / steps
  int diff_steps = 0;  // FTCS sub-steps per step, each stable: D dt_sub (2/dx^2 + 2/dy^2) <= 0.9
  static StreamPowerSchedule of(const StreamPowerParams& p, double dx, double dy, std::size_t samples);
};

// The height change of one diffusion sub-step at a cell: c = D dt_sub, kfac the cell's mask factor, cx = 1/dx^2,
// cy = 1/dy^2, its height zc and its four neighbours' (mirrored across the domain's border). 0 at base level.
inline double diffusion_change(bool outlet, double c, double kfac, double cx, double cy, double zc, double zw,
                               double ze, double zs, double zn) {
  const double lx = (zw + ze - 2 * zc) * cx;
  const double ly = (zs + zn - 2 * zc) * cy;
  return outlet ? 0.0 : c * kfac * (lx + ly);
}

// The implicit incision of a cell towards its receiver, already at t + dt (Braun and Willett 2013; Newton for
// n != 1).
class StreamPowerIncision {
 public:
  StreamPowerIncision(const StreamPowerParams& p, const hydrology::FlowGrid& grid, double dt);

  // Whether a cell of drainage area `area` (m^2) incises at all: channel cells only.
  bool incises(double area) const { return area >= p_.channel_area; }
  // The new height of a cell at z0 with mask factor `kfac` and drainage area `area`, draining along D8 direction
  // `direction` to a receiver already at zr.
  double incised(double z0, double zr, double area, double kfac, int direction) const;

 private:
  static constexpr int kTable = 1 << 16;
  StreamPowerParams p_;
  double dt_ = 0.0, cell_area_ = 0.0;
  // A^m by table for areas of up to kTable whole cells (exactly count x cell area): the same pow() values,
  // computed once; L^n per direction.
  std::vector<double> area_pow_;
  double len_pow_[8] = {};
};

}  // namespace orogen::erosion
