#include "nodes/erosion/pipe.h"

#include "nodes/erosion/pipe_step.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "nodes/common/cancellable_rows.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/common/work_bounds.h"

namespace orogen::erosion {
namespace {

// Rows per chunk of the fused sweep (the chunking changes no result, only the share of recomputed rows).
constexpr int kDefaultChunkRows = 64;

// Per-thread rows of the sweep: rings of 4 rows of rained depth, water surface and concentration, the new fluxes
// (L, R, D, U) of the two rows just outside a chunk, a ring of 2 rows of new terrain, and a row where the vectorised
// update writes the speed before the last step (only the last step's speed is kept: no traffic to the speed map).
struct Scratch {
  std::vector<float> dr, surf, conc, flux, out, speed;
  void resize(int w) {
    const std::size_t need = static_cast<std::size_t>(4) * w;
    if (dr.size() != need)
      dr.assign(need, 0.0f), surf.assign(need, 0.0f), conc.assign(need, 0.0f), flux.assign(2 * need, 0.0f),
          out.assign(2 * static_cast<std::size_t>(w), 0.0f), speed.assign(w, 0.0f);
  }
};

// The vectorised loops below are also compiled for AVX2, chosen at run time where the CPU has it: twice the lanes,
// the same IEEE operations in the same order (AVX2 without FMA: no product is fused), so the same bits.
#define OROGEN_PIPE_VECTOR_LOOP __attribute__((target_clones("avx2", "default")))

// The interior cells [i0, i1) (within 1 .. w-2) of a row's outflow fluxes, L, R, D and U in place: plain pointers
// and selects rather than branches, so the loop vectorises (the same arithmetic as the generic cell).
OROGEN_PIPE_VECTOR_LOOP void flux_interior(int i0, int i1, const float* __restrict DR, const float* __restrict SF,
                                           const float* __restrict SFd, const float* __restrict SFu,
                                           float* __restrict L, float* __restrict R, float* __restrict D,
                                           float* __restrict U, float cx, float cy, float t, float area) {
  for (int i = i0; i < i1; ++i) {
    const float dk = DR[i], hk = SF[i];
    float l = L[i] + cx * dk * (hk - SF[i - 1]), rr = R[i] + cx * dk * (hk - SF[i + 1]);
    float dn = D[i] + cy * dk * (hk - SFd[i]), up = U[i] + cy * dk * (hk - SFu[i]);
    l = l > 0.0f ? l : 0.0f, rr = rr > 0.0f ? rr : 0.0f, dn = dn > 0.0f ? dn : 0.0f, up = up > 0.0f ? up : 0.0f;
    const float total = (l + rr + dn + up) * t;
    const float q = dk * area / total;
    const float K = total > dk * area ? q : 1.0f;
    L[i] = l * K, R[i] = rr * K, D[i] = dn * K, U[i] = up * K;
  }
}

// The largest of n depths (0 if none is positive), in 8 lanes so the loop vectorises: a maximum is the same in
// any order.
OROGEN_PIPE_VECTOR_LOOP float deepest(const float* __restrict depth, int n) {
  float lane[8] = {};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int l = 0; l < 8; ++l) lane[l] = depth[i + l] > lane[l] ? depth[i + l] : lane[l];
  float most = 0.0f;
  for (; i < n; ++i) most = depth[i] > most ? depth[i] : most;
  for (const float v : lane) most = v > most ? v : most;
  return most;
}

// Asks for the cache line of `p`. GCC infers that a function whose only effects are __builtin_prefetch has none,
// and deletes calls to it; a volatile asm it keeps.
inline void prefetch(const void* p) {
#if defined(__x86_64__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

struct UpdateConst {
  float t, area, dx, dy, two_dx, two_dy, kc, ks1, kd;
  float evap;  // with a temperature field the share evaporated at factor 1, else the share of water kept
};

// The interior cells [i0, i1) (within 1 .. w-2) of a row without mask, hardness or soil layers: water, transport,
// velocity, dissolution/deposition, evaporation with the same arithmetic as the generic cell, selects for branches.
// kTemperature: T is the row of the evaporation factor field; kSinks: SINK marks the row's sinks, which
// neither erode nor deposit and count 0 water in the flow map (the caller empties them afterwards).
#define OROGEN_PIPE_UPDATE_PARAMS                                                                                      \
  int i0, int i1, const float *__restrict T, const unsigned char *__restrict SINK, const float *__restrict FL,         \
      const float *__restrict FR, const float *__restrict FD, const float *__restrict FU, const float *__restrict FUd, \
      const float *__restrict FDu, const float *__restrict DR, const float *__restrict C, const float *__restrict Cd,  \
      const float *__restrict Cu, float *__restrict S, const float *__restrict B, const float *__restrict Bd,          \
      const float *__restrict Bu, float *__restrict B2, float *__restrict D2, float *__restrict SPD,                   \
      float *__restrict FACC, UpdateConst k
#define OROGEN_PIPE_UPDATE_ARGS \
  i0, i1, T, SINK, FL, FR, FD, FU, FUd, FDu, DR, C, Cd, Cu, S, B, Bd, Bu, B2, D2, SPD, FACC, k
template <bool kTemperature, bool kSinks>
[[gnu::always_inline]] inline void update_cells(OROGEN_PIPE_UPDATE_PARAMS) {
  const float t = k.t, area = k.area, ddx = k.dx, ddy = k.dy, tdx = k.two_dx, tdy = k.two_dy, kcap = k.kc;
  const float ks1 = k.ks1, kdep = k.kd, evap = k.evap;
  for (int i = i0; i < i1; ++i) {
    const float dk = DR[i], conc = C[i];
    const float vl = FL[i] * t, vr = FR[i] * t, vd = FD[i] * t, vu = FU[i] * t;
    const float out_v = (FL[i] + FR[i] + FD[i] + FU[i]) * t;
    const float out_s = ((conc * vl + conc * vr) + conc * vd) + conc * vu;
    const float fin_l = FR[i - 1], fin_r = FL[i + 1], fin_d = FUd[i], fin_u = FDu[i];
    const float il = fin_l * t, ir = fin_r * t, id = fin_d * t, iu = fin_u * t;
    const float in_v = ((il + ir) + id) + iu;
    const float in_s = ((C[i - 1] * il + C[i + 1] * ir) + Cd[i] * id) + Cu[i] * iu;
    float d1 = dk + (in_v - out_v) / area;
    d1 = 0.0f < d1 ? d1 : 0.0f;
    float s1 = S[i] + in_s - out_s;
    const float wx = 0.5f * (fin_l - FL[i] + FR[i] - fin_r);
    const float wy = 0.5f * (fin_d - FD[i] + FU[i] - fin_u);
    const float dmean = 0.5f * (dk + d1);
    const float uq = wx / (ddy * dmean), vq = wy / (ddx * dmean);
    const float u = dmean > 1e-3f ? uq : 0.0f, v = dmean > 1e-3f ? vq : 0.0f;
    const float speed = std::sqrt(u * u + v * v);
    const float bx = (B[i + 1] - B[i - 1]) / tdx;
    const float by = (Bu[i] - Bd[i]) / tdy;
    const float g2 = bx * bx + by * by;
    float sin_tilt = std::sqrt(g2 / (1.0f + g2));
    sin_tilt = sin_tilt < 0.005f ? 0.005f : (0.5f < sin_tilt ? 0.5f : sin_tilt);
    const float cap = kcap * sin_tilt * speed * d1;
    const float e1 = ks1 * (cap - s1), e2 = kdep * (s1 - cap);
    const bool dissolve = cap > s1;
    float bk = dissolve ? B[i] - e1 : B[i] + e2;
    float s2 = dissolve ? s1 + e1 : s1 - e2;
    if constexpr (kSinks) {
      const bool sink = SINK[i] != 0;
      bk = sink ? B[i] : bk;
      s2 = sink ? s1 : s2;
    }
    if constexpr (kTemperature) {
      const float temp = T[i] > 0.0f ? T[i] : 0.0f;
      const float keep = 1.0f - evap * temp;
      d1 *= keep > 0.0f ? keep : 0.0f;
    } else {
      d1 *= evap;
    }
    B2[i] = bk, D2[i] = d1, S[i] = s2, SPD[i] = speed;
    if constexpr (kSinks) {
      FACC[i] += t * speed * (SINK[i] ? 0.0f : d1);
    } else {
      FACC[i] += t * speed * d1;
    }
  }
}

// The four variants, each also compiled for AVX2 (multiversioned functions cannot be templates).
OROGEN_PIPE_VECTOR_LOOP void update_interior(OROGEN_PIPE_UPDATE_PARAMS) {
  update_cells<false, false>(OROGEN_PIPE_UPDATE_ARGS);
}
OROGEN_PIPE_VECTOR_LOOP void update_interior_sinks(OROGEN_PIPE_UPDATE_PARAMS) {
  update_cells<false, true>(OROGEN_PIPE_UPDATE_ARGS);
}
OROGEN_PIPE_VECTOR_LOOP void update_interior_evaporation(OROGEN_PIPE_UPDATE_PARAMS) {
  update_cells<true, false>(OROGEN_PIPE_UPDATE_ARGS);
}
OROGEN_PIPE_VECTOR_LOOP void update_interior_evaporation_sinks(OROGEN_PIPE_UPDATE_PARAMS) {
  update_cells<true, true>(OROGEN_PIPE_UPDATE_ARGS);
}
#undef OROGEN_PIPE_UPDATE_PARAMS
#undef OROGEN_PIPE_UPDATE_ARGS

// The constants of one time step.
struct StepConstants {
  double dt;           // s
  std::uint64_t step;  // step number (Drops: part of the rain hash)
  bool last;           // the last step (the velocity map is written)
  float fdt;           // dt in float
  float ks, kd, kc;    // dissolution and deposition per step, capacity constant
  float rain_uniform;  // m of rain per step (uniform mode, no rainfall field)
  float keep;          // evaporation factor per step at temperature factor 1
  float cgx, cgy;      // dt g kx, dt g ky: flux gain per metre of head
  float fdx, fdy, two_dx, two_dy;
};

// One run of the pipe model: the fields, and the stages of a step. A step is one fused sweep over rows
// (rain, water surface and concentration; outflow fluxes; water, transport, velocity, dissolution and
// deposition, evaporation, sinks), pipelined over chunks of rows: chunks run in parallel, each recomputing
// the one or two rows it needs beyond its edges from the previous step's fields, so every value is the same
// whatever the chunking and thread count.
//
// The fields are updated in place: a row's new values go into its fields where nothing in the chunk reads the old
// ones any more (fluxes, water and sediment as they are computed; terrain, which the next row's tilt reads, once that
// row is updated). In-place
// stores land on lines the step has just read, where a second copy of every field would cost a fill of each
// line written and twice the memory. The two rows at each end of a chunk, which the neighbouring chunks read
// while it runs, go to the chunk's edge rows instead and into the fields when every chunk is done.
struct PipeRun {
  const Heightfield& in;
  const PipeParams& p;
  const PipeWindow window;  // where the grid lies in the whole domain (for the Drops rain)
  const int whole_h;        // rows of the whole domain
  const Heightfield *mask, *rainfall, *moisture, *temperature, *hardness;
  const int w, h;
  const int chunk_rows;  // rows per chunk of the sweep
  const std::size_t n;
  const double dx, dy;
  const float A;  // cell area, m^2
  const float g;
  // Pipe geometry: flux (m^3/s) += dt x g x (width x depth) x dh / length.
  const float kx, ky;
  static constexpr double mm_per_h = 1.0 / 3.6e6;  // mm/h -> m/s
  std::vector<float> b, d, s;
  std::vector<float> fl, fr, fd, fu;
  std::vector<float> spd, flow_acc;
  // The new values of the rows the neighbouring chunks read: per chunk, 4 rows (kEdgeRows) of the 7 fields a step
  // writes (kEdgeFields: terrain, water, sediment, fluxes L, R, D, U).
  static constexpr int kEdgeRows = 4, kEdgeFields = 7;
  std::vector<float> edge;
  std::vector<double> row_sed_out, row_water_out, row_dmax, row_sum;
  tbb::enumerable_thread_specific<Scratch> scratch;
  // Sinks, and rows with a sink. A sink among sinks holds no water and moves nothing (sinks catch no rain and
  // empty every step), so the sweep computes each row only on its spans: the runs of columns within one cell of
  // land in the rows around (the sea away from the coast, inside the island's lagoons and between its shores as
  // well as around it, is never touched; outside the spans every field keeps its initial value, which is what
  // computing it would give, and adds 0 to the row's totals). The prep spans are wider: the rows around read them.
  struct Span {
    int lo = 0, hi = -1;  // inclusive columns
  };
  using Spans = std::vector<Span>;  // disjoint and apart, left to right
  std::vector<unsigned char> sink, row_sink;
  std::vector<Spans> span, prep_span;
  // Per row, the columns outside its spans where the updates of the rows around read its new fluxes (one column
  // beyond the spans of rows r - 1 .. r + 1): 0 there, as in every cell the sweep skips, though the scratch row that
  // holds them when the row lies just outside a chunk held another row's fluxes.
  std::vector<Spans> flux_zero;
  bool plain = false;  // no mask, hardness or soil layers: the interior of rows takes the vectorised path

  PipeRun(const Heightfield& in_, const PipeParams& p_, const Heightfield* mask_, const Heightfield* rainfall_,
          const Heightfield* moisture_, const Heightfield* temperature_, const Heightfield* hardness_,
          PipeWindow window_, bool every_cell = false, int chunk_rows_ = kDefaultChunkRows)
      : in(in_),
        p(p_),
        window(std::move(window_)),
        whole_h(window.whole.y > 0 ? window.whole.y : in_.height()),
        mask(mask_),
        rainfall(rainfall_),
        moisture(moisture_),
        temperature(temperature_),
        hardness(hardness_),
        w(in_.width()),
        h(in_.height()),
        chunk_rows(std::max(1, chunk_rows_)),
        n(in_.data.size()),
        dx(in_.domain.spacing.x),
        dy(in_.domain.spacing.y),
        A(static_cast<float>(dx * dy)),
        g(static_cast<float>(p_.gravity)),
        kx(static_cast<float>(dy / dx)),
        ky(static_cast<float>(dx / dy)),
        b(in_.data),
        d(n, 0.0f),
        s(n, 0.0f),
        fl(n, 0.0f),
        fr(n, 0.0f),
        fd(n, 0.0f),
        fu(n, 0.0f),
        spd(n, 0.0f),
        flow_acc(n, 0.0f),
        row_sed_out(h),
        row_water_out(h),
        row_dmax(h),
        row_sum(h),
        sink(n),
        row_sink(h, 0),
        span(h),
        prep_span(h) {
    std::vector<Spans> land(h);  // the runs of land columns of each row
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * w + i;
        sink[k] = in.data[k] < p.sea_level;
        row_sink[j] |= sink[k];
        if (sink[k]) continue;
        if (land[j].empty() || land[j].back().hi < i - 1) land[j].push_back({i, i});
        land[j].back().hi = i;
      }
    // The land of rows j - r .. j + r, widened by r columns, within the grid.
    const auto widened = [&](int j, int r) {
      Spans runs;
      for (int q = std::max(0, j - r); q <= std::min(h - 1, j + r); ++q)
        for (const Span& s : land[q]) runs.push_back({std::max(0, s.lo - r), std::min(w - 1, s.hi + r)});
      std::sort(runs.begin(), runs.end(), [](const Span& a, const Span& b) { return a.lo < b.lo; });
      Spans out;
      for (const Span& s : runs)
        if (!out.empty() && s.lo <= out.back().hi + 1)
          out.back().hi = std::max(out.back().hi, s.hi);
        else
          out.push_back(s);
      return out;
    };
    for (int j = 0; j < h; ++j) span[j] = widened(j, 1), prep_span[j] = widened(j, 2);
    if (every_cell) std::fill(span.begin(), span.end(), Spans{{0, w - 1}}), prep_span = span;
    flux_zero.resize(h);
    for (int r = 0; r < h; ++r) {
      std::vector<unsigned char> read(w, 0);
      for (int q = std::max(0, r - 1); q <= std::min(h - 1, r + 1); ++q)
        for (const Span& sp : span[q])
          std::fill(read.begin() + std::max(0, sp.lo - 1), read.begin() + std::min(w - 1, sp.hi + 1) + 1, 1);
      for (const Span& sp : span[r]) std::fill(read.begin() + sp.lo, read.begin() + sp.hi + 1, 0);
      for (int i = 0; i < w; ++i) {
        if (!read[i]) continue;
        if (flux_zero[r].empty() || flux_zero[r].back().hi < i - 1) flux_zero[r].push_back({i, i});
        flux_zero[r].back().hi = i;
      }
    }
    edge.assign(static_cast<std::size_t>(chunks()) * kEdgeRows * kEdgeFields * w, 0.0f);
    plain = !mask && !hardness && !(p.layer_depth > 0);
  }

  // Sum of (b + s) x A, rows summed in order.
  double volume(const ExecContext* ctx) {
    for_each_row_unreported(ctx, h, [&](int j) {
      double acc = 0;
      for (int i = 0; i < w; ++i) acc += static_cast<double>(b[in.index(i, j)]) + s[in.index(i, j)];
      row_sum[j] = acc;
    });
    double t = 0;
    for (double r : row_sum) t += r;
    return t * A;
  }

  StepConstants constants(double dt, std::uint64_t step, bool last) const {
    StepConstants c;
    c.dt = dt;
    c.step = step;
    c.last = last;
    c.fdt = static_cast<float>(dt);
    c.ks = static_cast<float>(p.dissolving * dt);
    c.kd = static_cast<float>(std::min(1.0, p.depositing * dt));
    c.kc = static_cast<float>(p.capacity);
    c.rain_uniform = static_cast<float>(dt * (p.rain_rate * mm_per_h));
    c.keep = static_cast<float>(p.evaporation * dt);
    c.cgx = c.fdt * g * kx;
    c.cgy = c.fdt * g * ky;
    c.fdx = static_cast<float>(dx);
    c.fdy = static_cast<float>(dy);
    c.two_dx = static_cast<float>(2 * dx);
    c.two_dy = static_cast<float>(2 * dy);
    return c;
  }

  int chunks() const { return (h + chunk_rows - 1) / chunk_rows; }

  // The rows of one chunk [j0, j1) of the sweep: the thread's rings of 4 rows (r & 3) of rained depth, surface and
  // concentration, its ring of 2 rows (r & 1) of new terrain, and where each row's new values go: the fields, or the
  // chunk's edge rows for the two rows at either end (the new fluxes of the rows just outside it: the scratch).
  struct Chunk {
    Scratch& sc;
    int w, j0, j1;
    float* edge;                 // the chunk's kEdgeRows x kEdgeFields rows
    float* fields[kEdgeFields];  // terrain, water, sediment, fluxes L, R, D, U
    float* DRrow(int r) const { return sc.dr.data() + static_cast<std::size_t>(r & 3) * w; }
    float* SFrow(int r) const { return sc.surf.data() + static_cast<std::size_t>(r & 3) * w; }
    float* CCrow(int r) const { return sc.conc.data() + static_cast<std::size_t>(r & 3) * w; }
    // Where row r's new fluxes are (which: L, R, D, U): the chunk's rows in the fields or the edge rows, the rows
    // just outside it in the scratch.
    float* Frow(int r, int which) const {
      if (r >= j0 && r < j1) return target(r, 3 + which);
      return sc.flux.data() + (static_cast<std::size_t>(r < j0 ? 0 : 4) + which) * w;
    }
    float* Brow(int r) const { return sc.out.data() + static_cast<std::size_t>(r & 1) * w; }
    // Row r's edge row (r within the chunk), or -1 if the neighbouring chunks never read it.
    int edge_slot(int r) const {
      if (r - j0 < 2) return r - j0;
      if (r >= j1 - 2) return 2 + r - (j1 - 2);
      return -1;
    }
    // Where row r's new values of field f (0..6, as kEdgeFields) go.
    float* target(int r, int f) const {
      const int slot = edge_slot(r);
      if (slot < 0) return fields[f] + static_cast<std::size_t>(r) * w;
      return edge + (static_cast<std::size_t>(slot) * kEdgeFields + f) * w;
    }
  };

  // Copies the columns of `spans` from `from` to `to`.
  static void copy_spans(const Spans& spans, const float* from, float* to) {
    for (const Span& sp : spans) std::copy(from + sp.lo, from + sp.hi + 1, to + sp.lo);
  }

  // Drops mode: the drops of row r this step. Each cell catches a drop with probability min(1, moisture x
  // drop_chance x dt); the cells that do are drawn as gaps of a geometric law at the largest chance (moisture
  // 1), each kept with probability moisture, so a row costs a few draws per drop instead of one per cell. The
  // draws hash (seed, step, row): every chunk that recomputes the row gets the same drops. Sinks catch none:
  // rain on them would be removed in the same step.
  void rain_drops(const StepConstants& cs, int r, float* __restrict DR) const {
    const double chance = std::min(1.0, p.drop_chance * cs.dt);
    if (!(chance > 0)) return;
    // The draws follow the whole domain's row from its first column; the grid holds columns x0 .. x_end - 1.
    const std::size_t row = static_cast<std::size_t>(r) * w;
    const double x0 = window.first.x, x_end = window.first.x + w;
    std::uint64_t state =
        hash64(p.seed, cs.step * static_cast<std::uint64_t>(whole_h) + static_cast<std::uint64_t>(r + window.first.y));
    const auto draw = [&] { return unit_double(splitmix64(state++)); };
    const double log_miss = chance < 1.0 ? std::log1p(-chance) : 0.0;  // log of a cell's chance of no drop
    const float depth = static_cast<float>(p.rain_rate * mm_per_h / std::max(p.drop_chance, 1e-9));
    for (double i = -1;;) {
      // The cells skipped before the next candidate: floor(log(U) / log(1 - chance)), 0 when chance is 1.
      i += 1 + (chance < 1.0 ? std::floor(std::log1p(-draw()) / log_miss) : 0.0);
      if (!(i < x_end)) break;
      if (i < x0) {  // a column before the grid: only its draws count
        const std::size_t b =
            static_cast<std::size_t>(r) * static_cast<std::size_t>(window.first.x) + static_cast<std::size_t>(i);
        if ((window.draws_before[b >> 6] >> (b & 63)) & 1u) draw();
        continue;
      }
      const std::size_t k = row + static_cast<std::size_t>(i - x0);
      if (sink[k]) continue;
      const float m = moisture ? std::clamp(moisture->data[k], 0.0f, 1.0f) : 1.0f;
      // The second draw keeps it with chance m (pipe_drop_draws on a cell known to be land: only m is read).
      if (m < 1.0f && !(draw() < m)) continue;
      DR[k - row] +=
          rainfall ? static_cast<float>(std::max(0.0f, rainfall->data[k]) * mm_per_h / std::max(p.drop_chance, 1e-9))
                   : depth;
    }
  }

  // Asks the cache for what the preparation of row r reads, a row before it runs: a row's spans are short runs 4 KiB
  // apart, too short for the hardware's stream prefetch to warm up on, and the moisture field is read only where a
  // drop falls, at random. Those first touches were half the preparation's time. (Fetching the fluxes, the flow and
  // the temperature as well was slower: the requests of a row come at once, and the core has few slots for misses.)
  void prefetch_row(int r) const {
    const std::size_t row = static_cast<std::size_t>(r) * w;
    const float* fields[] = {d.data(), b.data(), s.data(), moisture ? moisture->data.data() : nullptr};
    for (const Span& sp : prep_span[r])
      for (int i = sp.lo; i <= sp.hi; i += 16)  // 16 floats a cache line
        for (const float* f : fields)
          if (f) prefetch(f + row + i);
  }

  // 1. Rain, then the water surface and each cell's sediment concentration (per m^3 of water) of row r.
  void prep(const Chunk& ch, const StepConstants& cs, int r) const {
    const float rain_uniform = cs.rain_uniform;
    const double dt = cs.dt;
    const std::size_t row = static_cast<std::size_t>(r) * w;
    float* __restrict DR = ch.DRrow(r);
    float* __restrict SF = ch.SFrow(r);
    float* __restrict CC = ch.CCrow(r);
    const float* __restrict D = d.data() + row;
    const float* __restrict S = s.data() + row;
    const float* __restrict B = b.data() + row;
    const unsigned char* __restrict SINK = sink.data() + row;
    const Spans& spans = prep_span[r];
    if (spans.empty()) return;  // open sea: nothing here is read, and its drops would fall on sinks
    for (const Span& sp : spans) {
      const int i0 = sp.lo, i1 = sp.hi + 1;
      if (p.rain_mode == RainMode::Drops) {
        for (int i = i0; i < i1; ++i) DR[i] = D[i];
      } else if (!rainfall) {
        for (int i = i0; i < i1; ++i) DR[i] = D[i] + (SINK[i] ? 0.0f : rain_uniform);
      } else {
        for (int i = i0; i < i1; ++i) {
          const double rate = std::max(0.0f, rainfall->data[row + i]) * mm_per_h;
          DR[i] = D[i] + (SINK[i] ? 0.0f : static_cast<float>(dt * rate));
        }
      }
    }
    if (p.rain_mode == RainMode::Drops) rain_drops(cs, r, DR);  // drops fall on land, always inside the spans
    for (const Span& sp : spans)
      for (int i = sp.lo; i <= sp.hi; ++i) {
        const float dk = DR[i];
        SF[i] = B[i] + dk;
        const float q = S[i] / (dk * A);  // computed unconditionally (a select, not a branch: vectorises)
        CC[i] = dk > 0.0f ? q : 0.0f;
      }
  }

  // 2. Outflow fluxes of row r, in place where Frow puts them (the old ones copied there first if that is not the
  // fields): a generic cell for the border, an unchecked loop for the interior.
  void flux(const Chunk& ch, const StepConstants& cs, int r) const {
    const float fdt = cs.fdt, cgx = cs.cgx, cgy = cs.cgy;
    const std::size_t row = static_cast<std::size_t>(r) * w;
    const float* __restrict DR = ch.DRrow(r);
    const float* __restrict SF = ch.SFrow(r);
    const float* __restrict SFd = r > 0 ? ch.SFrow(r - 1) : nullptr;
    const float* __restrict SFu = r < h - 1 ? ch.SFrow(r + 1) : nullptr;
    float* const F[4] = {ch.Frow(r, 0), ch.Frow(r, 1), ch.Frow(r, 2), ch.Frow(r, 3)};
    const Spans& spans = span[r];
    const std::vector<float>* old[4] = {&fl, &fr, &fd, &fu};
    for (int f = 0; f < 4; ++f)
      if (F[f] != old[f]->data() + row) copy_spans(spans, old[f]->data() + row, F[f]);
    if (r < ch.j0 || r >= ch.j1)  // a scratch row, which held another row: 0 where the updates read beyond the spans
      for (const Span& sp : flux_zero[r])
        for (float* f : F) std::fill(f + sp.lo, f + sp.hi + 1, 0.0f);
    float *L = F[0], *R = F[1], *D = F[2], *U = F[3];
    auto generic = [&](int i) {
      const float dk = DR[i], hk = SF[i], c = fdt * g * dk;
      const float hl = i > 0 ? hk - SF[i - 1] : dk, hr = i < w - 1 ? hk - SF[i + 1] : dk;
      const float hd = SFd ? hk - SFd[i] : dk, hu = SFu ? hk - SFu[i] : dk;
      const float l = std::max(0.0f, L[i] + c * kx * hl), rr = std::max(0.0f, R[i] + c * kx * hr);
      const float dn = std::max(0.0f, D[i] + c * ky * hd), up = std::max(0.0f, U[i] + c * ky * hu);
      const float total = (l + rr + dn + up) * fdt;
      const float K = total > dk * A ? dk * A / total : 1.0f;
      L[i] = l * K, R[i] = rr * K, D[i] = dn * K, U[i] = up * K;
    };
    for (const Span& sp : spans) {
      if (r == 0 || r == h - 1 || w < 3) {
        for (int i = sp.lo; i <= sp.hi; ++i) generic(i);
        continue;
      }
      if (sp.lo == 0) generic(0);
      flux_interior(std::max(sp.lo, 1), std::min(sp.hi, w - 2) + 1, DR, SF, SFd, SFu, L, R, D, U, cgx, cgy, fdt, A);
      if (sp.hi == w - 1) generic(w - 1);
    }
  }

  // 3. Water, sediment transport, velocity, dissolution/deposition, evaporation, sinks of row j; the row's outflow
  // through the border and sinks and its deepest water into the row totals. The terrain of rows j - 1 and j + 1
  // that it reads is still the old one: row j - 1 is retired after this.
  void update(const Chunk& ch, const StepConstants& cs, int j) {
    const float fdt = cs.fdt, ks = cs.ks, kd = cs.kd, kc = cs.kc, keep = cs.keep;
    const float fdx = cs.fdx, fdy = cs.fdy, two_dx = cs.two_dx, two_dy = cs.two_dy;
    const bool last = cs.last;
    double sed_out = 0, water_out = 0, dm = 0;
    const std::size_t row = static_cast<std::size_t>(j) * w;
    const Spans& spans = span[j];
    if (spans.empty()) {
      row_sed_out[j] = 0, row_water_out[j] = 0, row_dmax[j] = 0;
      return;
    }
    const float* __restrict FL = ch.Frow(j, 0);
    const float* __restrict FR = ch.Frow(j, 1);
    const float* __restrict FD = ch.Frow(j, 2);
    const float* __restrict FU = ch.Frow(j, 3);
    const float* __restrict FUd = j > 0 ? ch.Frow(j - 1, 3) : nullptr;  // the up flux of the row below
    const float* __restrict FDu = j < h - 1 ? ch.Frow(j + 1, 2) : nullptr;
    const float* __restrict DR = ch.DRrow(j);
    const float* __restrict C = ch.CCrow(j);
    const float* __restrict Cd = j > 0 ? ch.CCrow(j - 1) : nullptr;
    const float* __restrict Cu = j < h - 1 ? ch.CCrow(j + 1) : nullptr;
    // Sediment in place (the chunk's edge rows from a copy); water into the fields or the edge rows: the prep
    // stage, the only other reader, is past this row; terrain into the ring, until the next row's update is done.
    float* __restrict S = ch.target(j, 2);
    if (S != s.data() + row) copy_spans(spans, s.data() + row, S);
    const float* __restrict B = b.data() + row;
    const float* __restrict Bd = j > 0 ? B - w : B;
    const float* __restrict Bu = j < h - 1 ? B + w : B;
    const float by_len = j > 0 && j < h - 1 ? two_dy : fdy;
    const unsigned char* __restrict SINK = sink.data() + row;
    float* __restrict B2 = ch.Brow(j);
    float* __restrict D2 = ch.target(j, 1);
    float* __restrict SPD = last ? spd.data() + row : ch.sc.speed.data();
    float* __restrict FACC = flow_acc.data() + row;
    auto cell = [&](int i) {
      const std::size_t k = row + i;
      const float dk = DR[i];
      // Volumes through each pipe this step and the sediment they carry (concentration of the source).
      const float out_v = (FL[i] + FR[i] + FD[i] + FU[i]) * fdt;
      const float conc = C[i];
      float in_v = 0.0f, in_s = 0.0f, out_s = 0.0f;
      auto pipe_out = [&](float f, bool border) {
        const float vol = f * fdt;
        const float sv = conc * vol;
        out_s += sv;
        if (border) {
          water_out += vol;
          sed_out += static_cast<double>(sv) * A;
        }
      };
      pipe_out(FL[i], i == 0);
      pipe_out(FR[i], i == w - 1);
      pipe_out(FD[i], j == 0);
      pipe_out(FU[i], j == h - 1);
      auto pipe_in = [&](float cn, float f) {
        const float vol = f * fdt;
        in_v += vol;
        in_s += cn * vol;
      };
      float fin_l = 0, fin_r = 0, fin_d = 0, fin_u = 0;
      if (i > 0) fin_l = FR[i - 1], pipe_in(C[i - 1], fin_l);
      if (i < w - 1) fin_r = FL[i + 1], pipe_in(C[i + 1], fin_r);
      if (FUd) fin_d = FUd[i], pipe_in(Cd[i], fin_d);
      if (FDu) fin_u = FDu[i], pipe_in(Cu[i], fin_u);
      float d1 = std::max(0.0f, dk + (in_v - out_v) / A);
      // Sediment heights moving in and out: the source's s / (d A) times the pipe's volume.
      float s1 = S[i] + in_s - out_s;
      const float wx = 0.5f * (fin_l - FL[i] + FR[i] - fin_r);
      const float wy = 0.5f * (fin_d - FD[i] + FU[i] - fin_u);
      const float dmean = 0.5f * (dk + d1);
      float u = 0, v = 0;
      if (dmean > 1e-3f) {
        u = wx / (fdy * dmean);
        v = wy / (fdx * dmean);
      }
      const float speed = std::sqrt(u * u + v * v);
      // Tilt from the terrain's central differences.
      const float bx = (B[i < w - 1 ? i + 1 : i] - B[i > 0 ? i - 1 : i]) / (i > 0 && i < w - 1 ? two_dx : fdx);
      const float by = (Bu[i] - Bd[i]) / by_len;
      const float g2 = bx * bx + by * by;
      const float sin_tilt = std::clamp(std::sqrt(g2 / (1.0f + g2)), 0.005f, 0.5f);
      // Capacity in proportion to the water that carries it (a concentration times the depth): a film
      // of water cannot hold metres of sediment however fast it runs.
      const float cap = kc * sin_tilt * speed * d1;
      float bk = B[i];
      const float m = mask ? mask_at(mask, k) : 1.0f;
      if (!SINK[i]) {
        if (cap > s1) {
          float rate = ks * m;
          if (hardness) rate *= 1.0f - std::clamp(hardness->data[k], 0.0f, 1.0f);
          if (p.layer_depth > 0)
            rate *= std::exp2(-std::max(0.0f, in.data[k] - bk) / static_cast<float>(p.layer_depth));
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
      d1 *= std::max(0.0f, 1.0f - keep * temp);
      if (SINK[i]) {
        water_out += static_cast<double>(d1) * A;
        sed_out += static_cast<double>(s1) * A;
        d1 = 0, s1 = 0;
      }
      B2[i] = bk, D2[i] = d1, S[i] = s1;
      SPD[i] = speed;
      FACC[i] += fdt * speed * d1;
      dm = std::max<double>(dm, d1);
    };
    if (!plain || j == 0 || j == h - 1 || w < 3) {
      for (const Span& sp : spans)
        for (int i = sp.lo; i <= sp.hi; ++i) cell(i);
    } else {
      const float* T = temperature ? temperature->data.data() + row : nullptr;
      const UpdateConst uc{fdt,    A,
                           fdx,    fdy,
                           two_dx, two_dy,
                           kc,     std::min(1.0f, ks),
                           kd,     temperature ? keep : std::max(0.0f, 1.0f - keep * 1.0f)};
      for (const Span& sp : spans) {
        const int i0 = std::max(sp.lo, 1), i1 = std::min(sp.hi, w - 2) + 1;
        if (sp.lo == 0) cell(0);
        const auto run = [&](auto interior) {
          interior(i0, i1, T, SINK, FL, FR, FD, FU, FUd, FDu, DR, C, Cd, Cu, S, B, Bd, Bu, B2, D2, SPD, FACC, uc);
        };
        if (T && row_sink[j])
          run(update_interior_evaporation_sinks);
        else if (T)
          run(update_interior_evaporation);
        else if (row_sink[j])
          run(update_interior_sinks);
        else
          run(update_interior);
        // Sinks take what reached them, in cell order as the generic cell does (the sums kept in registers).
        if (row_sink[j]) {
          double water = water_out, sediment = sed_out;
          for (int i = i0; i < i1; ++i)
            if (SINK[i]) {
              water += static_cast<double>(D2[i]) * A;
              sediment += static_cast<double>(S[i]) * A;
              D2[i] = 0, S[i] = 0;
            }
          water_out = water, sed_out = sediment;
        }
        dm = std::max<double>(dm, deepest(D2 + i0, i1 - i0));
        if (sp.hi == w - 1) cell(w - 1);
      }
    }
    row_sed_out[j] = sed_out, row_water_out[j] = water_out, row_dmax[j] = dm;
  }

  // Row r's new terrain from the ring into the field (or the edge rows).
  void retire(const Chunk& ch, int r) const { copy_spans(span[r], ch.Brow(r), ch.target(r, 0)); }

  Chunk chunk(Scratch& sc, int index) {
    const int j0 = index * chunk_rows, j1 = std::min(h, j0 + chunk_rows);
    return Chunk{sc,
                 w,
                 j0,
                 j1,
                 edge.data() + static_cast<std::size_t>(index) * kEdgeRows * kEdgeFields * w,
                 {b.data(), d.data(), s.data(), fl.data(), fr.data(), fd.data(), fu.data()}};
  }

  // The fused sweep of one step over all rows: the pipeline preps rows j0-2 .. j1+1, fluxes j0-1 .. j1 and
  // updates j0 .. j1-1 of each chunk (within the grid), each as soon as the rows it reads are ready; then the
  // chunks' edge rows go into the fields.
  void sweep(const StepConstants& c) {
    tbb::parallel_for(tbb::blocked_range<int>(0, chunks(), 1), [&](const tbb::blocked_range<int>& cr) {
      Scratch& sc = scratch.local();
      sc.resize(w);
      for (int index = cr.begin(); index != cr.end(); ++index) {
        const Chunk ch = chunk(sc, index);
        const int j0 = ch.j0, j1 = ch.j1;
        const int pr_lo = std::max(0, j0 - 2), pr_hi = std::min(h, j1 + 2);
        const int fl_lo = std::max(0, j0 - 1), fl_hi = std::min(h, j1 + 1);
        int nf = fl_lo, nm = j0;
        for (int r = pr_lo; r < pr_hi; ++r) {
          if (r + 1 < pr_hi) prefetch_row(r + 1);
          prep(ch, c, r);
          while (nf < fl_hi && r >= std::min(nf + 1, h - 1)) flux(ch, c, nf++);
          while (nm < j1 && nf >= std::min(nm + 2, h)) {
            update(ch, c, nm);
            if (nm > j0) retire(ch, nm - 1);
            ++nm;
          }
        }
        retire(ch, j1 - 1);
      }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, chunks(), 1), [&](const tbb::blocked_range<int>& cr) {
      Scratch& sc = scratch.local();
      for (int index = cr.begin(); index != cr.end(); ++index) {
        const Chunk ch = chunk(sc, index);
        for (int r = ch.j0; r < ch.j1; ++r) {
          const int slot = ch.edge_slot(r);
          if (slot < 0) continue;
          for (int f = 0; f < kEdgeFields; ++f)
            copy_spans(span[r], ch.target(r, f), ch.fields[f] + static_cast<std::size_t>(r) * w);
        }
      }
    });
  }

  // The maps at the end: heights with the suspended sediment settled, water, speed, normalized flow.
  PipeMaps maps(const ExecContext* ctx) const {
    PipeMaps maps;
    maps.out = std::make_shared<Heightfield>(in.domain);
    maps.water = std::make_shared<Heightfield>(in.domain);
    maps.velocity = std::make_shared<Heightfield>(in.domain);
    maps.flow = std::make_shared<Heightfield>(in.domain);
    float fmax = 0;
    for (std::size_t k = 0; k < n; ++k) fmax = std::max(fmax, flow_acc[k]);
    const double lmax = pipe_flow_scale(fmax, A);
    for (std::size_t k = 0; k < n; ++k) {
      maps.out->data[k] = b[k] + s[k];  // what is still suspended settles
      maps.water->data[k] = d[k];
      maps.velocity->data[k] = spd[k];
      maps.flow->data[k] = pipe_flow(flow_acc[k], lmax, A);
    }
    fill_change_maps(in, maps, ctx);
    return maps;
  }
};

}  // namespace

void check_pipe_work(const PipeParams& p, const Domain& domain) {
  const double spacing = std::min(domain.spacing.x, domain.spacing.y);
  const double dt_max = p.courant * spacing / std::sqrt(p.gravity * p.depth_scale);
  const double steps = p.duration / dt_max;
  check_work(steps * static_cast<double>(domain.resolution.x) * static_cast<double>(domain.resolution.y),
             "PipeErosion: sample updates (at least duration / CFL time step x samples)",
             "lower duration, or use a coarser grid");
}

PipeStepLength pipe_step_length(const PipeParams& p, double spacing, double t, double deepest) {
  const double dt = std::min(pipe_time_step(p, spacing, deepest), p.duration - t);
  check_pipe_step(dt, t, deepest);
  return {dt, t + dt >= p.duration - kPipeTimeSlack};
}

void check_pipe_step(double dt, double t, double deepest) {
  if (!(dt > 0.0) || !(t + dt > t))
    throw NodeError("PipeErosion: the CFL time step became " + std::to_string(dt) + " s at t = " + std::to_string(t) +
                    " s (a water depth of " + std::to_string(deepest) +
                    " m): simulated time cannot advance; lower rain_rate or the rainfall input, or duration");
}

struct PipeGrid::Run {
  PipeRun run;
};

PipeGrid::PipeGrid(const Heightfield& in, const PipeParams& p, const Heightfield* mask, const Heightfield* rainfall,
                   const Heightfield* moisture, const Heightfield* temperature, const Heightfield* hardness,
                   PipeWindow window)
    : run_(new Run{PipeRun(in, p, mask, rainfall, moisture, temperature, hardness, std::move(window))}) {}

PipeGrid::~PipeGrid() = default;

void PipeGrid::step(double dt, std::uint64_t step, bool last) { run_->run.sweep(run_->run.constants(dt, step, last)); }

float PipeGrid::cell_area() const { return run_->run.A; }

std::vector<float>& PipeGrid::field(Field f) {
  PipeRun& r = run_->run;
  std::vector<float>* all[kFields] = {&r.b, &r.d, &r.s, &r.fl, &r.fr, &r.fd, &r.fu, &r.spd, &r.flow_acc};
  return *all[f];
}

PipeMaps pipe_erosion(const Heightfield& in, const PipeParams& p, const Heightfield* mask, const Heightfield* rainfall,
                      const Heightfield* moisture, const Heightfield* temperature, const Heightfield* hardness,
                      const ExecContext* ctx, PipeStats* stats, PipeChecks checks) {
  // Non-finite heights and driving fields are refused (an infinite rain rate makes the CFL step 0: time
  // would stand still); so is a plan above the work ceiling, counted with the largest step the CFL condition
  // allows. The names are the node's ports.
  require_finite_inputs("PipeErosion", {{"in", &in},
                                        {"mask", mask},
                                        {"rainfall_rate", rainfall},
                                        {"moisture", moisture},
                                        {"evaporation_factor", temperature},
                                        {"hardness", hardness}});
  check_pipe_work(p, in.domain);
  PipeRun run(in, p, mask, rainfall, moisture, temperature, hardness, PipeWindow{}, checks.every_cell,
              checks.chunk_rows > 0 ? checks.chunk_rows : kDefaultChunkRows);
  PipeStats st;
  st.total_volume = 0;
  for (float v : in.data) st.total_volume += std::abs(static_cast<double>(v)) * run.A;
  double t = 0.0, dmax = 0.0;
  const double spacing = std::min(run.dx, run.dy);
  std::uint64_t step = 0;
  while (t < p.duration - kPipeTimeSlack) {
    check_cancelled(ctx);
    const auto [dt, last] = pipe_step_length(p, spacing, t, dmax);
    const double before = checks.conservation ? run.volume(ctx) : 0.0;
    run.sweep(run.constants(dt, step, last));
    double sed_out = 0;
    dmax = 0;
    for (int j = 0; j < run.h; ++j) {
      sed_out += run.row_sed_out[j];
      st.water_out += run.row_water_out[j];
      dmax = std::max(dmax, run.row_dmax[j]);
    }
    st.sediment_out += sed_out;
    if (checks.conservation)
      st.max_conservation_error = std::max(st.max_conservation_error, std::abs(run.volume(ctx) + sed_out - before));
    t += dt;
    ++step;
    st.dt = dt;
    report(ctx, t / p.duration);
  }
  st.steps = static_cast<int>(step);
  if (stats) *stats = st;
  return run.maps(ctx);
}

}  // namespace orogen::erosion
