#include "nodes/erosion/particles.h"

#include <algorithm>
#include <cmath>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace orogen::erosion {
namespace {

struct TileStats {
  double eroded = 0.0, deposited = 0.0, carried_off = 0.0;  // m^3
  std::uint64_t steps = 0;
};

// Adds a x weight to the brush rows around zc (W > 0: rows of W weights known at compile time; widths are
// multiples of 4, so SSE takes 4 at a time, the same product and sum per sample as scalar code).
template <int W>
inline void brush_rows(float* zc, float a, const std::ptrdiff_t* __restrict RO, const float* __restrict RW, int rows,
                       int row_width) {
  const int n = W > 0 ? W : row_width;
#if defined(__SSE2__)
  const __m128 va = _mm_set1_ps(a);
  for (int r = 0; r < rows; ++r) {
    float* zr = zc + RO[r];
    const float* wr = RW + static_cast<std::size_t>(r) * n;
    for (int q = 0; q < n; q += 4)
      _mm_storeu_ps(zr + q, _mm_add_ps(_mm_loadu_ps(zr + q), _mm_mul_ps(va, _mm_loadu_ps(wr + q))));
  }
#else
  for (int r = 0; r < rows; ++r) {
    float* __restrict zr = zc + RO[r];
    const float* __restrict wr = RW + static_cast<std::size_t>(r) * n;
    for (int q = 0; q < n; ++q) zr[q] += a * wr[q];
  }
#endif
}

struct BrushTap {
  int di, dj;
  float w;
};

// One droplet's simulation over the shared heights (the parameters copied into locals first: stores to the
// heights cannot then alias them, and they stay in registers).
struct Sim {
  float* Z;
  std::uint32_t* V;
  const Heightfield* mask;
  const std::vector<BrushTap>* brush;
  const std::ptrdiff_t* RO;  // brush rows: offset of each row's first column from the centre sample
  const float* RW;           // brush rows: row_width weights each (0 outside the disc and in the padding)
  int rows, row_width;
  int w, h, rx, ry, max_steps;
  std::uint64_t seed;
  float step_u, step_v, inv_dx, inv_dy, cell_area, inv_cell_area, inv_step, inertia, min_slope, capacity,
      deposition, erosion, gravity, keep_water, brush_area;

  // amt m^3 spread bilinearly over the 4 samples around (u, v).
  static void deposit(float* Z, int w, int h, float a, float u, float v) {
    const int i = std::min(static_cast<int>(u), w - 2), j = std::min(static_cast<int>(v), h - 2);
    const float fu = u - static_cast<float>(i), fv = v - static_cast<float>(j);
    float* zk = Z + static_cast<std::size_t>(j) * w + i;
    zk[0] += a * (1 - fu) * (1 - fv);
    zk[1] += a * fu * (1 - fv);
    zk[w] += a * (1 - fu) * fv;
    zk[w + 1] += a * fu * fv;
  }
  // a m of height (per unit weight) removed with the brush around a sample near the border: taps outside
  // the grid are dropped and the rest renormalised.
  void erode_border(float a, int ni, int nj) const {
    float inside = 0.0f;
    for (const auto& t : *brush) {
      const int i = ni + t.di, j = nj + t.dj;
      if (i >= 0 && i < w && j >= 0 && j < h) inside += t.w;
    }
    a /= inside;
    for (const auto& t : *brush) {
      const int i = ni + t.di, j = nj + t.dj;
      if (i >= 0 && i < w && j >= 0 && j < h) Z[static_cast<std::size_t>(j) * w + i] += a * t.w;
    }
  }

  struct Drop {
    std::uint64_t key;
    float u, v, dirx, diry, speed, water, sed, hgt, gx, gy;
    int s;
  };
  // Droplets in flight per tile, stepped in turn (a fixed order: part of the schedule, not of the thread
  // count). Measured: 2 or 4 lanes were 8% slower than 1 (the erode/deposit branch mispredicts flush the
  // overlap they would buy), so one.
  static constexpr int kLanes = 1;

  // The droplets first + ids[0..count) of one tile: kLanes at a time, each ended droplet's lane taking the
  // next droplet of the list.
  void run_tile(std::uint64_t first, const std::uint32_t* ids, std::uint32_t count, TileStats& ts) const {
    float* __restrict const Z = this->Z;
    std::uint32_t* __restrict const V = this->V;
    const std::ptrdiff_t* __restrict const RO = this->RO;
    const float* __restrict const RW = this->RW;
    const int rows = this->rows, row_width = this->row_width;
    const int w = this->w, h = this->h, rx = this->rx, ry = this->ry, max_steps = this->max_steps;
    const float step_u = this->step_u, step_v = this->step_v, inv_dx = this->inv_dx, inv_dy = this->inv_dy;
    const float cell_area = this->cell_area, inv_cell_area = this->inv_cell_area, inv_step = this->inv_step;
    const float inertia = this->inertia, min_slope = this->min_slope, capacity = this->capacity;
    const float deposition = this->deposition, erosion = this->erosion, gravity = this->gravity;
    const float keep_water = this->keep_water, brush_area = this->brush_area;
    const float umax = static_cast<float>(w - 1), vmax = static_cast<float>(h - 1);
    const Heightfield* mask = this->mask;
    double eroded = 0, deposited = 0, carried_off = 0;
    std::uint64_t steps = 0;

    auto height_grad = [&](float u, float v, float& hgt, float& gx, float& gy) {
      const int i = std::min(static_cast<int>(u), w - 2), j = std::min(static_cast<int>(v), h - 2);
      const float fu = u - static_cast<float>(i), fv = v - static_cast<float>(j);
      const float* zk = Z + static_cast<std::size_t>(j) * w + i;
      const float a = zk[0], b = zk[1], c = zk[w], d = zk[w + 1];
      gx = ((b - a) * (1 - fv) + (d - c) * fv) * inv_dx;
      gy = ((c - a) * (1 - fu) + (d - b) * fu) * inv_dy;
      hgt = (a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv;
    };
    auto start = [&](Drop& d, std::uint64_t id) {
      d.key = hash64(seed, id);
      d.u = static_cast<float>(hash01(d.key, 1) * (w - 1));
      d.v = static_cast<float>(hash01(d.key, 2) * (h - 1));
      d.dirx = d.diry = d.sed = 0;
      d.speed = d.water = 1;
      d.s = 0;
      height_grad(d.u, d.v, d.hgt, d.gx, d.gy);
    };
    // One step; false when the droplet has ended (and settled what it carried).
    auto step = [&](Drop& d) -> bool {
      const float u = d.u, v = d.v;
      const int ni = static_cast<int>(u + 0.5f), nj = static_cast<int>(v + 0.5f);
      const std::size_t node = static_cast<std::size_t>(nj) * w + ni;
      ++V[node];
      ++steps;
      float dirx = d.dirx * inertia - d.gx * (1 - inertia);
      float diry = d.diry * inertia - d.gy * (1 - inertia);
      const float len2 = dirx * dirx + diry * diry;
      if (len2 > 1e-24f) [[likely]] {
        const float inv_len = 1.0f / std::sqrt(len2);
        dirx *= inv_len;
        diry *= inv_len;
      } else {
        const double a = 2.0 * M_PI * hash01(d.key, 16 + static_cast<std::uint64_t>(d.s));
        dirx = static_cast<float>(std::cos(a));
        diry = static_cast<float>(std::sin(a));
      }
      const float nu = u + dirx * step_u, nv = v + diry * step_v;
      if (!(nu >= 0 && nu <= umax && nv >= 0 && nv <= vmax)) [[unlikely]] {
        carried_off += d.sed;
        return false;
      }
      float nh, ngx, ngy;
      height_grad(nu, nv, nh, ngx, ngy);
      const float dh = nh - d.hgt;
      const float m = mask ? mask_at(mask, node) : 1.0f;
      float sed = d.sed;
      const float cap = std::max(-dh * inv_step, min_slope) * d.speed * d.water * capacity;
      // Uphill: fill the pit up to what it carries; over capacity: deposit a share of the surplus; else erode
      // a share of the free capacity, at most the drop, with the brush.
      if (dh > 0 || sed > cap) {
        const float amt = dh > 0 ? std::min(dh * cell_area, sed) : (sed - cap) * deposition * m;
        if (amt > 0) {
          sed -= amt;
          deposit(Z, w, h, amt * inv_cell_area, u, v);
          deposited += amt;
        }
      } else {
        const float amt = std::min((cap - sed) * erosion, -dh * brush_area) * m;
        if (amt > 0) {
          const float a = -amt * inv_cell_area;
          if (ni >= rx && nj >= ry && ni - rx + row_width <= w && nj + ry < h) [[likely]] {
            float* __restrict zc = Z + node;
            // Row by row over padded rows of a multiple of 4 weights: the inner loop vectorises.
            switch (row_width) {  // fixed widths unroll to whole vectors
              case 4: brush_rows<4>(zc, a, RO, RW, rows, 4); break;
              case 8: brush_rows<8>(zc, a, RO, RW, rows, 8); break;
              case 12: brush_rows<12>(zc, a, RO, RW, rows, 12); break;
              case 16: brush_rows<16>(zc, a, RO, RW, rows, 16); break;
              default: brush_rows<0>(zc, a, RO, RW, rows, row_width);
            }
          } else {
            erode_border(a, ni, nj);
          }
          eroded += amt;
          sed += amt;
        }
      }
      d.speed = std::sqrt(std::max(0.0f, d.speed * d.speed - dh * gravity));
      d.water *= keep_water;
      d.dirx = dirx, d.diry = diry;
      d.u = nu, d.v = nv, d.hgt = nh, d.gx = ngx, d.gy = ngy;
      d.sed = sed;
      if (++d.s < max_steps) return true;
      // End of life: what the droplet still carries settles where it stopped.
      if (sed > 0) {
        deposit(Z, w, h, sed * inv_cell_area, nu, nv);
        deposited += sed;
      }
      return false;
    };

    Drop lane[kLanes];
    int live = 0;
    std::uint32_t next = 0;
    while (live < kLanes && next < count) start(lane[live++], first + ids[next++]);
    while (live > 0) {
      for (int g = 0; g < live;) {
        if (step(lane[g])) {
          ++g;
        } else if (next < count) {
          start(lane[g], first + ids[next++]);
          ++g;
        } else {
          lane[g] = lane[--live];
        }
      }
    }
    ts.eroded += eroded;
    ts.deposited += deposited;
    ts.carried_off += carried_off;
    ts.steps += steps;
  }
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

  // Brush around the nearest sample: weights 1 - distance / radius, normalised; a table of offsets and
  // weights computed once.
  std::vector<BrushTap> brush_taps;
  auto& brush = brush_taps;
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
  // The brush as rows of columns -rx .. -rx + row_width - 1, row_width the multiple of 4 at or above
  // 2 rx + 1 (the padding and the corners outside the disc weigh 0: adding a * 0 changes no height); rows
  // without a tap are left out.
  const int row_width = (2 * rx + 1 + 3) / 4 * 4, pad = row_width - (2 * rx + 1);
  std::vector<std::ptrdiff_t> row_offset;
  std::vector<float> row_weights;
  float w_centre = 0.0f;
  for (int dj = -ry; dj <= ry; ++dj) {
    std::vector<float> row(row_width, 0.0f);
    bool any = false;
    for (const auto& t : brush)
      if (t.dj == dj) row[t.di + rx] = t.w, any = true;
    if (!any) continue;
    row_offset.push_back(static_cast<std::ptrdiff_t>(dj) * w - rx);
    row_weights.insert(row_weights.end(), row.begin(), row.end());
  }
  for (const auto& t : brush)
    if (t.di == 0 && t.dj == 0) w_centre = t.w;
  // The erosion of one step never lowers the brush centre by more than the drop: volume <= -dh x area / w0.
  const float brush_area = static_cast<float>(cell_area / std::max(w_centre, 1e-6f));

  std::vector<float> z = in.data;
  std::vector<std::uint32_t> visits(z.size(), 0);

  // Schedule (the determinism): droplets run in rounds of a fixed number (set by the grid, not the thread
  // count). A round bins its droplets by the tile of the grid their origin falls in; tiles are at least twice
  // a droplet's reach (lifetime + brush + 2 samples) wide and high, so two tiles of the same colour of a 2 x 2
  // checkerboard never touch the same sample. The four colours run one after the other; the tiles of one
  // colour run in parallel, each tile's droplets one after the other in index order, changing the heights
  // directly (every droplet sees the changes of the droplets before it, as in Beyer's serial loop). Every
  // sample therefore receives the same changes in the same order for any thread count: bit-identical, with
  // no atomics and no change logs, and a tile's samples stay in cache while its droplets run.
  const float step_u = static_cast<float>(p.step_length / dx), step_v = static_cast<float>(p.step_length / dy);
  // (+2: the bilinear neighbour and rounding to the nearest sample, which also cover one column of the brush
  // rows' padding; more padding widens the reach.)
  const double reach_u = max_steps * static_cast<double>(step_u) + rx + 2.0 + std::max(0, pad - 1);
  const double reach_v = max_steps * static_cast<double>(step_v) + ry + 2.0;
  const int tile_w = static_cast<int>(std::min<double>(w, std::max(32.0, 2.0 * std::ceil(reach_u))));
  const int tile_h = static_cast<int>(std::min<double>(h, std::max(32.0, 2.0 * std::ceil(reach_v))));
  const int tiles_x = (w + tile_w - 1) / tile_w, tiles_y = (h + tile_h - 1) / tile_h;
  const int tiles = tiles_x * tiles_y;
  std::vector<int> colour_tiles[4];
  for (int ty = 0; ty < tiles_y; ++ty)
    for (int tx = 0; tx < tiles_x; ++tx) colour_tiles[(ty & 1) * 2 + (tx & 1)].push_back(ty * tiles_x + tx);
  const std::uint64_t round_size = std::max<std::uint64_t>(4096, static_cast<std::uint64_t>(w) * h / 8);
  std::vector<std::uint32_t> tile_start(tiles + 1), order(static_cast<std::size_t>(std::min(round_size, droplets)));
  std::vector<std::uint32_t> tile_of(order.size());
  std::vector<TileStats> tile_stats(tiles);

  Sim sim;
  sim.Z = z.data();
  sim.V = visits.data();
  sim.mask = mask;
  sim.brush = &brush_taps;
  sim.RO = row_offset.data();
  sim.RW = row_weights.data();
  sim.rows = static_cast<int>(row_offset.size());
  sim.row_width = row_width;
  sim.w = w, sim.h = h, sim.rx = rx, sim.ry = ry, sim.max_steps = max_steps;
  sim.seed = p.seed;
  sim.step_u = step_u, sim.step_v = step_v;
  sim.inv_dx = static_cast<float>(1.0 / dx), sim.inv_dy = static_cast<float>(1.0 / dy);
  sim.cell_area = static_cast<float>(cell_area), sim.inv_cell_area = static_cast<float>(1.0 / cell_area);
  sim.inv_step = static_cast<float>(1.0 / p.step_length);
  sim.inertia = static_cast<float>(std::clamp(p.inertia, 0.0, 1.0));
  sim.min_slope = static_cast<float>(p.min_slope), sim.capacity = static_cast<float>(p.capacity);
  sim.deposition = static_cast<float>(p.deposition), sim.erosion = static_cast<float>(p.erosion);
  sim.gravity = static_cast<float>(p.gravity), sim.keep_water = static_cast<float>(1.0 - p.evaporation);
  sim.brush_area = brush_area;

  const std::uint64_t rounds = (droplets + round_size - 1) / round_size;
  for (std::uint64_t r = 0; r < rounds; ++r) {
    check_cancelled(ctx);
    const std::uint64_t first = r * round_size;
    const std::uint32_t count = static_cast<std::uint32_t>(std::min(round_size, droplets - first));
    // Bin the round's droplets by the tile of their origin (a counting sort keeps index order per tile).
    std::fill(tile_start.begin(), tile_start.end(), 0u);
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint64_t key = hash64(p.seed, first + k);
      const int i = static_cast<int>(static_cast<float>(hash01(key, 1) * (w - 1)));
      const int j = static_cast<int>(static_cast<float>(hash01(key, 2) * (h - 1)));
      const std::uint32_t t = static_cast<std::uint32_t>(std::min(j / tile_h, tiles_y - 1) * tiles_x + std::min(i / tile_w, tiles_x - 1));
      tile_of[k] = t;
      ++tile_start[t + 1];
    }
    for (int t = 0; t < tiles; ++t) tile_start[t + 1] += tile_start[t];
    {
      std::vector<std::uint32_t> fill(tile_start.begin(), tile_start.end() - 1);
      for (std::uint32_t k = 0; k < count; ++k) order[fill[tile_of[k]]++] = k;
    }
    for (int c = 0; c < 4; ++c) {
      const auto& list = colour_tiles[c];
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, list.size(), 1), [&](const tbb::blocked_range<std::size_t>& br) {
        for (std::size_t q = br.begin(); q != br.end(); ++q) {
          const int t = list[q];
          sim.run_tile(first, order.data() + tile_start[t], tile_start[t + 1] - tile_start[t], tile_stats[t]);
        }
      });
      check_cancelled(ctx);
      report(ctx, (static_cast<double>(r) + (c + 1) / 4.0) / static_cast<double>(rounds));
    }
  }
  ParticleStats st;
  st.droplets = droplets;
  for (const auto& ts : tile_stats) {
    st.eroded += ts.eroded;
    st.deposited += ts.deposited;
    st.carried_off += ts.carried_off;
    st.steps += ts.steps;
  }
  if (stats) *stats = st;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.out->data = std::move(z);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  // Flow: visits per unit length of path crossing a cell, log-scaled to 0..1 (a table per visit count).
  std::uint32_t vmax_visits = 0;
  for (auto vv : visits) vmax_visits = std::max(vmax_visits, vv);
  const double lmax = std::log1p(static_cast<double>(vmax_visits));
  if (lmax > 0) {
    std::vector<float> table(std::min<std::size_t>(vmax_visits, 1u << 20) + 1);
    for (std::size_t k = 0; k < table.size(); ++k) table[k] = static_cast<float>(std::log1p(static_cast<double>(k)) / lmax);
    for (std::size_t k = 0; k < visits.size(); ++k)
      maps.flow->data[k] = visits[k] < table.size() ? table[visits[k]]
                                                   : static_cast<float>(std::log1p(static_cast<double>(visits[k])) / lmax);
  }
  fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
