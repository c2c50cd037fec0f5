#include "nodes/erosion/thermal.h"

#include <algorithm>
#include <vector>

#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/thermal_step.h"

namespace orogen::erosion {

ErosionMaps thermal_erosion(const Heightfield& in, const ThermalParams& p, const Heightfield* mask,
                            const Heightfield* hardness, const ExecContext* ctx, int* iterations_run) {
  require_finite_inputs("ThermalErosion", {{"in", &in}, {"mask", mask}, {"hardness", hardness}});
  const int w = in.width(), h = in.height();
  const ThermalStencil stencil = thermal_stencil(p, in.domain.spacing, in.domain.resolution);
  // The samples surrounded by one cell of walls: nothing flows out of the grid.
  ThermalGrids g(w + 2, h + 2, hardness != nullptr);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t k = in.index(i, j), q = g.at(i + 1, j + 1);
      g.z[q] = in.data[k];
      g.rate[q] = thermal_rate(p, mask ? mask->data[k] : 1.0f);
      if (hardness) g.tan_cell[q] = thermal_tangent(p, hardness->data[k]);
    }
  const GridWindow all{1, 1, w + 1, h + 1};
  int it = 0;
  for (; it < stencil.iterations; ++it) {
    check_cancelled(ctx);
    const float change = thermal_iteration(g, stencil, all, all);
    report(ctx, static_cast<double>(it + 1) / stencil.iterations);
    if (change <= p.tolerance) {
      ++it;
      break;
    }
  }
  if (iterations_run) *iterations_run = it;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  float mmax = 0.0f;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      maps.out->at(i, j) = g.z[g.at(i + 1, j + 1)];
      mmax = std::max(mmax, g.moved[g.at(i + 1, j + 1)]);
    }
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      maps.flow->at(i, j) = thermal_flow(g.moved[g.at(i + 1, j + 1)], mmax);
    }
  fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
