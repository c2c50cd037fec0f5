#include "nodes/erosion/particles.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace orogen::erosion {
namespace {

// One change of the terrain by a droplet step, applied later in droplet order: a deposit spread
// bilinearly over the 4 samples around (u, v) = (corner + (fu, fv)), or an erosion with the brush around a
// sample (fu < 0), `amount` metres of height per unit weight.
struct Change {
  std::uint32_t node;
  std::int32_t ci, cj;  // column and row of node (no division when the changes are applied)
  float amount;
  float fu, fv;
};

struct DropletLog {
  std::vector<Change> changes;
  std::vector<std::uint32_t> visits;
  double eroded = 0.0, deposited = 0.0, carried_off = 0.0;  // m^3
  std::uint32_t steps = 0;
};

struct BrushTap {
  int di, dj;
  float w;
};

}  // namespace

ErosionMaps particle_erosion(const Heightfield& in, const ParticleParams& p, const Heightfield* mask,
                             const ExecContext* ctx, ParticleStats* stats) {
  const int w = in.width(), h = in.height();
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
  const double cell_area = dx * dy;
  const glm::dvec2 size = in.domain.size();
  const double area_km2 = size.x * size.y * 1e-6;
  const std::uint64_t droplets =
      static_cast<std::uint64_t>(std::llround(std::max(0.0, p.droplets_per_km2) * area_km2));
  const int max_steps = std::max(1, static_cast<int>(std::ceil(p.lifetime / p.step_length)));

  // Brush around the nearest sample: weights 1 - distance / radius, normalised.
  std::vector<BrushTap> brush;
  // Taps farther than the grid's extent never land on a sample; clamping them keeps the brush finite on
  // fine grids and huge radii without changing any result (deposits are normalised by the taps inside).
  const int rx = static_cast<int>(std::min<double>(std::ceil(p.radius / dx), w));
  const int ry = static_cast<int>(std::min<double>(std::ceil(p.radius / dy), h));
  {
    double total = 0.0;
    for (int dj = -ry; dj <= ry; ++dj)
      for (int di = -rx; di <= rx; ++di) {
        const double dist = std::hypot(di * dx, dj * dy);
        const double wt = 1.0 - dist / std::max(p.radius, 1e-9);
        if (wt > 0.0) {
          brush.push_back({di, dj, static_cast<float>(wt)});
          total += wt;
        }
      }
    if (brush.empty()) {
      brush.push_back({0, 0, 1.0f});
      total = 1.0;
    }
    for (auto& t : brush) t.w = static_cast<float>(t.w / total);
  }
  std::vector<long> tap_offset;
  for (const auto& t : brush) tap_offset.push_back(static_cast<long>(t.dj) * w + t.di);
  float w_centre = 0.0f;
  for (const auto& t : brush)
    if (t.di == 0 && t.dj == 0) w_centre = t.w;
  // The erosion of one step never lowers the brush centre by more than the drop: volume <= -dh x area / w0.
  const double brush_area = cell_area / std::max(w_centre, 1e-6f);

  std::vector<float> z = in.data;
  std::vector<std::uint32_t> visits(z.size(), 0);
  std::vector<DropletLog> logs(kParticleBatch);
  ParticleStats st;
  st.droplets = droplets;

  const double step_u = p.step_length / dx, step_v = p.step_length / dy;
  const double inv_dx = 1.0 / dx, inv_dy = 1.0 / dy, inv_cell_area = 1.0 / cell_area, inv_step = 1.0 / p.step_length;
  std::vector<float> brush_w;
  for (const auto& t : brush) brush_w.push_back(t.w);
  const double inertia = std::clamp(p.inertia, 0.0, 1.0);

  auto height_grad = [&](double u, double v, double& hgt, double& gx, double& gy) {
    const int i = std::min(static_cast<int>(u), w - 2), j = std::min(static_cast<int>(v), h - 2);
    const double fu = u - i, fv = v - j;
    const std::size_t k = static_cast<std::size_t>(j) * w + i;
    const double a = z[k], b = z[k + 1], c = z[k + w], d = z[k + w + 1];
    gx = ((b - a) * (1 - fv) + (d - c) * fv) * inv_dx;
    gy = ((c - a) * (1 - fu) + (d - b) * fu) * inv_dy;
    hgt = a * (1 - fu) * (1 - fv) + b * fu * (1 - fv) + c * (1 - fu) * fv + d * fu * fv;
  };

  // One droplet's state; step() advances it one step and returns false when it has ended. Droplets are
  // independent within a batch (frozen heights, own logs), so a thread advances a group of them in lock
  // step: the cache misses of their height reads overlap (memory-level parallelism) while every droplet
  // computes exactly what it would alone.
  struct Droplet {
    std::uint64_t key;
    DropletLog* log;
    double u, v, dirx, diry, speed, water, sed, hgt, gx, gy;
    double nu, nv;  // the next position (move), read by advance
    std::size_t node;
    int ni, nj, s;
  };
  auto deposit = [&](DropletLog& log, double amt, double uu, double vv) {
    const int i = std::min(static_cast<int>(uu), w - 2), j = std::min(static_cast<int>(vv), h - 2);
    log.changes.push_back({static_cast<std::uint32_t>(j * w + i), i, j, static_cast<float>(amt * inv_cell_area),
                           static_cast<float>(uu - i), static_cast<float>(vv - j)});
    log.deposited += amt;
  };
  auto start = [&](std::uint64_t id, DropletLog& log, Droplet& d) {
    log.changes.clear();
    log.visits.clear();
    log.eroded = log.deposited = log.carried_off = 0.0;
    log.steps = 0;
    d.key = hash64(p.seed, id);
    d.log = &log;
    d.u = hash01(d.key, 1) * (w - 1);
    d.v = hash01(d.key, 2) * (h - 1);
    d.dirx = d.diry = 0.0;
    d.speed = d.water = 1.0;
    d.sed = 0.0;
    d.s = 0;
    // Heights are frozen during a batch, so the height and gradient at the new position carry over.
    height_grad(d.u, d.v, d.hgt, d.gx, d.gy);
  };
  auto finish = [&](Droplet& d) {
    // End of life: what the droplet still carries settles where it stopped.
    if (d.sed > 0) deposit(*d.log, d.sed, d.u, d.v);
  };
  // A step in two halves: move() picks the direction and the next position and prefetches the heights
  // there; advance() reads them and erodes or deposits. A group runs move() for all its droplets before
  // advance(), so their cache misses overlap.
  auto move = [&](Droplet& d) -> bool {
    DropletLog& log = *d.log;
    d.ni = static_cast<int>(d.u + 0.5);
    d.nj = static_cast<int>(d.v + 0.5);
    d.node = static_cast<std::size_t>(d.nj) * w + d.ni;
    log.visits.push_back(static_cast<std::uint32_t>(d.node));
    ++log.steps;
    double dirx = d.dirx * inertia - d.gx * (1 - inertia);
    double diry = d.diry * inertia - d.gy * (1 - inertia);
    double len = std::sqrt(dirx * dirx + diry * diry);
    if (len < 1e-12) {
      const double a = 2.0 * M_PI * hash01(d.key, 16 + static_cast<std::uint64_t>(d.s));
      dirx = std::cos(a);
      diry = std::sin(a);
      len = 1.0;
    }
    const double inv_len = 1.0 / len;
    dirx *= inv_len;
    diry *= inv_len;
    d.dirx = dirx;
    d.diry = diry;
    d.nu = d.u + dirx * step_u;
    d.nv = d.v + diry * step_v;
    if (!(d.nu >= 0 && d.nu <= w - 1 && d.nv >= 0 && d.nv <= h - 1)) {
      log.carried_off += d.sed;
      d.sed = 0;
      return false;
    }
    const int i = std::min(static_cast<int>(d.nu), w - 2), j = std::min(static_cast<int>(d.nv), h - 2);
    const float* zk = z.data() + static_cast<std::size_t>(j) * w + i;
    __builtin_prefetch(zk);
    __builtin_prefetch(zk + 1);
    __builtin_prefetch(zk + w);
    __builtin_prefetch(zk + w + 1);
    return true;
  };
  auto advance = [&](Droplet& d) -> bool {
    DropletLog& log = *d.log;
    const int ni = d.ni, nj = d.nj;
    const std::size_t node = d.node;
    const double nu = d.nu, nv = d.nv;
    double nh, ngx, ngy;
    height_grad(nu, nv, nh, ngx, ngy);
    const double dh = nh - d.hgt;
    const double m = mask ? mask_at(mask, node) : 1.0;
    const double cap = std::max(-dh * inv_step, p.min_slope) * d.speed * d.water * p.capacity;
    if (dh > 0 || d.sed > cap) {
      const double amt = dh > 0 ? std::min(dh * cell_area, d.sed) : (d.sed - cap) * p.deposition * m;
      if (amt > 0) {
        d.sed -= amt;
        deposit(log, amt, d.u, d.v);
      }
    } else {
      const double amt = std::min((cap - d.sed) * p.erosion, -dh * brush_area) * m;
      if (amt > 0) {
        // Taps outside the grid are dropped and the rest renormalised.
        double inside = 1.0;
        if (ni < rx || nj < ry || ni + rx >= w || nj + ry >= h) {
          inside = 0.0;
          for (const auto& t : brush) {
            const int i = ni + t.di, j = nj + t.dj;
            if (i >= 0 && i < w && j >= 0 && j < h) inside += t.w;
          }
        }
        log.changes.push_back({static_cast<std::uint32_t>(node), ni, nj, static_cast<float>(-amt * inv_cell_area / inside), -1.0f, 0.0f});
        log.eroded += amt;
        d.sed += amt;
      }
    }
    d.speed = std::sqrt(std::max(0.0, d.speed * d.speed - dh * p.gravity));
    d.water *= (1.0 - p.evaporation);
    d.u = nu;
    d.v = nv;
    d.hgt = nh;
    d.gx = ngx;
    d.gy = ngy;
    return ++d.s < max_steps;
  };
  // Droplets first..first+count-1 of a batch, kGroup at a time in lock step; an ended droplet's slot takes
  // the next droplet of the range.
  constexpr int kGroup = 16;
  auto simulate_range = [&](std::uint64_t first, int k0, int k1) {
    Droplet group[kGroup];
    int live = 0, next = k0;
    while (live < kGroup && next < k1) {
      start(first + static_cast<std::uint64_t>(next), logs[next], group[live]);
      ++live, ++next;
    }
    bool moved[kGroup];
    while (live > 0) {
      for (int g = 0; g < live; ++g) moved[g] = move(group[g]);
      for (int g = 0; g < live; ++g) moved[g] = moved[g] && advance(group[g]);
      // Ended droplets settle; their slots take the next droplets (the survivors keep their order).
      int kept = 0;
      for (int g = 0; g < live; ++g) {
        if (moved[g]) {
          group[kept++] = group[g];
          continue;
        }
        finish(group[g]);
      }
      live = kept;
      while (live < kGroup && next < k1) {
        start(first + static_cast<std::uint64_t>(next), logs[next], group[live]);
        ++live, ++next;
      }
    }
  };

  const std::uint64_t batches = (droplets + kParticleBatch - 1) / kParticleBatch;
  for (std::uint64_t b = 0; b < batches; ++b) {
    check_cancelled(ctx);
    const std::uint64_t first = b * kParticleBatch;
    const int count = static_cast<int>(std::min<std::uint64_t>(kParticleBatch, droplets - first));
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 16), [&](const tbb::blocked_range<int>& r) {
      simulate_range(first, r.begin(), r.end());
    });
    // Apply in droplet order: every sample receives its changes in the same order for any thread count.
    // Bands of rows in parallel; each band walks all changes of the batch in order and applies the taps
    // that fall in its rows (the band split does not change any sample's sequence of additions).
    // One band per worker: the band count does not affect the result, only the speed.
    const int bands = std::max(1, std::min(h / 4, tbb::this_task_arena::max_concurrency()));
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& br) {
      for (int band = br.begin(); band != br.end(); ++band) {
        const int j0 = static_cast<int>(static_cast<long>(h) * band / bands);
        const int j1 = static_cast<int>(static_cast<long>(h) * (band + 1) / bands);
        for (int k = 0; k < count; ++k) {
          const DropletLog& log = logs[k];
          for (const Change& c : log.changes) {
            const int ci = c.ci, cj = c.cj;
            if (c.fu >= 0.0f) {
              if (cj + 1 < j0 || cj >= j1) continue;
              const float a = c.amount, fu = c.fu, fv = c.fv;
              if (cj >= j0) {
                z[c.node] += a * (1 - fu) * (1 - fv);
                z[c.node + 1] += a * fu * (1 - fv);
              }
              if (cj + 1 < j1) {
                z[c.node + w] += a * (1 - fu) * fv;
                z[c.node + w + 1] += a * fu * fv;
              }
            } else {
              if (cj + ry < j0 || cj - ry >= j1) continue;
              if (ci >= rx && ci + rx < w && cj - ry >= j0 && cj + ry < j1) {  // wholly inside: no checks
                float* zc = z.data() + c.node;
                const float a = c.amount;
                const long* to = tap_offset.data();
                const float* bw = brush_w.data();
                const std::size_t nt = brush_w.size();
                for (std::size_t q = 0; q < nt; ++q) zc[to[q]] += a * bw[q];
                continue;
              }
              for (const auto& t : brush) {
                const int i = ci + t.di, j = cj + t.dj;
                if (j < j0 || j >= j1 || i < 0 || i >= w) continue;
                z[static_cast<std::size_t>(j) * w + i] += c.amount * t.w;
              }
            }
          }
          // Rows j0..j1 are the nodes j0 w .. j1 w: no division per visit.
          const std::uint32_t v0 = static_cast<std::uint32_t>(j0) * static_cast<std::uint32_t>(w);
          const std::uint32_t v1 = static_cast<std::uint32_t>(j1) * static_cast<std::uint32_t>(w);
          for (std::uint32_t vi : log.visits)
            if (vi >= v0 && vi < v1) ++visits[vi];
        }
      }
    });
    for (int k = 0; k < count; ++k) {
      st.eroded += logs[k].eroded;
      st.deposited += logs[k].deposited;
      st.carried_off += logs[k].carried_off;
      st.steps += logs[k].steps;
    }
    report(ctx, static_cast<double>(b + 1) / static_cast<double>(batches));
  }
  if (stats) *stats = st;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.out->data = std::move(z);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  // Flow: visits per unit length of path crossing a cell, log-scaled to 0..1.
  std::uint32_t vmax = 0;
  for (auto v : visits) vmax = std::max(vmax, v);
  const double lmax = std::log1p(static_cast<double>(vmax));
  for (std::size_t k = 0; k < visits.size(); ++k)
    maps.flow->data[k] = lmax > 0 ? static_cast<float>(std::log1p(static_cast<double>(visits[k])) / lmax) : 0.0f;
  fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
