#include "nodes/erosion/particles.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <hwy/targets.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/common/cancellable_rows.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/common/work_bounds.h"
#include "nodes/common/work_poll.h"
#include "nodes/erosion/droplet_schedule.h"

namespace orogen::erosion {
namespace {

// One tile's droplets for run_tiles: indices (from the round's first) in their order, and its totals.
struct TileRun {
  const std::uint32_t* ids;
  std::uint32_t count;
  DropletBlockStats* stats;
};

// (The 8-lane helpers are only inlined: GCC's note that passing 32-byte vectors by value without AVX changes
// the calling convention concerns no call here.)
#pragma GCC diagnostic ignored "-Wpsabi"

// Four or eight floats (ints), one per droplet lane: GCC/Clang vector extensions, SSE2 on x86-64 (eight: two
// SSE2 registers, or one AVX register in code compiled for AVX2). Comparisons give lane masks (-1 or 0).
using f4 = float __attribute__((vector_size(16)));
using i4 = std::int32_t __attribute__((vector_size(16)));
using f8 = float __attribute__((vector_size(32)));
using i8 = std::int32_t __attribute__((vector_size(32)));
using d2 = double __attribute__((vector_size(16)));

template <class F, class I>
inline F sel(I m, F a, F b) {            // m ? a : b per lane
  return (F)((m & (I)a) | (~m & (I)b));  // vector casts keep the bits
}
template <class F>
inline F min_v(F a, F b) {  // std::min per lane
  return sel(b < a, b, a);
}
template <class F>
inline F max_v(F a, F b) {  // std::max per lane
  return sel(a < b, b, a);
}
// Lanes 4q .. 4q + 3 of v (q = 0 of a 4-lane vector: itself); two 4-lane vectors as one of 8.
template <class Q, class V>
inline Q quarter(const V& v, int q) {
  Q r;
  std::memcpy(&r, reinterpret_cast<const char*>(&v) + sizeof r * q, sizeof r);
  return r;
}
inline f4 quarter(const f4& v, int q) { return quarter<f4>(v, q); }
inline f4 quarter(const f8& v, int q) { return quarter<f4>(v, q); }
inline i4 quarter(const i8& v, int q) { return quarter<i4>(v, q); }
inline f8 join(f4 lo, f4 hi) { return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7); }
inline f4 vsqrt(f4 a) {
#if defined(__SSE2__)
  return _mm_sqrt_ps(a);
#else
  for (int k = 0; k < 4; ++k) a[k] = std::sqrt(a[k]);
  return a;
#endif
}
inline f8 vsqrt(f8 a) { return join(vsqrt(quarter(a, 0)), vsqrt(quarter(a, 1))); }
inline int movemask(i4 m) {  // bit k: lane k set
#if defined(__SSE2__)
  return _mm_movemask_ps((__m128)m);
#else
  return (m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8);
#endif
}
inline int movemask(i8 m) { return movemask(quarter(m, 0)) | movemask(quarter(m, 1)) << 4; }
template <class I>
inline bool any(I m) {
  return movemask(m) != 0;
}

// The 2 x 2 samples (a b / c d) of the cells (i[k], j[k]) of the four lanes, read one float at a time (an
// 8-byte read across two of the brush's vector stores could not be forwarded from them), then transposed
// into one vector per corner.
inline void gather_cells(const float* Z, int pitch, std::ptrdiff_t origin, i4 i, i4 j, f4& a, f4& b, f4& c, f4& d) {
#if defined(__SSE2__)
  __m128 ab[4], cd[4];
  for (int k = 0; k < 4; ++k) {
    const float* zk = Z + (static_cast<std::ptrdiff_t>(j[k]) * pitch + i[k] - origin);
    ab[k] = _mm_unpacklo_ps(_mm_load_ss(zk), _mm_load_ss(zk + 1));
    cd[k] = _mm_unpacklo_ps(_mm_load_ss(zk + pitch), _mm_load_ss(zk + pitch + 1));
  }
  const __m128 t01 = _mm_unpacklo_ps(ab[0], ab[1]), t23 = _mm_unpacklo_ps(ab[2], ab[3]);
  const __m128 b01 = _mm_unpacklo_ps(cd[0], cd[1]), b23 = _mm_unpacklo_ps(cd[2], cd[3]);
  a = _mm_movelh_ps(t01, t23), b = _mm_movehl_ps(t23, t01);
  c = _mm_movelh_ps(b01, b23), d = _mm_movehl_ps(b23, b01);
#else
  for (int k = 0; k < 4; ++k) {
    const float* zk = Z + (static_cast<std::ptrdiff_t>(j[k]) * pitch + i[k] - origin);
    a[k] = zk[0], b[k] = zk[1], c[k] = zk[pitch], d[k] = zk[pitch + 1];
  }
#endif
}
inline void gather_cells(const float* Z, int pitch, std::ptrdiff_t origin, i8 i, i8 j, f8& a, f8& b, f8& c, f8& d) {
  f4 a0, b0, c0, d0, a1, b1, c1, d1;
  gather_cells(Z, pitch, origin, quarter(i, 0), quarter(j, 0), a0, b0, c0, d0);
  gather_cells(Z, pitch, origin, quarter(i, 1), quarter(j, 1), a1, b1, c1, d1);
  a = join(a0, a1), b = join(b0, b1), c = join(c0, c1), d = join(d0, d1);
}

inline f4 load4(const float* p) {
  f4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(float* p, f4 v) { std::memcpy(p, &v, sizeof v); }

// Adds a x weight to the brush rows, the first at zr, rows `stride` apart: W weights a row (a multiple of 4),
// R rows (R = 0: `rows`, W = 0: `row_width`, known at run time only), Wide floats at a time while they fit
// (8: only inlined into code compiled for AVX2), then 4. The weights' rows start 16-byte aligned (a vector's
// storage, rows of a multiple of 4 floats). Each sample gets one product and one sum whatever the width.
template <int W, int R, int Wide>
[[gnu::always_inline]] inline void brush_rows(float* zr, float a, std::ptrdiff_t stride, const float* __restrict RW,
                                              int rows, int row_width) {
  const int n = W > 0 ? W : row_width, nr = R > 0 ? R : rows;
  const f4 av = f4{} + a;
  for (int r = 0; r < nr; ++r, zr += stride, RW += n) {
    int q = 0;
    if constexpr (Wide == 8) {
      for (; q + 8 <= n; q += 8) {
        f8 z8, w8;
        std::memcpy(&z8, zr + q, sizeof z8);
        std::memcpy(&w8, RW + q, sizeof w8);
        z8 += (f8{} + a) * w8;
        std::memcpy(zr + q, &z8, sizeof z8);
      }
    }
    for (; q < n; q += 4) {
      const f4 wq = load4(static_cast<const float*>(__builtin_assume_aligned(RW + q, 16)));
      store4(zr + q, load4(zr + q) + av * wq);
    }
  }
}

// A droplet's origin in samples, 0 <= u <= w - 1, 0 <= v <= h - 1, from its key hash64(seed, index): where it
// starts and which tile it is binned to.
inline void droplet_origin(std::uint64_t key, int w, int h, float& u, float& v) {
  u = static_cast<float>(hash01(key, 1) * (w - 1));
  v = static_cast<float>(hash01(key, 2) * (h - 1));
}

// Row pitch (floats) of the droplets' working copy of the heights and of the visit counts: the width, widened
// by 16 floats at a time while one of the next 8 rows starts within 128 bytes of the same offset modulo 4 KiB
// (widths of 1024, 2048, ... samples). The brush stores a row and then reads the rows below it; a read whose
// address matches a pending store's in the low 12 bits (4K aliasing) waits for it, which cost ~10% of the run
// time at 1024^2. The layout changes no value.
inline int row_pitch(int w) {
  auto aliases = [](int pitch) {
    for (long long r = 1; r <= 8; ++r) {
      const long long m = r * pitch * 4 % 4096;
      if (m < 128 || m > 4096 - 128) return true;
    }
    return false;
  };
  int pitch = w;
  while (aliases(pitch)) pitch += 16;
  return pitch;
}

struct BrushTap {
  int di, dj;
  float w;
};

// The droplets' simulation over the shared heights (run_tile copies the parameters into locals first: stores
// to the heights cannot then alias them, and they stay in registers). Positions and sample indices are the whole
// domain's; the grids hold a window of it (DropletGrid), sample (i, j) at j * pitch + i - origin.
struct Sim {
  float* Z;
  std::uint32_t* V;
  const float* M;         // the mask, sample (i, j) at j * mask_pitch + i - mask_origin; nullptr: none
  std::ptrdiff_t origin;  // y0 * pitch + x0 of the window
  std::ptrdiff_t mask_origin;
  int x0 = 0, y0 = 0;  // the window's first sample: where lanes without a droplet read, inside the grids
  int mask_pitch;
  const std::vector<BrushTap>* brush;
  const ExecContext* ctx;  // cancellation, polled by droplet steps (one droplet can take 1e7 steps)
  std::ptrdiff_t row0;     // brush rows: offset of the first row's first column from the centre sample
  const float* RW;         // brush rows: row_width weights each (0 outside the disc and in the padding)
  int rows, row_width;
  int w, h, rx, ry, max_steps;
  int pitch;  // floats from one row of Z (and V) to the next, >= w: see row_pitch
  std::uint64_t seed;
  float step_u, step_v, inv_dx, inv_dy, inv_cell_area, inv_step, inertia, min_slope, capacity, deposition, erosion,
      gravity, keep_water, brush_area;

  // a m of height (per unit weight) added (a > 0) or removed (a < 0) with the brush around a sample near the
  // border: taps outside the grid are dropped and the rest renormalised, so the volume stays a x cell area.
  void brush_border(float a, int ni, int nj) const {
    float inside = 0.0f;
    for (const auto& t : *brush) {
      const int i = ni + t.di, j = nj + t.dj;
      if (i >= 0 && i < w && j >= 0 && j < h) inside += t.w;
    }
    a /= inside;
    for (const auto& t : *brush) {
      const int i = ni + t.di, j = nj + t.dj;
      if (i >= 0 && i < w && j >= 0 && j < h) Z[static_cast<std::ptrdiff_t>(j) * pitch + i - origin] += a * t.w;
    }
  }

  // Droplets in flight per tile, one per lane of a 4-float vector, stepped together (which droplet takes a
  // lane is fixed by the tile's list: part of the schedule, not of the thread count). A droplet step is a
  // chain of dependent latencies (position -> heights -> gradient -> direction -> square root and division
  // -> position) with little work beside it: four independent droplets share the arithmetic of one. Reads
  // (the 2 x 2 heights) happen for the four lanes first, then each lane's changes in lane order, so a
  // droplet sees the changes of the others one step late.
  static constexpr int kLanes = 4;

  // T tiles (1 or 2) of one colour stepped together, kLanes lanes each, in vectors of T x kLanes floats: tiles
  // of one colour touch disjoint samples, so a tile's droplets do exactly what they do alone (AVX2 code steps
  // two tiles in 8-float vectors: the step's arithmetic once for eight droplets).
  // Each tile runs the droplets first + ids[0..count) of its list, an ended droplet's lane taking the next.
  // W, R: the brush rows' width and count when known at compile time (0: at run time).
  // Wide: the brush's vector width (see brush_rows).
  template <int W, int R, int Wide, int T>
  [[gnu::always_inline]] void run_tiles(std::uint64_t first, const TileRun* tiles) const {
    constexpr int N = T * kLanes;
    using F = std::conditional_t<T == 1, f4, f8>;
    using I = std::conditional_t<T == 1, i4, i8>;
    float* __restrict const Z = this->Z;
    std::uint32_t* __restrict const V = this->V;
    const float* __restrict const M = this->M;
    const std::ptrdiff_t origin = this->origin, mask_origin = this->mask_origin;
    const int mask_pitch = this->mask_pitch;
    const float* __restrict const RW = this->RW;
    const std::ptrdiff_t row0 = this->row0;
    const int rows = this->rows, row_width = this->row_width;
    const int w = this->w, h = this->h, rx = this->rx, ry = this->ry, max_steps = this->max_steps;
    const int pitch = this->pitch;
    const float step_u = this->step_u, step_v = this->step_v, inv_dx = this->inv_dx, inv_dy = this->inv_dy;
    const float inv_cell_area = this->inv_cell_area, inv_step = this->inv_step;
    const float inertia = this->inertia, min_slope = this->min_slope, capacity = this->capacity;
    const float deposition = this->deposition, erosion = this->erosion, gravity = this->gravity;
    const float keep_water = this->keep_water, brush_area = this->brush_area;
    const float umax = static_cast<float>(w - 1), vmax = static_cast<float>(h - 1);
    const float imax = static_cast<float>(w - 2), jmax = static_cast<float>(h - 2);
    // Brush centres whose rows lie inside the grid: unsigned (ni - rx) <= bu and (nj - ry) <= bv.
    const bool brush_fits = row_width <= w && 2 * ry + 1 <= h;
    const unsigned bu = static_cast<unsigned>(w - row_width), bv = static_cast<unsigned>(h - 1 - 2 * ry);
    // Per tile: totals (m^3; d2: two lanes at a time) and steps, the lanes in use, the next droplet.
    double eroded[T] = {}, deposited[T] = {}, carried_off[T] = {};
    d2 eroded2[T] = {}, deposited2[T] = {};
    std::uint64_t steps[T] = {};
    int live_count[T] = {};
    std::uint32_t next[T] = {};

    // Lane state: position (samples), its 2 x 2 cell (first sample ci, cj; offsets fu, fv), direction,
    // speed, water, sediment, and the bilinear height and gradient read when the droplet got there.
    // Lanes that never get a droplet read (and change nothing) at the window's first sample.
    F U = F{} + static_cast<float>(this->x0), Vp = F{} + static_cast<float>(this->y0);
    F FU{}, FV{}, DX{}, DY{}, SP{}, WA{}, SE{}, HG{}, GX{}, GY{};
    I CI = I{} + this->x0, CJ = I{} + this->y0, S{};
    std::uint64_t key[N] = {};
    int live = 0;  // bit k: lane k holds a droplet
    I on{};        // the same as lane masks

    // Bilinear height and gradient at (u, v), 0 <= u <= w - 1, 0 <= v <= h - 1, from the 2 x 2 cell
    // (i, j) = (min(floor u, w - 2), min(floor v, h - 2)) with offsets (fu, fv).
    auto bilinear = [&](auto a, auto b, auto c, auto d, auto fu, auto fv, auto& hgt, auto& gx, auto& gy) {
      gx = ((b - a) * (1 - fv) + (d - c) * fv) * inv_dx;
      gy = ((c - a) * (1 - fu) + (d - b) * fu) * inv_dy;
      hgt = (a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv;
    };
    auto start = [&](int k, std::uint64_t id) {
      key[k] = hash64(seed, id);
      float u, v;
      droplet_origin(key[k], w, h, u, v);
      const int i = static_cast<int>(std::min(u, imax)), j = static_cast<int>(std::min(v, jmax));
      const float* zk = Z + (static_cast<std::ptrdiff_t>(j) * pitch + i - origin);
      f4 hgt, gx, gy;
      const float fu = u - static_cast<float>(i), fv = v - static_cast<float>(j);
      bilinear(f4{} + zk[0], f4{} + zk[1], f4{} + zk[pitch], f4{} + zk[pitch + 1], f4{} + fu, f4{} + fv, hgt, gx, gy);
      U[k] = u, Vp[k] = v, CI[k] = i, CJ[k] = j, FU[k] = fu, FV[k] = fv;
      HG[k] = hgt[0], GX[k] = gx[0], GY[k] = gy[0];
      DX[k] = DY[k] = SE[k] = 0;
      SP[k] = WA[k] = 1;
      S[k] = 0;
      live |= 1 << k;
      on[k] = -1;
      ++live_count[k / kLanes];
    };
    // a m of height (per unit weight; a x cell area m^3) added, or removed when negative, with the brush around
    // the sample (ni, nj). Erosion and deposition share the brush: a deposit spread bilinearly over the 2 x 2
    // cell of the droplet left a bump a cell or two across, which on fine grids dams the channel above it into
    // a closed hollow (the pits of issue 29); the brush lays it down as a cone as wide as the erosion's.
    auto apply_brush = [&](float a, int ni, int nj) {
      if (brush_fits && static_cast<unsigned>(ni - rx) <= bu && static_cast<unsigned>(nj - ry) <= bv) [[likely]] {
        // Row by row over padded rows of a multiple of 4 weights (0 outside the disc; adding a x 0 changes
        // nothing, so no branch on whether the step changed anything).
        brush_rows<W, R, Wide>(Z + (static_cast<std::ptrdiff_t>(nj) * pitch + ni + row0 - origin), a, pitch, RW, rows,
                               row_width);
      } else if (a != 0) {
        brush_border(a, ni, nj);
      }
    };

    for (int t = 0; t < T; ++t)
      for (int k = t * kLanes; k < (t + 1) * kLanes && next[t] < tiles[t].count; ++k)
        start(k, first + tiles[t].ids[next[t]++]);
    // Visited samples, counted in batches: the count's read-modify-write of a sample far from the last misses
    // the cache more often than the heights do, and in the step it held up the droplets' chain (~12%); in a
    // loop of its own the misses overlap. Counts are sums: their order changes nothing.
    constexpr int kVisitBatch = 512;
    std::ptrdiff_t visited[kVisitBatch];
    int visit_count = 0;
    auto count_visits = [&] {
      if (V)  // (no flow map: no counts)
        for (int q = 0; q < visit_count; ++q) ++V[visited[q]];
      visit_count = 0;
    };
    WorkPoll poll(ctx);
    while (live) {
      poll();  // one unit: a step of every lane
      if (visit_count > kVisitBatch - N) count_visits();
      for (int t = 0; t < T; ++t) steps[t] += static_cast<unsigned>(live_count[t]);
      // Nearest sample of each position: the brush centre and the visit count.
      const I NI = CI - (FU >= 0.5f), NJ = CJ - (FV >= 0.5f);
      F dirx = DX * inertia - GX * (1 - inertia);
      F diry = DY * inertia - GY * (1 - inertia);
      const F len2 = dirx * dirx + diry * diry;
      const I flat = len2 <= 1e-24f;
      const F inv_len = 1.0f / vsqrt(sel(flat, F{} + 1, len2));
      dirx *= inv_len;
      diry *= inv_len;
      if (any(flat & on)) [[unlikely]] {
        // No slope and no momentum: a random direction.
        for (int k = 0; k < N; ++k)
          if (flat[k]) {
            const double a = 2.0 * M_PI * hash01(key[k], 16 + static_cast<std::uint64_t>(S[k]));
            dirx[k] = static_cast<float>(std::cos(a));
            diry[k] = static_cast<float>(std::sin(a));
          }
      }
      F nu = U + dirx * step_u, nv = Vp + diry * step_v;
      // Lanes that leave the grid (or hold no droplet) read at their old position and change nothing.
      const I in = on & (nu >= 0) & (nu <= umax) & (nv >= 0) & (nv <= vmax);
      nu = sel(in, nu, U), nv = sel(in, nv, Vp);
      const I nci = __builtin_convertvector(min_v(nu, F{} + imax), I);
      const I ncj = __builtin_convertvector(min_v(nv, F{} + jmax), I);
      const F nfu = nu - __builtin_convertvector(nci, F), nfv = nv - __builtin_convertvector(ncj, F);
      F za, zb, zc, zd;
      gather_cells(Z, pitch, origin, nci, ncj, za, zb, zc, zd);
      F nh, ngx, ngy;
      bilinear(za, zb, zc, zd, nfu, nfv, nh, ngx, ngy);
      const F dh = nh - HG;
      F m = F{} + 1;
      if (M) {
        for (int k = 0; k < N; ++k)
          m[k] = std::clamp(M[static_cast<std::ptrdiff_t>(NJ[k]) * mask_pitch + NI[k] - mask_origin], 0.0f, 1.0f);
      }
      const F cap = max_v(-dh * inv_step, F{} + min_slope) * SP * WA * capacity;
      // Uphill: the droplet sits in a hollow; fill it up to its spill height along the path (the next height)
      // or with all it carries, whichever is less: the brush raises its centre by dh for dh x brush_area.
      // Over capacity: deposit a share of the surplus; else erode a share of the free capacity, at most the
      // drop. Both with the brush around the nearest sample; one of the two amounts is 0.
      const I up = dh > 0;
      F dep = sel(up, min_v(dh * brush_area, SE), max_v(SE - cap, F{}) * deposition * m);
      F ero = sel(up, F{}, min_v(max_v(cap - SE, F{}) * erosion, -dh * brush_area) * m);
      dep = sel(in, dep, F{}), ero = sel(in, ero, F{});
      const F da = (dep - ero) * inv_cell_area;
      for (int k = 0; k < N; ++k) {
        if (!(live >> k & 1)) continue;
        const int ni = NI[k], nj = NJ[k];
        visited[visit_count++] = static_cast<std::ptrdiff_t>(nj) * pitch + ni - origin;
        apply_brush(da[k], ni, nj);
      }
      // Totals in double, per tile two lanes at a time (0 for lanes that changed nothing).
      for (int t = 0; t < T; ++t) {
        const f4 e = quarter(ero, t), d = quarter(dep, t);
        eroded2[t] += __builtin_convertvector(__builtin_shufflevector(e, e, 0, 1), d2) +
                      __builtin_convertvector(__builtin_shufflevector(e, e, 2, 3), d2);
        deposited2[t] += __builtin_convertvector(__builtin_shufflevector(d, d, 0, 1), d2) +
                         __builtin_convertvector(__builtin_shufflevector(d, d, 2, 3), d2);
      }
      SE = SE + ero - dep;
      SP = vsqrt(max_v(SP * SP - dh * gravity, F{}));
      WA *= keep_water;
      DX = dirx, DY = diry;
      U = nu, Vp = nv, HG = nh, GX = ngx, GY = ngy;
      CI = nci, CJ = ncj, FU = nfu, FV = nfv;
      S += 1;
      const int ended = live & ~(movemask(in) & ~movemask(S >= max_steps));
      if (ended) [[unlikely]] {
        for (int k = 0; k < N; ++k) {
          if (!(ended >> k & 1)) continue;
          const int t = k / kLanes;
          if (!in[k]) {
            carried_off[t] += SE[k];  // left the grid with its droplet
          } else if (SE[k] > 0) {
            // End of life: what the droplet still carries settles where it stopped (with the brush).
            apply_brush(SE[k] * inv_cell_area, CI[k] + (FU[k] >= 0.5f), CJ[k] + (FV[k] >= 0.5f));
            deposited[t] += SE[k];
          }
          live &= ~(1 << k);
          on[k] = 0;
          --live_count[t];
          if (next[t] < tiles[t].count) start(k, first + tiles[t].ids[next[t]++]);
        }
      }
    }
    count_visits();
    for (int t = 0; t < T; ++t) {
      DropletBlockStats& ts = *tiles[t].stats;
      ts.eroded += eroded[t] + eroded2[t][0] + eroded2[t][1];
      ts.deposited += deposited[t] + deposited2[t][0] + deposited2[t][1];
      ts.carried_off += carried_off[t];
      ts.steps += steps[t];
    }
  }
};

// run_tiles compiled twice: for the baseline x86-64 (SSE2), a tile at a time, and for AVX2, two tiles at a
// time, chosen at run time when the CPU has AVX2 (hwy::SupportedTargets(), which tests restrict with
// hwy::SetSupportedTargetsForTest to run the baseline). AVX2 code also adds the brush's rows of 8 weights in
// one vector and, with 3-operand instructions, needs fewer register copies. Every tile's droplets take the
// same steps in the same order either way, and every lane the same operations: AVX2 alone enables no FMA (the
// file is compiled with -ffp-contract=off too), so both give the same bits.
using RunTiles = void (*)(const Sim&, std::uint64_t, const TileRun*);
template <int W, int R>
void run_tiles_sse2(const Sim& s, std::uint64_t first, const TileRun* tiles) {
  s.run_tiles<W, R, 4, 1>(first, tiles);
}
#if defined(__x86_64__) || defined(__i386__)
template <int W, int R>
[[gnu::target("avx2")]] void run_tiles_avx2(const Sim& s, std::uint64_t first, const TileRun* tiles) {
  s.run_tiles<W, R, 8, 2>(first, tiles);
}
template <int W, int R>
RunTiles run_tiles_for(bool avx2) {
  return avx2 ? &run_tiles_avx2<W, R> : &run_tiles_sse2<W, R>;
}
#else
template <int W, int R>
RunTiles run_tiles_for(bool) {
  return &run_tiles_sse2<W, R>;
}
#endif

}  // namespace

// Flow: visits per unit length of path crossing a cell, log-scaled to 0..1 (a table per visit count; each entry is
// droplet_flow's value, so tiles that compute it sample by sample agree).
static void flow_map(const std::vector<std::uint32_t>& visits, int pitch, const Domain& domain, ErosionMaps& maps) {
  const int w = domain.width(), h = domain.height();
  maps.flow = std::make_shared<Heightfield>(domain);
  std::uint32_t vmax_visits = 0;
  for (auto vv : visits) vmax_visits = std::max(vmax_visits, vv);
  const double lmax = std::log1p(static_cast<double>(vmax_visits));
  if (lmax > 0) {
    std::vector<float> table(std::min<std::size_t>(vmax_visits, 1u << 20) + 1);
    for (std::size_t k = 0; k < table.size(); ++k) table[k] = droplet_flow(static_cast<std::uint32_t>(k), lmax);
    float* flow = maps.flow->data.data();
    for_each_row(nullptr, h, [&](int j) {
      const std::uint32_t* vj = visits.data() + static_cast<std::size_t>(j) * pitch;
      float* fj = flow + static_cast<std::size_t>(j) * w;
      for (int i = 0; i < w; ++i) fj[i] = vj[i] < table.size() ? table[vj[i]] : droplet_flow(vj[i], lmax);
    });
  }
}

struct DropletSchedule::Impl {
  int w = 0, h = 0;
  std::uint64_t droplets = 0, round_size = 1, rounds = 0;
  int tile_w = 1, tile_h = 1, tiles_x = 1, tiles_y = 1;
  glm::ivec2 margin{0, 0};
  std::uint64_t seed = 0;
  std::vector<int> colour_tiles[4];
  std::vector<BrushTap> brush;
  std::vector<float> row_weights;
  int dj_lo = 0, rx = 0;
  Sim sim{};  // everything but the grid
  RunTiles run = nullptr;
  RunTiles run_one = nullptr;  // one tile alone (the baseline kernel: no idle half of an 8-lane vector)
  std::size_t together = 1;    // tiles a run_tiles call steps together
};

DropletSchedule::DropletSchedule(const ParticleParams& p, const Domain& whole) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  const int w = whole.width(), h = whole.height();
  s.w = w, s.h = h, s.seed = p.seed;
  const double dx = whole.spacing.x, dy = whole.spacing.y;
  const double cell_area = dx * dy;
  const glm::dvec2 size = whole.size();
  const double area_km2 = size.x * size.y * 1e-6;
  // Counts checked, never cast: a huge domain times a high density does not fit a 64-bit count.
  const double wanted = std::max(0.0, p.droplets_per_km2) * area_km2;
  (void)checked_count(wanted, "HydraulicErosion: droplets (droplets_per_km2 x the domain's area)",
                      "lower droplets_per_km2 or use a smaller domain", std::int64_t{1} << 53, true);
  const auto droplets = static_cast<std::uint64_t>(std::llround(wanted));
  const auto max_steps = static_cast<int>(checked_count(p.lifetime / p.step_length,
                                                        "HydraulicErosion: steps per droplet (lifetime / step_length)",
                                                        "lower lifetime or raise step_length"));

  // Brush around the nearest sample: weights 1 - distance / radius, normalised; a table of offsets and
  // weights computed once.
  std::vector<BrushTap>& brush = s.brush;
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
  // 2 rx + 1 (the padding and the corners outside the disc weigh 0: adding a * 0 changes no height), from the
  // first to the last row with a tap (a disc's rows are contiguous).
  const int row_width = (2 * rx + 1 + 3) / 4 * 4, pad = row_width - (2 * rx + 1);
  int dj_lo = ry, dj_hi = -ry;
  for (const auto& t : brush) dj_lo = std::min(dj_lo, t.dj), dj_hi = std::max(dj_hi, t.dj);
  s.row_weights.assign(static_cast<std::size_t>(dj_hi - dj_lo + 1) * row_width, 0.0f);
  for (const auto& t : brush) s.row_weights[static_cast<std::size_t>(t.dj - dj_lo) * row_width + t.di + rx] = t.w;
  s.dj_lo = dj_lo, s.rx = rx;
  float w_centre = 0.0f;
  for (const auto& t : brush)
    if (t.di == 0 && t.dj == 0) w_centre = t.w;
  // The erosion of one step never lowers the brush centre by more than the drop: volume <= -dh x area / w0.
  const float brush_area = static_cast<float>(cell_area / std::max(w_centre, 1e-6f));

  // Schedule (the determinism): droplets run in rounds of a fixed number (set by the grid, not the thread
  // count). A round bins its droplets by the tile of the grid their origin falls in; tiles are at least twice
  // a droplet's reach (lifetime + brush + 2 samples) wide and high, so two tiles of the same colour of a 2 x 2
  // checkerboard never touch the same sample. The four colours run one after the other; the tiles of one
  // colour run in parallel, each tile's droplets one after the other in index order, changing the heights
  // directly (every droplet sees the changes of the droplets before it, as in Beyer's serial loop). Every
  // sample therefore receives the same changes in the same order for any thread count: bit-identical, with
  // no atomics and no change logs, and a tile's samples stay in cache while its droplets run.
  // Each step of each droplet erodes or deposits over the brush's taps.
  check_work(static_cast<double>(droplets) * max_steps * static_cast<double>(brush.size() + 1),
             "HydraulicErosion (droplets x steps per droplet x brush taps)",
             "lower droplets_per_km2, lifetime or radius, or raise step_length");
  const float step_u = static_cast<float>(p.step_length / dx), step_v = static_cast<float>(p.step_length / dy);
  // (+2: the bilinear neighbour and rounding to the nearest sample, which also cover one column of the brush
  // rows' padding; more padding widens the reach.)
  const double reach_u = max_steps * static_cast<double>(step_u) + rx + 2.0 + std::max(0, pad - 1);
  const double reach_v = max_steps * static_cast<double>(step_v) + ry + 2.0;
  s.tile_w = static_cast<int>(std::min<double>(w, std::max(32.0, 2.0 * std::ceil(reach_u))));
  s.tile_h = static_cast<int>(std::min<double>(h, std::max(32.0, 2.0 * std::ceil(reach_v))));
  s.tiles_x = (w + s.tile_w - 1) / s.tile_w, s.tiles_y = (h + s.tile_h - 1) / s.tile_h;
  for (int ty = 0; ty < s.tiles_y; ++ty)
    for (int tx = 0; tx < s.tiles_x; ++tx) s.colour_tiles[(ty & 1) * 2 + (tx & 1)].push_back(ty * s.tiles_x + tx);
  // A block's droplets, on each side: the steps' travel, the brush (its padding on the right), the bilinear cell and
  // the nearest sample, and the float rounding of a position over its steps (at most max_steps x (an ulp of the
  // domain's size + a relative 2^-21 of a step), within 2^-21 x max_steps x (size + step)).
  const double drift = std::ldexp(max_steps * (std::max(w, h) + std::max<double>(step_u, step_v)), -21);
  s.margin.x =
      static_cast<int>(std::min<double>(w, std::ceil(max_steps * static_cast<double>(step_u) + drift) + rx + pad + 3));
  s.margin.y =
      static_cast<int>(std::min<double>(h, std::ceil(max_steps * static_cast<double>(step_v) + drift) + ry + 3));
  s.round_size = std::max<std::uint64_t>(4096, static_cast<std::uint64_t>(w) * h / 8);
  s.droplets = droplets;
  s.rounds = (droplets + s.round_size - 1) / s.round_size;

  Sim& sim = s.sim;
  sim.brush = &s.brush;
  sim.RW = s.row_weights.data();
  sim.rows = dj_hi - dj_lo + 1;
  sim.row_width = row_width;
  sim.w = w, sim.h = h, sim.rx = rx, sim.ry = ry, sim.max_steps = max_steps;
  sim.seed = p.seed;
  sim.step_u = step_u, sim.step_v = step_v;
  sim.inv_dx = static_cast<float>(1.0 / dx), sim.inv_dy = static_cast<float>(1.0 / dy);
  sim.inv_cell_area = static_cast<float>(1.0 / cell_area);
  sim.inv_step = static_cast<float>(1.0 / p.step_length);
  sim.inertia = static_cast<float>(std::clamp(p.inertia, 0.0, 1.0));
  sim.min_slope = static_cast<float>(p.min_slope), sim.capacity = static_cast<float>(p.capacity);
  sim.deposition = static_cast<float>(p.deposition), sim.erosion = static_cast<float>(p.erosion);
  sim.gravity = static_cast<float>(p.gravity), sim.keep_water = static_cast<float>(1.0 - p.evaporation);
  sim.brush_area = brush_area;
  // The brush loop unrolled for the common shapes (radius 3 cells: 5 rows of 8; 1.5 cells: 3 rows of 4), else
  // unrolled over a row's width only.
  const bool avx2 = (hwy::SupportedTargets() & HWY_AVX2) != 0;
  s.together = avx2 ? 2 : 1;
  for (RunTiles* into : {&s.run, &s.run_one}) {
    const bool two = into == &s.run && avx2;
    RunTiles& run = *into;
    run = run_tiles_for<0, 0>(two);
    if (row_width == 8 && sim.rows == 5)
      run = run_tiles_for<8, 5>(two);
    else if (row_width == 8 && sim.rows == 3)
      run = run_tiles_for<8, 3>(two);
    else if (row_width == 4)
      run = run_tiles_for<4, 0>(two);
    else if (row_width == 8)
      run = run_tiles_for<8, 0>(two);
    else if (row_width == 12)
      run = run_tiles_for<12, 0>(two);
    else if (row_width == 16)
      run = run_tiles_for<16, 0>(two);
  }
}

DropletSchedule::~DropletSchedule() = default;

glm::ivec2 DropletSchedule::size() const { return {impl_->w, impl_->h}; }
std::uint64_t DropletSchedule::droplets() const { return impl_->droplets; }
std::uint64_t DropletSchedule::rounds() const { return impl_->rounds; }
glm::ivec2 DropletSchedule::blocks() const { return {impl_->tiles_x, impl_->tiles_y}; }
glm::ivec2 DropletSchedule::block_lo(int b) const {
  return {b % impl_->tiles_x * impl_->tile_w, b / impl_->tiles_x * impl_->tile_h};
}
glm::ivec2 DropletSchedule::block_hi(int b) const {
  return glm::min(block_lo(b) + glm::ivec2(impl_->tile_w, impl_->tile_h), size()) - 1;
}
const std::vector<int>& DropletSchedule::color_blocks(int c) const { return impl_->colour_tiles[c]; }
glm::ivec2 DropletSchedule::margin() const { return impl_->margin; }
int DropletSchedule::pitch_for(int width) { return row_pitch(width); }

void DropletSchedule::bin(std::uint64_t round, DropletBins& bins) const {
  const Impl& s = *impl_;
  const int tiles = s.tiles_x * s.tiles_y;
  const std::uint64_t first = round * s.round_size;
  const auto count = static_cast<std::uint32_t>(std::min(s.round_size, s.droplets - first));
  bins.first = first;
  bins.start.assign(static_cast<std::size_t>(tiles) + 1, 0u);
  bins.order.resize(count);
  bins.block_of.resize(count);
  // Bin the round's droplets by the tile of their origin (a counting sort keeps index order per tile).
  for (std::uint32_t k = 0; k < count; ++k) {
    float u, v;
    droplet_origin(hash64(s.seed, first + k), s.w, s.h, u, v);
    const int i = static_cast<int>(u), j = static_cast<int>(v);
    const std::uint32_t t = static_cast<std::uint32_t>(std::min(j / s.tile_h, s.tiles_y - 1) * s.tiles_x +
                                                       std::min(i / s.tile_w, s.tiles_x - 1));
    bins.block_of[k] = t;
    ++bins.start[t + 1];
  }
  for (int t = 0; t < tiles; ++t) bins.start[t + 1] += bins.start[t];
  std::vector<std::uint32_t> fill(bins.start.begin(), bins.start.end() - 1);
  for (std::uint32_t k = 0; k < count; ++k) bins.order[fill[bins.block_of[k]]++] = k;
}

void DropletSchedule::run(const DropletGrid& grid, const DropletBins& bins, const std::vector<int>& blocks,
                          DropletBlockStats* stats, const ExecContext* ctx) const {
  const Impl& s = *impl_;
  Sim sim = s.sim;
  sim.Z = grid.z;
  sim.V = grid.visits;
  sim.M = grid.mask;
  sim.pitch = grid.pitch;
  sim.origin = static_cast<std::ptrdiff_t>(grid.y0) * grid.pitch + grid.x0;
  sim.x0 = grid.x0, sim.y0 = grid.y0;
  sim.mask_pitch = grid.mask_pitch;
  sim.mask_origin = static_cast<std::ptrdiff_t>(grid.y0) * grid.mask_pitch + grid.x0;
  sim.row0 = static_cast<std::ptrdiff_t>(s.dj_lo) * grid.pitch - s.rx;
  sim.ctx = ctx;
  const std::size_t together = s.together;
  const std::size_t groups = (blocks.size() + together - 1) / together;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups, 1), [&](const tbb::blocked_range<std::size_t>& br) {
    for (std::size_t q = br.begin(); q != br.end(); ++q) {
      TileRun runs[2];
      std::size_t n = 0;
      for (std::size_t g = 0; g < together; ++g) {
        const std::size_t k = q * together + g;
        if (k < blocks.size()) {
          const int t = blocks[k];
          runs[n++] = {bins.order.data() + bins.start[t], bins.start[t + 1] - bins.start[t], &stats[t]};
        }
      }
      // A tile left without a partner runs alone (both kernels give every tile the same bits).
      (n == together ? s.run : s.run_one)(sim, bins.first, runs);
    }
  });
}

ErosionMaps particle_erosion(const Heightfield& in, const ParticleParams& p, const Heightfield* mask,
                             const ExecContext* ctx, ParticleStats* stats) {
  require_finite_inputs("HydraulicErosion", {{"in", &in}, {"mask", mask}});
  const DropletSchedule schedule(p, in.domain);
  const int w = in.width(), h = in.height();
  const int pitch = row_pitch(w);
  std::vector<float> z;
  if (pitch == w) {
    z = in.data;
  } else {
    z.resize(static_cast<std::size_t>(h) * pitch);
    for (int j = 0; j < h; ++j)
      std::copy_n(in.data.data() + static_cast<std::size_t>(j) * w, w, z.data() + static_cast<std::size_t>(j) * pitch);
  }
  // Visit counts only for the flow map: fresh memory costs this machine ~15 us a page on first touch, and at
  // 50k droplets on 1024^2 the grids a call allocates cost more than its droplets.
  std::vector<std::uint32_t> visits(p.flow_map ? z.size() : 0, 0);
  DropletGrid grid;
  grid.z = z.data();
  grid.visits = p.flow_map ? visits.data() : nullptr;
  grid.mask = mask ? mask->data.data() : nullptr;
  grid.pitch = pitch, grid.mask_pitch = w;
  std::vector<DropletBlockStats> block_stats(static_cast<std::size_t>(schedule.block_count()));
  DropletBins bins;
  const std::uint64_t rounds = schedule.rounds();
  for (std::uint64_t r = 0; r < rounds; ++r) {
    check_cancelled(ctx);
    schedule.bin(r, bins);
    for (int c = 0; c < 4; ++c) {
      schedule.run(grid, bins, schedule.color_blocks(c), block_stats.data(), ctx);
      check_cancelled(ctx);
      report(ctx, (static_cast<double>(r) + (c + 1) / 4.0) / static_cast<double>(rounds));
    }
  }
  ParticleStats st;
  st.droplets = schedule.droplets();
  for (const auto& ts : block_stats) {
    st.eroded += ts.eroded;
    st.deposited += ts.deposited;
    st.carried_off += ts.carried_off;
    st.steps += ts.steps;
  }
  if (stats) *stats = st;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>();  // (not Heightfield(domain): its zeros would be thrown away)
  maps.out->domain = in.domain;
  // The rows packed in place (each moves down to a lower address) rather than copied to fresh memory: a page
  // touched for the first time costs this machine more than copying it.
  if (pitch != w) {
    for (int j = 1; j < h; ++j)
      std::memmove(z.data() + static_cast<std::size_t>(j) * w, z.data() + static_cast<std::size_t>(j) * pitch,
                   static_cast<std::size_t>(w) * sizeof(float));
    z.resize(static_cast<std::size_t>(w) * h);
  }
  maps.out->data = std::move(z);
  if (p.flow_map) flow_map(visits, pitch, in.domain, maps);
  if (p.change_maps) fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
