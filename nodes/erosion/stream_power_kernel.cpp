#include "nodes/erosion/stream_power_kernel.h"

#include <algorithm>

#include "nodes/common/work_bounds.h"

namespace orogen::erosion {

StreamPowerSchedule StreamPowerSchedule::of(const StreamPowerParams& p, double dx, double dy, std::size_t samples) {
  StreamPowerSchedule s;
  // Counts checked before anything runs (a bare cast of 1e10 steps to int is undefined and ran one step).
  s.steps = static_cast<int>(checked_count(p.duration / p.dt - 1e-9, "StreamPower: time steps (duration / time_step)",
                                           "raise time_step or lower duration"));
  s.dt = p.duration / s.steps;
  // Diffusion sub-steps: explicit FTCS is stable for D dt_sub (2/dx^2 + 2/dy^2) <= 1.
  const double dt_diff_max = 0.9 / (std::max(p.diffusion, 1e-30) * (2.0 / (dx * dx) + 2.0 / (dy * dy)));
  s.diff_steps = p.diffusion > 0
                     ? static_cast<int>(checked_count(s.dt / dt_diff_max,
                                                      "StreamPower: diffusion sub-steps per time step "
                                                      "(diffusion x time_step / spacing^2)",
                                                      "lower diffusion or time_step, or use a coarser grid"))
                     : 0;
  check_work(static_cast<double>(s.steps) * (1.0 + s.diff_steps) * static_cast<double>(samples),
             "StreamPower: sample updates (time steps x (1 + diffusion sub-steps) x samples)",
             "raise time_step, lower duration or diffusion, or use a coarser grid");
  return s;
}

StreamPowerIncision::StreamPowerIncision(const StreamPowerParams& p, const hydrology::FlowGrid& grid, double dt)
    : p_(p), dt_(dt), cell_area_(grid.cell_area()) {
  area_pow_.resize(kTable);
  for (int q = 0; q < kTable; ++q) area_pow_[static_cast<std::size_t>(q)] = std::pow(q * cell_area_, p.m);
  for (int q = 0; q < 8; ++q) len_pow_[q] = std::pow(grid.distance(q), p.n);
}

double StreamPowerIncision::incised(double z0, double zr, double a, double kfac, int direction) const {
  const double cells = std::nearbyint(a / cell_area_);
  const double am =
      cells < kTable && cells * cell_area_ == a ? area_pow_[static_cast<std::size_t>(cells)] : std::pow(a, p_.m);
  const double f = p_.k * kfac * dt_ * am / len_pow_[direction];
  if (!(z0 > zr && f > 0)) return z0;
  if (p_.n == 1.0) return (z0 + f * zr) / (1.0 + f);
  // Newton on g(z) = z - z0 + f (z - zr)^n over (zr, z0], safeguarded by bisection.
  double lo = zr, hi = z0, zn = z0;
  for (int it = 0; it < 50; ++it) {
    const double d = zn - zr;
    const double g = zn - z0 + f * std::pow(d, p_.n);
    if (g > 0)
      hi = zn;
    else
      lo = zn;
    const double gp = 1.0 + f * p_.n * std::pow(d, p_.n - 1.0);
    double next = zn - g / gp;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - zn) <= 1e-12 * std::max(1.0, std::abs(zn))) return next;
    zn = next;
  }
  return zn;
}

}  // namespace orogen::erosion
