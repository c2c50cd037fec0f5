#include "nodes/erosion/pipe.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace orogen::erosion {
namespace {

template <class Fn>
void rows(int h, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) fn(j);
  });
}

}  // namespace

PipeMaps pipe_erosion(const Heightfield& in, const PipeParams& p, const Heightfield* mask, const Heightfield* rainfall,
                      const Heightfield* moisture, const Heightfield* temperature, const Heightfield* hardness,
                      const ExecContext* ctx, PipeStats* stats, bool check_conservation) {
  const int w = in.width(), h = in.height();
  const std::size_t n = in.data.size();
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
  const float A = static_cast<float>(dx * dy);
  const float g = static_cast<float>(p.gravity);
  // Pipe geometry: flux (m^3/s) += dt x g x (width x depth) x dh / length.
  const float kx = static_cast<float>(dy / dx), ky = static_cast<float>(dx / dy);
  const double mm_per_h = 1.0 / 3.6e6;  // mm/h -> m/s

  std::vector<float> b = in.data, b2(n), d(n, 0.0f), d2(n), s(n, 0.0f), s2(n), surf(n), conc_of(n);
  std::vector<float> fl(n, 0.0f), fr(n, 0.0f), fd(n, 0.0f), fu(n, 0.0f), spd(n, 0.0f), flow_acc(n, 0.0f);
  std::vector<double> row_sed_out(h), row_water_out(h), row_vmax(h), row_dmax(h), row_sum(h);
  std::vector<unsigned char> sink(n);
  for (std::size_t k = 0; k < n; ++k) sink[k] = in.data[k] < p.sea_level;

  auto volume = [&]() {  // sum of (b + s) x A, rows summed in order
    rows(h, [&](int j) {
      double acc = 0;
      for (int i = 0; i < w; ++i) acc += static_cast<double>(b[in.index(i, j)]) + s[in.index(i, j)];
      row_sum[j] = acc;
    });
    double t = 0;
    for (double r : row_sum) t += r;
    return t * A;
  };

  PipeStats st;
  st.total_volume = 0;
  for (float v : in.data) st.total_volume += std::abs(static_cast<double>(v)) * A;
  double t = 0.0, vmax = 0.0, dmax = 0.0;
  const double spacing = std::min(dx, dy);
  std::uint64_t step = 0;
  while (t < p.duration - 1e-9) {
    check_cancelled(ctx);
    // The gravity-wave speed sqrt(g d) bounds the stable step of the pipe model. (The flow speed is not
    // added: in thin films the flux limiter already caps it at spacing / dt, and feeding that back would
    // shrink the step without end.)
    double dt = p.courant * spacing / std::sqrt(p.gravity * std::max(dmax, p.depth_scale));
    dt = std::min(dt, p.duration - t);
    const float fdt = static_cast<float>(dt);
    const double before = check_conservation ? volume() : 0.0;

    // 1. Rain.
    rows(h, [&](int j) {
      for (int i = 0; i < w; ++i) {
        const std::size_t k = in.index(i, j);
        const double rate = (rainfall ? std::max(0.0f, rainfall->data[k]) : p.rain_rate) * mm_per_h;
        if (p.rain_mode == RainMode::Uniform) {
          d[k] += static_cast<float>(dt * rate);
        } else {
          const double m = moisture ? std::clamp(static_cast<double>(moisture->data[k]), 0.0, 1.0) : 1.0;
          const double chance = std::min(1.0, m * p.drop_chance * dt);
          if (chance > 0 && hash01(p.seed, step * n + k) < chance)
            d[k] += static_cast<float>(rate / std::max(p.drop_chance, 1e-9));
        }
      }
    });
    // 2. Outflow fluxes. The water surface first, then the fluxes: a generic cell for the border and an
    // unchecked loop for the interior of each row.
    rows(h, [&](int j) {
      // And each cell's sediment concentration (per m^3 of water), computed once instead of by every pipe.
      for (int i = 0; i < w; ++i) {
        const std::size_t k = in.index(i, j);
        const float dk = d[k];
        surf[k] = b[k] + dk;
        conc_of[k] = dk > 0.0f ? s[k] / (dk * A) : 0.0f;
      }
    });
    rows(h, [&](int j) {
      auto finish = [&](std::size_t k, float dk, float l, float r, float dn, float up) {
        l = std::max(0.0f, l), r = std::max(0.0f, r), dn = std::max(0.0f, dn), up = std::max(0.0f, up);
        const float total = (l + r + dn + up) * fdt;
        const float K = total > dk * A ? dk * A / total : 1.0f;
        fl[k] = l * K, fr[k] = r * K, fd[k] = dn * K, fu[k] = up * K;
      };
      auto generic = [&](int i) {
        const std::size_t k = in.index(i, j);
        const float dk = d[k], hk = surf[k], c = fdt * g * dk;
        auto head = [&](int ii, int jj) { return (ii < 0 || ii >= w || jj < 0 || jj >= h) ? dk : hk - surf[in.index(ii, jj)]; };
        finish(k, dk, fl[k] + c * kx * head(i - 1, j), fr[k] + c * kx * head(i + 1, j),
               fd[k] + c * ky * head(i, j - 1), fu[k] + c * ky * head(i, j + 1));
      };
      if (j == 0 || j == h - 1 || w < 3) {
        for (int i = 0; i < w; ++i) generic(i);
        return;
      }
      generic(0);
      const std::size_t row = in.index(0, j);
      const float* sf = surf.data();
      const float cgx = fdt * g * kx, cgy = fdt * g * ky;
      for (std::size_t k = row + 1; k < row + static_cast<std::size_t>(w) - 1; ++k) {
        const float dk = d[k], hk = sf[k];
        finish(k, dk, fl[k] + cgx * dk * (hk - sf[k - 1]), fr[k] + cgx * dk * (hk - sf[k + 1]),
               fd[k] + cgy * dk * (hk - sf[k - w]), fu[k] + cgy * dk * (hk - sf[k + w]));
      }
      generic(w - 1);
    });
    // 3. Water, sediment transport, velocity, dissolution/deposition, evaporation, sinks.
    const float ks = static_cast<float>(p.dissolving * dt), kd = static_cast<float>(std::min(1.0, p.depositing * dt));
    const float kc = static_cast<float>(p.capacity);
    rows(h, [&](int j) {
      double sed_out = 0, water_out = 0, vm = 0, dm = 0;
      // Local restrict pointers: the closure's references are not reloaded for every access.
      const float* __restrict FL = fl.data();
      const float* __restrict FR = fr.data();
      const float* __restrict FD = fd.data();
      const float* __restrict FU = fu.data();
      const float* __restrict D = d.data();
      const float* __restrict S = s.data();
      const float* __restrict B = b.data();
      const float* __restrict C = conc_of.data();
      const unsigned char* __restrict SINK = sink.data();
      float* __restrict B2 = b2.data();
      float* __restrict D2 = d2.data();
      float* __restrict S2 = s2.data();
      float* __restrict SPD = spd.data();
      float* __restrict FACC = flow_acc.data();
      for (int i = 0; i < w; ++i) {
        const std::size_t k = in.index(i, j);
        const float dk = D[k];
        // Volumes through each pipe this step and the sediment they carry (concentration of the source).
        const float out_v = (FL[k] + FR[k] + FD[k] + FU[k]) * fdt;
        const float conc = C[k];
        float in_v = 0.0f, in_s = 0.0f, out_s = 0.0f;
        float wx = 0.0f, wy = 0.0f;
        auto pipe_out = [&](float f, bool border) {
          const float vol = f * fdt;
          const float sv = conc * vol;
          out_s += sv;
          if (border) {
            water_out += vol;
            sed_out += static_cast<double>(sv) * A;
          }
        };
        pipe_out(FL[k], i == 0);
        pipe_out(FR[k], i == w - 1);
        pipe_out(FD[k], j == 0);
        pipe_out(FU[k], j == h - 1);
        auto pipe_in = [&](std::size_t nb, float f) {
          const float vol = f * fdt;
          in_v += vol;
          in_s += C[nb] * vol;
        };
        float fin_l = 0, fin_r = 0, fin_d = 0, fin_u = 0;
        if (i > 0) fin_l = FR[k - 1], pipe_in(k - 1, fin_l);
        if (i < w - 1) fin_r = FL[k + 1], pipe_in(k + 1, fin_r);
        if (j > 0) fin_d = FU[k - w], pipe_in(k - w, fin_d);
        if (j < h - 1) fin_u = FD[k + w], pipe_in(k + w, fin_u);
        float d1 = std::max(0.0f, dk + (in_v - out_v) / A);
        // Sediment heights moving in and out: the source's s / (d A) times the pipe's volume.
        float s1 = S[k] + in_s - out_s;
        wx = 0.5f * (fin_l - FL[k] + FR[k] - fin_r);
        wy = 0.5f * (fin_d - FD[k] + FU[k] - fin_u);
        const float dmean = 0.5f * (dk + d1);
        float u = 0, v = 0;
        if (dmean > 1e-3f) {
          u = wx / (static_cast<float>(dy) * dmean);
          v = wy / (static_cast<float>(dx) * dmean);
        }
        const float speed = std::sqrt(u * u + v * v);
        // Tilt from the terrain's central differences.
        const float bx = (B[i < w - 1 ? k + 1 : k] - B[i > 0 ? k - 1 : k]) / static_cast<float>((i > 0 && i < w - 1 ? 2 : 1) * dx);
        const float by = (B[j < h - 1 ? k + w : k] - B[j > 0 ? k - w : k]) / static_cast<float>((j > 0 && j < h - 1 ? 2 : 1) * dy);
        const float g2 = bx * bx + by * by;
        const float sin_tilt = std::clamp(std::sqrt(g2 / (1.0f + g2)), 0.005f, 0.5f);
        // Capacity in proportion to the water that carries it (a concentration times the depth): a film
        // of water cannot hold metres of sediment however fast it runs.
        const float cap = kc * sin_tilt * speed * d1;
        float bk = B[k];
        const float m = mask ? mask_at(mask, k) : 1.0f;
        if (!SINK[k]) {
          if (cap > s1) {
            float rate = ks * m;
            if (hardness) rate *= 1.0f - std::clamp(hardness->data[k], 0.0f, 1.0f);
            if (p.layer_depth > 0) rate *= std::exp2(-std::max(0.0f, in.data[k] - bk) / static_cast<float>(p.layer_depth));
            const float e = std::min(1.0f, rate) * (cap - s1);
            bk -= e;
            s1 += e;
          } else {
            const float e = kd * m * (s1 - cap);
            bk += e;
            s1 -= e;
          }
        }
        const float temp = temperature ? std::max(0.0f, temperature->data[k]) : 1.0f;
        d1 *= std::max(0.0f, 1.0f - static_cast<float>(p.evaporation * dt) * temp);
        if (SINK[k]) {
          water_out += static_cast<double>(d1) * A;
          sed_out += static_cast<double>(s1) * A;
          d1 = 0, s1 = 0;
        }
        B2[k] = bk, D2[k] = d1, S2[k] = s1, SPD[k] = speed;
        FACC[k] += static_cast<float>(dt) * speed * d1;
        vm = std::max<double>(vm, speed);
        dm = std::max<double>(dm, d1);
      }
      row_sed_out[j] = sed_out, row_water_out[j] = water_out, row_vmax[j] = vm, row_dmax[j] = dm;
    });
    std::swap(b, b2), std::swap(d, d2), std::swap(s, s2);
    double sed_out = 0;
    vmax = 0, dmax = 0;
    for (int j = 0; j < h; ++j) {
      sed_out += row_sed_out[j];
      st.water_out += row_water_out[j];
      vmax = std::max(vmax, row_vmax[j]);
      dmax = std::max(dmax, row_dmax[j]);
    }
    st.sediment_out += sed_out;
    if (check_conservation)
      st.max_conservation_error = std::max(st.max_conservation_error, std::abs(volume() + sed_out - before));
    t += dt;
    ++step;
    st.dt = dt;
    report(ctx, t / p.duration);
  }
  st.steps = static_cast<int>(step);
  if (stats) *stats = st;

  PipeMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.water = std::make_shared<Heightfield>(in.domain);
  maps.velocity = std::make_shared<Heightfield>(in.domain);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  float fmax = 0;
  for (std::size_t k = 0; k < n; ++k) fmax = std::max(fmax, flow_acc[k]);
  const double lmax = std::log1p(static_cast<double>(fmax) / A * 1e3);
  for (std::size_t k = 0; k < n; ++k) {
    maps.out->data[k] = b[k] + s[k];  // what is still suspended settles
    maps.water->data[k] = d[k];
    maps.velocity->data[k] = spd[k];
    maps.flow->data[k] = lmax > 0 ? static_cast<float>(std::log1p(static_cast<double>(flow_acc[k]) / A * 1e3) / lmax) : 0.0f;
  }
  fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
