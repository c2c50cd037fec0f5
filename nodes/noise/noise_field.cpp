#include "nodes/noise/noise_field.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_kernels.h"
#include "nodes/noise/noise_reference.h"
#include "nodes/noise/worley_neighbourhood.h"

namespace orogen::noise {

namespace {

constexpr int kRun = 256;  // samples per kernel call: the scratch buffers of a run stay in L1

// Working memory of one run of a block of rows (about 70 KB, on the stack of the task).
struct alignas(64) Scratch {
  double u[kRun], v[kRun];
  std::uint32_t cx[kRun], cy[kRun];
  float fx[kRun], fy[kRun];
  float warp_x[kernels::kMaxRows][kRun], warp_y[kernels::kMaxRows][kRun];
  float noise[kernels::kMaxRows][kRun], sum[kernels::kMaxRows][kRun], aux[kernels::kMaxRows][kRun];
  float q[kernels::kMaxRows][kRun], amplitude[kernels::kMaxRows][kRun], tail[kernels::kMaxRows][kRun];
};

void check_input(const Heightfield* f, const char* name, const Domain& domain) {
  if (f) require_same_grid(f->domain, domain, name);
}

// Copies samples [c0, c0 + n) of row j into dst and pads it to `padded` with `fill`.
const float* copy_run(const Heightfield* f, int j, int c0, int n, int padded, float fill, float* dst) {
  if (!f) return nullptr;
  std::memcpy(dst, f->row(j).data() + c0, sizeof(float) * static_cast<std::size_t>(n));
  std::fill(dst + n, dst + padded, fill);
  return dst;
}

// Per-octave lattice coordinates of every column (unwarped evaluation).
// Simplex splits two column terms (see kernels::SimplexRows): cell/frac hold u (1 + F2) and cell_j/frac_j u F2,
// cells not pre-multiplied.
struct ColumnCoords {
  std::vector<std::uint32_t> cell;  // lattice bases: cell * kHashPrimeX; simplex: the cell
  std::vector<float> frac;
  std::vector<std::uint32_t> cell_j;  // simplex only: the cell
  std::vector<float> frac_j;
};

}  // namespace

Heightfield evaluate_noise(const Domain& domain, const NoisePlan& plan, const NoiseInputs& inputs,
                           const ExecContext* ctx) {
  Heightfield out;
  out.domain = domain;
  evaluate_noise_into(out, plan, inputs, ctx);
  return out;
}

void evaluate_noise_into(Heightfield& out, const NoisePlan& plan, const NoiseInputs& inputs, const ExecContext* ctx) {
  const Domain domain = out.domain;
  if (plan.octaves.empty()) throw NodeError("noise plan without octaves");
  check_input(inputs.warp_x, "warp_x", domain);
  check_input(inputs.warp_y, "warp_y", domain);
  check_input(inputs.roughness, "roughness", domain);
  check_input(inputs.amplitude, "amplitude", domain);

  out.data.resize(domain.sample_count());
  const int width = domain.width(), height = domain.height();
  const int padded_width = kernels::padded(width);
  const bool warped = inputs.warp_x || inputs.warp_y;
  const bool simplex = plan.basis == Basis::Simplex;
  const auto octave_count = plan.octaves.size();

  // World x of every column, padded with the (real) columns beyond the domain.
  std::vector<double> xs(static_cast<std::size_t>(padded_width));
  for (int i = 0; i < padded_width; ++i) xs[static_cast<std::size_t>(i)] = domain.x(i);

  // Unwarped: x coordinates are shared by all rows, so they are split once per octave.
  std::vector<ColumnCoords> columns(warped ? 0 : octave_count);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const OctavePlan& o = plan.octaves[k];
    ColumnCoords& c = columns[k];
    c.cell.resize(xs.size());
    c.frac.resize(xs.size());
    if (simplex) {
      c.cell_j.resize(xs.size());
      c.frac_j.resize(xs.size());
    }
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double u = xs[i] * o.frequency + o.shift_x;
      const auto s = reference::split(simplex ? u * (1.0 + reference::kSimplexF2) : u);
      c.cell[i] = simplex ? s.cell : s.cell * kHashPrimeX;
      c.frac[i] = s.frac;
      if (simplex) {
        const auto sj = reference::split(u * reference::kSimplexF2);
        c.cell_j[i] = sj.cell;
        c.frac_j[i] = sj.frac;
      }
    }
  }

  WorleyNeighbourhood neighbourhood;
  kernels::WorleyRun worley;
  if (plan.basis == Basis::Worley) {
    neighbourhood = worley_neighbourhood(plan.worley_metric, plan.worley_jitter, worley_rank(plan.worley_output));
    worley = {plan.worley_metric,      plan.worley_output,      plan.worley_jitter,
              neighbourhood.dx.data(), neighbourhood.dy.data(), neighbourhood.size()};
  }

  const float ln_r = std::log(plan.lacunarity);
  const float q_constant = std::exp(ln_r * (plan.roughness - 1.0f));
  const bool fbm = plan.mode == FractalMode::Fbm;

  // Rows go in blocks of kMaxRows. Unwarped lattice bases (all but Simplex) hand each group of rows lying in
  // the same lattice row to one kernel call, which hashes every lattice cell once for the whole group.
  const bool shared_rows = !warped && plan.basis != Basis::Simplex;
  constexpr int kRows = kernels::kMaxRows;
  const int blocks = (height + kRows - 1) / kRows;
  for_each_row(ctx, blocks, [&](int block) {
    Scratch s;
    const int j0 = block * kRows, rows = std::min(kRows, height - j0);
    double ys[kRows];
    for (int r = 0; r < rows; ++r) ys[r] = domain.y(j0 + r);
    for (int c0 = 0; c0 < width; c0 += kRun) {
      const int n = std::min(kRun, width - c0);
      const int np = kernels::padded(n);
      // Whole vectors go straight into the rows; a padded tail goes through scratch.
      const bool direct = np == n;
      float* const target = direct ? out.row(j0).data() + c0 : s.tail[0];
      const std::ptrdiff_t target_stride = direct ? width : kRun;
      const float* wx[kRows];
      const float* wy[kRows];
      const float* amplitude[kRows];
      for (int r = 0; r < rows; ++r) {
        wx[r] = copy_run(inputs.warp_x, j0 + r, c0, n, np, 0.0f, s.warp_x[r]);
        wy[r] = copy_run(inputs.warp_y, j0 + r, c0, n, np, 0.0f, s.warp_y[r]);
        amplitude[r] = copy_run(inputs.amplitude, j0 + r, c0, n, np, 0.0f, s.amplitude[r]);
        if (plan.mode == FractalMode::Multifractal) {
          if (inputs.roughness) {
            copy_run(inputs.roughness, j0 + r, c0, n, np, 0.0f, s.aux[r]);
            kernels::roughness_ratio(s.aux[r], ln_r, np, s.q[r]);
          } else {
            std::fill(s.q[r], s.q[r] + np, q_constant);
          }
        }
      }
      for (std::size_t k = 0; k < octave_count; ++k) {
        const OctavePlan& o = plan.octaves[k];
        const bool first = k == 0;
        // fbm accumulates straight into the output; other modes combine a separate noise run.
        auto destination = [&](int r) {
          return fbm ? kernels::Output{target + r * target_stride, o.amplitude * plan.scale, !first, target_stride}
                     : kernels::Output{s.noise[r], 1.0f, false, kRun};
        };
        auto lattice_basis = [&](const kernels::LatticeRun& run, const kernels::Output& dst) {
          switch (plan.basis) {
            case Basis::Perlin:
              kernels::perlin(run, o.key, np, dst);
              break;
            case Basis::Value:
              kernels::value(run, o.key, np, dst);
              break;
            case Basis::White:
              kernels::white(run, o.key, np, dst);
              break;
            case Basis::Worley:
              kernels::worley(run, o.key, worley, np, dst);
              break;
            case Basis::Simplex:
              break;  // not a lattice basis
          }
        };
        if (shared_rows) {
          std::uint32_t hy[kRows];
          float fy[kRows];
          for (int r = 0; r < rows; ++r) {
            const auto split = reference::split(ys[r] * o.frequency + o.shift_y);
            hy[r] = split.cell * kHashPrimeY;
            fy[r] = split.frac;
          }
          for (int r0 = 0, r1 = 0; r0 < rows; r0 = r1) {
            for (r1 = r0 + 1; r1 < rows && hy[r1] == hy[r0]; ++r1) {}
            const kernels::LatticeRun run{
                columns[k].cell.data() + c0, columns[k].frac.data() + c0, nullptr, nullptr, hy[r0], fy + r0, r1 - r0};
            lattice_basis(run, destination(r0));
          }
        } else if (simplex && !warped) {
          // All rows of the block in one call: they share the columns' split.
          const ColumnCoords& col = columns[k];
          kernels::SimplexRows run;
          run.ci = col.cell.data() + c0;
          run.cj = col.cell_j.data() + c0;
          run.fi = col.frac.data() + c0;
          run.fj = col.frac_j.data() + c0;
          run.rows = rows;
          for (int r = 0; r < rows; ++r) {
            const double v = ys[r] * o.frequency + o.shift_y;
            const auto b = reference::split(v * reference::kSimplexF2);
            const auto c = reference::split(v * (1.0 + reference::kSimplexF2));
            run.row_ci[r] = b.cell;
            run.row_cj[r] = c.cell;
            run.row_fi[r] = b.frac;
            run.row_fj[r] = c.frac;
          }
          kernels::simplex_rows(run, o.key, np, destination(0));
        } else {
          for (int r = 0; r < rows; ++r) {
            const double y = ys[r];
            if (simplex) {  // warped
              kernels::displaced(xs.data() + c0, 0.0, wx[r], o.frequency, o.shift_x, np, s.u);
              kernels::displaced(nullptr, y, wy[r], o.frequency, o.shift_y, np, s.v);
              kernels::simplex_skew(s.u, s.v, 0.0, np, s.cx, s.cy, s.fx, s.fy);
              kernels::simplex({s.cx, s.cy, s.fx, s.fy}, o.key, np, destination(r));
            } else {  // warped lattice bases
              kernels::displaced(xs.data() + c0, 0.0, wx[r], o.frequency, o.shift_x, np, s.u);
              kernels::split_lattice(s.u, kHashPrimeX, np, s.cx, s.fx);
              kernels::displaced(nullptr, y, wy[r], o.frequency, o.shift_y, np, s.v);
              kernels::split_lattice(s.v, kHashPrimeY, np, s.cy, s.fy);
              lattice_basis({s.cx, s.fx, s.cy, s.fy, 0, nullptr, 1}, destination(r));
            }
          }
        }
        for (int r = 0; r < rows; ++r) {
          switch (plan.mode) {
            case FractalMode::Fbm:
              break;
            case FractalMode::Billow:
              kernels::billow_step(s.noise[r], o.amplitude, first, np, s.sum[r]);
              break;
            case FractalMode::Ridged:
              kernels::ridged_step(s.noise[r], o.amplitude, plan.offset, first, np, s.sum[r], s.aux[r]);
              break;
            case FractalMode::Hybrid:
              kernels::hybrid_step(s.noise[r], o.amplitude, plan.offset, first, np, s.sum[r], s.aux[r]);
              break;
            case FractalMode::Multifractal:
              kernels::multifractal_step(s.noise[r], s.q[r], first, np, s.sum[r], s.aux[r]);
              break;
          }
        }
      }
      for (int r = 0; r < rows; ++r) {
        float* t = target + r * target_stride;
        if (fbm && amplitude[r]) kernels::finish(t, amplitude[r], 1.0f, np, t);
        if (!fbm) kernels::finish(s.sum[r], amplitude[r], plan.scale, np, t);
        if (!direct) std::memcpy(out.row(j0 + r).data() + c0, t, sizeof(float) * static_cast<std::size_t>(n));
      }
    }
  });
}

float evaluate_noise_reference(const NoisePlan& plan, double x, double y, const ReferenceInputs& in) {
  const float ln_r = std::log(plan.lacunarity);
  const float q = std::exp(ln_r * (in.roughness.value_or(plan.roughness) - 1.0f));
  float sum = 0.0f, aux = 0.0f;
  for (std::size_t k = 0; k < plan.octaves.size(); ++k) {
    const OctavePlan& o = plan.octaves[k];
    const double u = (x + static_cast<double>(in.warp_x)) * o.frequency + o.shift_x;
    const double v = (y + static_cast<double>(in.warp_y)) * o.frequency + o.shift_y;
    const float n = plan.basis == Basis::Worley
                        ? reference::worley_select(
                              reference::worley_brute_force(u, v, o.key, plan.worley_metric, plan.worley_jitter),
                              plan.worley_output)
                        : reference::basis(plan.basis, u, v, o.key);
    const bool first = k == 0;
    switch (plan.mode) {
      case FractalMode::Fbm:
        sum += o.amplitude * n;
        break;
      case FractalMode::Billow:
        sum += o.amplitude * (2.0f * std::fabs(n) - 1.0f);
        break;
      case FractalMode::Ridged: {
        float s = (plan.offset - std::fabs(n)) * (plan.offset - std::fabs(n));
        if (!first) s *= std::clamp(2.0f * aux, 0.0f, 1.0f);
        aux = s;
        sum += o.amplitude * s;
        break;
      }
      case FractalMode::Hybrid: {
        const float s = (n + plan.offset) * o.amplitude;
        if (first) {
          sum = aux = s;
        } else {
          const float w = std::min(aux, 1.0f);
          sum += w * s;
          aux = w * s;
        }
        break;
      }
      case FractalMode::Multifractal:
        if (first) {
          sum = n;
          aux = q;
        } else {
          sum += aux * n;
          aux *= q;
        }
        break;
    }
  }
  return sum * plan.scale * in.amplitude;
}

}  // namespace orogen::noise
