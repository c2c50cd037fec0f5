#include "nodes/scatter/poisson_disk.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pt {
  float x, y;  // the output position
  float r;     // local radius
  int cls;     // class index into PoissonParams::classes
};

using scatter::FastDraws;  // the fast path's draws

// Bridson's candidate around a point of radius r from a 64-bit draw h: uniform in the annulus [r, 2r], drawn directly
// (no rejection, whose unpredictable branch and extra hashes cost most of Bridson's time): the distance
// r sqrt(1 + 3 u) (uniform area) and an angle of 32 bits, whose sine and cosine come from its nearest quarter
// turn and Taylor series on [-pi/4, pi/4] (within 2e-11 of libm).
inline __attribute__((always_inline)) void annulus_offset(std::uint64_t h, double r, double& ox, double& oy) {
  const double d = r * std::sqrt(1.0 + 3.0 * (static_cast<double>(h >> 32) * 0x1.0p-32));
  const auto w = static_cast<std::uint32_t>(h);
  const std::uint32_t q = ((w + (1u << 29)) >> 30) & 3u;                           // nearest quarter turn
  const double a = static_cast<double>(static_cast<std::int32_t>(w - (q << 30))) * (2.0 * kPi * 0x1.0p-32);
  const double a2 = a * a;
  const double s = a * (1.0 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 + a2 * (1.0 / 362880 - a2 / 39916800)))));
  const double c = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24 + a2 * (-1.0 / 720 + a2 * (1.0 / 40320 + a2 * (-1.0 / 3628800 + a2 / 479001600)))));
  // Rotated by q quarter turns: (c, s), (-s, c), (-c, -s), (s, -c).
  static constexpr double kSx[4] = {1.0, -1.0, -1.0, 1.0}, kSy[4] = {1.0, 1.0, -1.0, -1.0};
  const bool odd = q & 1u;
  ox = d * kSx[q] * (odd ? s : c);
  oy = d * kSy[q] * (odd ? c : s);
}

double field_value(const Heightfield* f, double x, double y) {
  if (!f) return 1.0;
  const double v = f->sample_world(x, y);
  if (!(v > 0.0)) return 0.0;  // NaN too
  return std::min(v, 1.0);
}

// The chunks of one class: a window of the class's world-space chunk grid (chunk side C, anchored at 0).
struct ClassChunks {
  double C = 1.0;
  std::int64_t cx0 = 0, cy0 = 0;  // chunk index of the window's (0, 0)
  int nx = 0, ny = 0;
  std::int64_t core_x0 = 0, core_y0 = 0, core_x1 = 0, core_y1 = 0;  // chunks overlapping the final rectangle
  std::vector<std::vector<Pt>> chunks;
  std::vector<Pt>& at(std::int64_t gx, std::int64_t gy) {
    return chunks[static_cast<std::size_t>(gy - cy0) * nx + static_cast<std::size_t>(gx - cx0)];
  }
  const std::vector<Pt>& at(std::int64_t gx, std::int64_t gy) const {
    return chunks[static_cast<std::size_t>(gy - cy0) * nx + static_cast<std::size_t>(gx - cx0)];
  }
};

struct Sampler {
  const PoissonParams& p;
  std::vector<int> order;       // class indices, largest radius first
  std::vector<int> rank;        // position of each class in `order`
  std::vector<double> rmax;     // per class: largest local radius
  std::vector<double> cell;     // per class: background grid cell (r / sqrt 2, slightly less)
  std::vector<double> chunk;    // per class: chunk side
  std::vector<double> reach;    // per class: largest conflict distance with itself and the classes before it
  std::vector<ClassChunks> grids;  // per class

  explicit Sampler(const PoissonParams& params) : p(params) {}

  double local_radius(int k, double x, double y) const {
    double d = field_value(p.density, x, y) * field_value(p.classes[k].density, x, y);
    if (p.mask) {
      const double m = p.mask->sample_world(x, y);
      if (!(m >= 0.5)) d = 0.0;
    }
    if (!(d >= p.min_density) || d <= 0.0) return 0.0;
    return p.classes[k].radius / std::sqrt(d);
  }

  double conflict(int a, double ra, int b, double rb) const {
    return a == b ? std::max(ra, rb) : p.cross_separation * 0.5 * (ra + rb);
  }

  // Per-chunk working state.
  struct Local {
    double ax0, ay0, ax1, ay1;  // the chunk [ax0, ax1) x [ay0, ay1)
    double gx0, gy0;            // origin of the local grids (the chunk minus the interaction distance)
    std::vector<double> x, y;   // gathered and new points (double copies of the float positions)
    std::vector<float> r;
    std::vector<int> cls;
    std::vector<int> own;       // indices of the points placed in this chunk
    struct Grid {
      double h = 0;
      int n = 0;
      std::vector<int> cells;  // point index or -1
    };
    std::vector<Grid> grids;    // per class
  };

  void grid_insert(Local& L, int idx) const {
    auto& g = L.grids[L.cls[idx]];
    if (g.n == 0) return;
    const int i = static_cast<int>(std::floor((L.x[idx] - L.gx0) / g.h));
    const int j = static_cast<int>(std::floor((L.y[idx] - L.gy0) / g.h));
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return;  // beyond the interaction distance of the chunk
    int& c = g.cells[static_cast<std::size_t>(j) * g.n + i];
    if (c >= 0) throw std::logic_error("PoissonDisk: two points of one class in one grid cell");
    c = idx;
  }

  // Grid offsets (nearest first) of the cells of class j that can hold a point conflicting with a class-k
  // point anywhere in a cell: the cells whose distance to the cell is below the largest conflict distance.
  std::vector<std::vector<std::vector<std::pair<int, int>>>> offsets;  // [k][j]
  bool varies = false;
  bool uniform = false;  // one class, constant radius: process_uniform

  void make_offsets() {
    const std::size_t K = p.classes.size();
    offsets.assign(K, std::vector<std::vector<std::pair<int, int>>>(K));
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t j = 0; j < K; ++j) {
        const double reach_kj = conflict(static_cast<int>(k), rmax[k], static_cast<int>(j), rmax[j]);
        if (reach_kj <= 0.0) continue;
        // Cell sizes differ between classes: measure in class j's cells, from a class-k cell that may span
        // several of them (the candidate's position is what is looked up, so one cell of class j suffices).
        const double h = cell[j];
        const int w = static_cast<int>(std::ceil(reach_kj / h)) + 1;
        std::vector<std::pair<double, std::pair<int, int>>> list;
        for (int dj = -w; dj <= w; ++dj)
          for (int di = -w; di <= w; ++di) {
            const double dx = std::max(0, std::abs(di) - 1) * h, dy = std::max(0, std::abs(dj) - 1) * h;
            const double d = std::sqrt(dx * dx + dy * dy);
            if (d < reach_kj) list.push_back({d, {di, dj}});
          }
        std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& e : list) offsets[k][j].push_back(e.second);
      }
  }

  // True if a point of class k with radius rk at (x, y) conflicts with none placed so far.
  bool free_at(const Local& L, int k, double x, double y, double rk) const {
    for (int j : order) {
      const auto& g = L.grids[j];
      if (g.n == 0) continue;
      const int ci = static_cast<int>(std::floor((x - L.gx0) / g.h));
      const int cj = static_cast<int>(std::floor((y - L.gy0) / g.h));
      for (const auto& [di, dj] : offsets[k][j]) {
        const int ii = ci + di, jj = cj + dj;
        if (ii < 0 || jj < 0 || ii >= g.n || jj >= g.n) continue;
        const int q = g.cells[static_cast<std::size_t>(jj) * g.n + ii];
        if (q < 0) continue;
        const double dx = L.x[q] - x, dy = L.y[q] - y;
        const double c = conflict(k, rk, j, L.r[q]);
        if (dx * dx + dy * dy < c * c) return false;
      }
    }
    return true;
  }

  // True if every point of the rectangle lies within the exclusion of the placed points: inside one exclusion
  // disk, or inside the union of two (two overlapping disks form a simply connected region, so a convex
  // rectangle whose boundary they cover lies inside them). Then no point of class k, whatever its radius, can
  // go there. Exact for one and two disks; rectangles that need three are refined further.
  bool covered(const Local& L, int k, double x0, double y0, double x1, double y1) const {
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    // A lower bound of the radius a class-k point would have in the rectangle: the smallest at its corners and
    // centre (the class radius where none of them admits a point).
    double r0 = p.classes[k].radius;
    if (varies) {
      r0 = INFINITY;
      for (const auto& [px, py] : {std::pair{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}, {cx, cy}}) {
        const double r = local_radius(k, px, py);
        if (r > 0.0) r0 = std::min(r0, r);
      }
      if (!std::isfinite(r0)) r0 = p.classes[k].radius;
    }
    // The disks that reach the rectangle: first whether one alone holds all four corners (it then holds the
    // rectangle), then, for pairs, the parameter interval of each edge each disk covers.
    constexpr int kMaxDisks = 24;
    int disk[kMaxDisks];
    double disk_c[kMaxDisks];
    int count = 0;
    auto consider = [&](int q, double c) {
      const double qx = L.x[q], qy = L.y[q], c2 = c * c;
      const double nx = std::clamp(qx, x0, x1) - qx, ny = std::clamp(qy, y0, y1) - qy;
      if (nx * nx + ny * ny >= c2) return false;  // does not reach the rectangle
      const double fx = std::max(qx - x0, x1 - qx), fy = std::max(qy - y0, y1 - qy);
      if (fx * fx + fy * fy < c2) return true;  // the farthest corner is inside
      if (count < kMaxDisks) {
        disk[count] = q;
        disk_c[count++] = c;
      }
      return false;
    };
    for (int j : order) {
      const auto& g = L.grids[j];
      if (g.n == 0) continue;
      // The rectangle may straddle class j's cells (other sizes): look around each of its corners' cells.
      const int ci0 = static_cast<int>(std::floor((x0 - L.gx0) / g.h)), ci1 = static_cast<int>(std::floor((x1 - L.gx0) / g.h));
      const int cj0 = static_cast<int>(std::floor((y0 - L.gy0) / g.h)), cj1 = static_cast<int>(std::floor((y1 - L.gy0) / g.h));
      if (ci0 == ci1 && cj0 == cj1) {
        for (const auto& [di, dj] : offsets[k][j]) {
          const int ii = ci0 + di, jj = cj0 + dj;
          if (ii < 0 || jj < 0 || ii >= g.n || jj >= g.n) continue;
          const int q = g.cells[static_cast<std::size_t>(jj) * g.n + ii];
          if (q >= 0 && consider(q, conflict(k, r0, j, L.r[q]))) return true;
        }
      } else {
        const int w = static_cast<int>(std::ceil(reach[k] / g.h)) + 1;
        for (int jj = std::max(cj0 - w, 0); jj <= std::min(cj1 + w, g.n - 1); ++jj)
          for (int ii = std::max(ci0 - w, 0); ii <= std::min(ci1 + w, g.n - 1); ++ii) {
            const int q = g.cells[static_cast<std::size_t>(jj) * g.n + ii];
            if (q >= 0 && consider(q, conflict(k, r0, j, L.r[q]))) return true;
          }
      }
    }
    if (count < 2) return false;
    struct Cover {
      double lo[4], hi[4];
    };
    Cover covers[kMaxDisks];
    const double ex[4][4] = {{x0, y0, x1, y0}, {x1, y0, x1, y1}, {x1, y1, x0, y1}, {x0, y1, x0, y0}};
    for (int d = 0; d < count; ++d) {
      const double qx = L.x[disk[d]], qy = L.y[disk[d]], c = disk_c[d];
      for (int e = 0; e < 4; ++e) {
        const double ax = ex[e][0] - qx, ay = ex[e][1] - qy, dx = ex[e][2] - ex[e][0], dy = ex[e][3] - ex[e][1];
        const double aa = dx * dx + dy * dy, bb = ax * dx + ay * dy, cc = ax * ax + ay * ay - c * c;
        const double disc = bb * bb - aa * cc;
        if (disc <= 0.0 || aa <= 0.0) {
          covers[d].lo[e] = 1.0;
          covers[d].hi[e] = 0.0;
        } else {
          const double sq = std::sqrt(disc);
          covers[d].lo[e] = (-bb - sq) / aa;
          covers[d].hi[e] = (-bb + sq) / aa;
        }
      }
    }
    for (int a = 0; a < count; ++a)
      for (int b = a + 1; b < count; ++b) {
        bool all = true;
        for (int e = 0; e < 4 && all; ++e) {
          double l1 = covers[a].lo[e], h1 = covers[a].hi[e], l2 = covers[b].lo[e], h2 = covers[b].hi[e];
          if (l1 > l2) {
            std::swap(l1, l2);
            std::swap(h1, h2);
          }
          const bool single = (l1 < 0.0 && h1 > 1.0) || (l2 < 0.0 && h2 > 1.0);
          const bool joined = l1 < 0.0 && h1 > l2 && l2 < h2 && std::max(h1, h2) > 1.0;
          all = single || joined;
        }
        if (all) return true;
      }
    return false;
  }

  // Tries to place a class-k point at (x, y) (double); returns its local index or -1.
  int try_place(Local& L, int k, double x, double y) const {
    const float fx = static_cast<float>(x), fy = static_cast<float>(y);
    const double dx = fx, dy = fy;
    if (!(dx >= L.ax0 && dx < L.ax1 && dy >= L.ay0 && dy < L.ay1)) return -1;
    const double rk = varies ? local_radius(k, dx, dy) : p.classes[k].radius;
    if (rk <= 0.0) return -1;
    const float rf = static_cast<float>(rk);
    if (!free_at(L, k, dx, dy, rf)) return -1;
    const int idx = static_cast<int>(L.x.size());
    L.x.push_back(dx);
    L.y.push_back(dy);
    L.r.push_back(rf);
    L.cls.push_back(k);
    L.own.push_back(idx);
    grid_insert(L, idx);
    return idx;
  }

  void process(std::int64_t gcx, std::int64_t gcy, int k) {
    const double C = chunk[k], D = reach[k];
    Local L;
    L.ax0 = static_cast<double>(gcx) * C;
    L.ax1 = static_cast<double>(gcx + 1) * C;
    L.ay0 = static_cast<double>(gcy) * C;
    L.ay1 = static_cast<double>(gcy + 1) * C;
    L.gx0 = L.ax0 - D;
    L.gy0 = L.ay0 - D;
    L.grids.resize(p.classes.size());
    // Grids for the classes placed so far and this one.
    for (int j : order) {
      auto& g = L.grids[j];
      g.h = cell[j];
      g.n = static_cast<int>(std::ceil((C + 2.0 * D) / g.h)) + 1;
      g.cells.assign(static_cast<std::size_t>(g.n) * g.n, -1);
      if (j == k) break;
    }
    // Gather the points within the interaction distance of the chunk: this class's from the neighbouring
    // chunks (earlier phases), the earlier classes' from their final chunks.
    std::vector<int> active;
    const double seed_reach = 2.0 * rmax[k];
    auto gather = [&](const Pt& q) {
      const double qx = q.x, qy = q.y;
      if (qx < L.ax0 - D || qx >= L.ax1 + D || qy < L.ay0 - D || qy >= L.ay1 + D) return;
      const int idx = static_cast<int>(L.x.size());
      L.x.push_back(qx);
      L.y.push_back(qy);
      L.r.push_back(q.r);
      L.cls.push_back(q.cls);
      grid_insert(L, idx);
      if (q.cls == k && qx >= L.ax0 - seed_reach && qx < L.ax1 + seed_reach && qy >= L.ay0 - seed_reach &&
          qy < L.ay1 + seed_reach)
        active.push_back(idx);
    };
    for (int j : order) {
      if (j == k) break;
      const ClassChunks& g = grids[j];
      const auto i0 = static_cast<std::int64_t>(std::floor((L.ax0 - D) / g.C));
      const auto i1 = static_cast<std::int64_t>(std::floor((L.ax1 + D) / g.C));
      const auto j0 = static_cast<std::int64_t>(std::floor((L.ay0 - D) / g.C));
      const auto j1 = static_cast<std::int64_t>(std::floor((L.ay1 + D) / g.C));
      for (auto cy = j0; cy <= j1; ++cy)
        for (auto cx = i0; cx <= i1; ++cx) {
          if (cx < g.core_x0 || cx > g.core_x1 || cy < g.core_y0 || cy > g.core_y1)
            throw std::logic_error("PoissonDisk: a chunk reads beyond an earlier class's final chunks");
          for (const Pt& q : g.at(cx, cy)) gather(q);
        }
    }
    ClassChunks& own = grids[k];
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (const Pt& q : own.at(gcx + dx, gcy + dy)) gather(q);
    scatter::Draws draw{scatter::hash(p.seed, 0x5CA77E5ull, static_cast<std::uint64_t>(k), scatter::bits(gcx),
                                      scatter::bits(gcy))};
    // Bridson: one initial dart into the chunk, then grow from the active points (neighbours' included).
    for (int t = 0; t < 4; ++t) {
      const int idx = try_place(L, k, L.ax0 + draw.next() * C, L.ay0 + draw.next() * C);
      if (idx >= 0) {
        active.push_back(idx);
        break;
      }
    }
    while (!active.empty()) {
      const std::size_t pick = static_cast<std::size_t>(draw.next() * static_cast<double>(active.size()));
      const int a = active[std::min(pick, active.size() - 1)];
      const double ra = L.r[a];
      bool placed = false;
      for (int t = 0; t < p.attempts; ++t) {
        double ox, oy;
        annulus_offset(draw.bits(), ra, ox, oy);
        const int idx = try_place(L, k, L.x[a] + ox, L.y[a] + oy);
        if (idx >= 0) {
          active.push_back(idx);
          placed = true;
          break;
        }
      }
      if (!placed) {
        auto it = std::find(active.begin(), active.end(), a);
        *it = active.back();
        active.pop_back();
      }
    }
    if (p.fill_gaps) fill(L, k, draw);
    // Store this chunk's new points.
    auto& dst = own.at(gcx, gcy);
    for (int idx : L.own) dst.push_back({static_cast<float>(L.x[idx]), static_cast<float>(L.y[idx]), L.r[idx], k});
  }

  // ---------------------------------------------------------------------------------------------------------
  // Fast path: one class of constant radius (no density, no mask), the common case and the benchmark's.
  // Same chunks and phases as `process`, with:
  // - a background grid aligned with the chunk (cell C / m with m = floor(C sqrt 2 / r) + 1, so a cell's
  //   diagonal is below r: at most one point per cell and a point covers its whole cell), padded so that the
  //   5 x 5 neighbourhood of any cell a candidate or a gathered point can fall in needs no bounds checks;
  //   cells hold the point's position (double copies of the stored floats) or a far sentinel, so a lookup is
  //   a load and a distance, no indirection; the per-thread grid is reused across chunks (no allocation);
  // - Bridson from the chunk's own points only (the neighbours' points constrain, they do not grow), with
  //   SplitMix64 draws and the candidates of an active point drawn in blocks before they are tested;
  // - gap filling cell by cell: a grid cell with a point is covered; a bitmask of sub-squares each inside one
  //   disk proves most empty ones covered; the others gather the (at most 24) points of their 5 x 5
  //   neighbourhood, get a few darts into their open sub-squares, then the exact coverage test and darts into
  //   what has room until one lands (then the cell is covered) or none is left.
  // Distances are compared exactly as the general path does (double, on the stored float positions).
  static constexpr double kEmpty = 1e150;
  static constexpr float kFar = 1e15f;  // float sentinel: squared distances stay finite
  static constexpr int kPad = 4;  // cells around the chunk: 2 for the reach r, 2 for the 5 x 5 window
  static constexpr int kBlock = 8;  // Bridson's candidates drawn at once

  struct UniformScratch {
    std::vector<double> gx, gy;                   // grid cells: position or kEmpty
    std::vector<float> lx, ly;                    // the same relative to the grid origin, in float (filter)
    std::vector<std::pair<double, double>> active;
    std::vector<std::pair<double, double>> own;
    std::vector<std::pair<double, double>> near;  // the gathered points of the neighbouring chunks
    std::vector<std::uint64_t> cover;             // gap filling: sub-squares inside one disk, a row per word
    struct Rect {
      double x0, y0, x1, y1;
    };
    std::vector<Rect> cells, next;
  };

  // The float a position is stored as, as a double. GCC 12's SLP vectoriser at -O3 drops this rounding once
  // inlined here (-fno-tree-slp-vectorize or -fno-ipa-cp-clone fix it; PoissonDisk.GuaranteeHoldsAtLargeCoordinates
  // then finds pairs too close): the empty asm pins f as a float in a register, which costs nothing.
  static double to_float(double v) {
    float f = static_cast<float>(v);
    asm("" : "+x"(f));
    return f;
  }

  static int uniform_cells(double C, double r) { return static_cast<int>(std::floor(C * std::sqrt(2.0) / r)) + 1; }

  void process_uniform(std::int64_t gcx, std::int64_t gcy, int k) {
    thread_local UniformScratch S;
    const double C = chunk[k];
    const float rf = static_cast<float>(p.classes[k].radius);
    const double r = rf, r2 = r * r;
    const int m = uniform_cells(C, p.classes[k].radius);
    const double h = C / m, inv_h = m / C;
    const int n = m + 2 * kPad;
    const double ax0 = static_cast<double>(gcx) * C, ax1 = static_cast<double>(gcx + 1) * C;
    const double ay0 = static_cast<double>(gcy) * C, ay1 = static_cast<double>(gcy + 1) * C;
    const double ox = ax0 - kPad * h, oy = ay0 - kPad * h;
    const double D = reach[k];
    S.gx.assign(static_cast<std::size_t>(n) * n, kEmpty);
    S.gy.assign(static_cast<std::size_t>(n) * n, kEmpty);
    // The float copies are read 8 cells per window row (a superset of the 5 needed: any point closer than r
    // in any cell is a real conflict), hence the tail.
    S.lx.assign(static_cast<std::size_t>(n) * n + 8, kFar);
    S.ly.assign(static_cast<std::size_t>(n) * n + 8, kFar);
    float* const lx = S.lx.data();
    float* const ly = S.ly.data();
    S.active.clear();
    S.own.clear();
    S.near.clear();
    double* const gx = S.gx.data();
    double* const gy = S.gy.data();
    // Truncation is the floor here: every position looked up (gathered within D < kPad h of the chunk, or
    // inside it) lies right of and above the grid origin.
    auto cell_of = [&](double x, double y) {
      const int i = static_cast<int>((x - ox) * inv_h);
      const int j = static_cast<int>((y - oy) * inv_h);
      return j * n + i;
    };
    auto insert = [&](double x, double y) {
      const int c = cell_of(x, y);
      if (gx[c] != kEmpty) throw std::logic_error("PoissonDisk: two points in one grid cell");
      gx[c] = x;
      gy[c] = y;
      lx[c] = static_cast<float>(x - ox);
      ly[c] = static_cast<float>(y - oy);
    };
    // No point of the 5 x 5 window around cell c closer than r to (x, y) (nearest rows first).
    auto free_at_cell = [&](int c, double x, double y) {
      for (int dj : {0, -1, 1, -2, 2}) {
        const int b = c + dj * n;
        bool hit = false;
        for (int di = -2; di <= 2; ++di) {
          const double dx = gx[b + di] - x, dy = gy[b + di] - y;
          hit |= dx * dx + dy * dy < r2;
        }
        if (hit) return false;
      }
      return true;
    };
    // The same test, filtered in float on positions relative to the grid origin (|l| < 16 r): the float
    // squared distance is within 1e-5 r^2 (relative to max(d^2, r^2)) of the double one, so below
    // r^2 (1 - 1e-4) it is a conflict, at or above r^2 (1 + 1e-4) no conflict, and in between the double
    // test decides.
    const float lo2 = static_cast<float>(r2 * (1.0 - 1e-4)), hi2 = static_cast<float>(r2 * (1.0 + 1e-4));
    auto free_fast = [&](int c, double x, double y) {
      typedef float v4f __attribute__((vector_size(16)));
      typedef int v4i __attribute__((vector_size(16)));
      const float cx = static_cast<float>(x - ox), cy = static_cast<float>(y - oy);
      const v4f vx = {cx, cx, cx, cx}, vy = {cy, cy, cy, cy};
      const v4f vlo = {lo2, lo2, lo2, lo2}, vhi = {hi2, hi2, hi2, hi2};
      v4i sure = {0, 0, 0, 0}, maybe = {0, 0, 0, 0};
      for (int dj = -2; dj <= 2; ++dj) {
        const float* px = lx + (c + dj * n - 2);
        const float* py = ly + (c + dj * n - 2);
        for (int e = 0; e < 8; e += 4) {
          v4f ax, ay;
          std::memcpy(&ax, px + e, sizeof ax);
          std::memcpy(&ay, py + e, sizeof ay);
          const v4f dx = ax - vx, dy = ay - vy;
          const v4f d2 = dx * dx + dy * dy;
          sure |= d2 < vlo;
          maybe |= d2 < vhi;
        }
      }
      if (sure[0] | sure[1] | sure[2] | sure[3]) return false;
      if (!(maybe[0] | maybe[1] | maybe[2] | maybe[3])) return true;
      return free_at_cell(c, x, y);
    };
    // Rounds a candidate to float; places it if inside the chunk and free.
    auto try_place = [&](double x, double y) {
      const double fx = to_float(x), fy = to_float(y);
      if (!(fx >= ax0 && fx < ax1 && fy >= ay0 && fy < ay1)) return false;
      const int c = cell_of(fx, fy);
      if (!free_fast(c, fx, fy)) return false;
      gx[c] = fx;
      gy[c] = fy;
      lx[c] = static_cast<float>(fx - ox);
      ly[c] = static_cast<float>(fy - oy);
      S.own.emplace_back(fx, fy);
      return true;
    };

    // Gather this class's points of the neighbouring chunks within the interaction distance. They are not made
    // active (unlike the general path): most of their candidates fall outside the chunk or near its points, so
    // each cost its k failures; the strips they would have grown into are left to the gap filling (2 km: 7%
    // faster, 0.3% more points).
    ClassChunks& own = grids[k];
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (const Pt& q : own.at(gcx + dx, gcy + dy)) {
          const double qx = q.x, qy = q.y;
          if (qx < ax0 - D || qx >= ax1 + D || qy < ay0 - D || qy >= ay1 + D) continue;
          insert(qx, qy);
          S.near.emplace_back(qx, qy);
        }
    FastDraws draw{scatter::hash(p.seed, 0x5CA77E5ull, static_cast<std::uint64_t>(k), scatter::bits(gcx),
                                      scatter::bits(gcy))};
    for (int t = 0; t < 4; ++t)
      if (try_place(ax0 + draw.next() * C, ay0 + draw.next() * C)) {
        S.active.push_back(S.own.back());
        break;
      }
    while (!S.active.empty()) {
      const std::size_t pick =
          std::min(static_cast<std::size_t>(draw.next() * static_cast<double>(S.active.size())), S.active.size() - 1);
      const auto [ax, ay] = S.active[pick];
      // The candidates in blocks of up to 8, computed before any is tested: independent of one another, their
      // draws and trigonometry overlap instead of each waiting for the previous test.
      bool placed = false;
      for (int t0 = 0; t0 < p.attempts && !placed; t0 += kBlock) {
        const int nb = std::min(kBlock, p.attempts - t0);
        double cx[kBlock], cy[kBlock];
        for (int t = 0; t < nb; ++t) annulus_offset(draw.bits(), r, cx[t], cy[t]);
        for (int t = 0; t < nb; ++t)
          if (try_place(ax + cx[t], ay + cy[t])) {
            S.active.push_back(S.own.back());
            placed = true;
            break;
          }
      }
      if (!placed) {
        S.active[pick] = S.active.back();
        S.active.pop_back();
      }
    }
    if (p.fill_gaps) fill_uniform(S, draw, m, n, h, ax0, ay0, ax1, ay1, r2, try_place);
    auto& dst = own.at(gcx, gcy);
    dst.reserve(S.own.size());
    for (const auto& [x, y] : S.own) dst.push_back({static_cast<float>(x), static_cast<float>(y), rf, k});
  }

  template <class TryPlace>
  void fill_uniform(UniformScratch& S, FastDraws& draw, int m, int n, double h, double ax0, double ay0,
                    double ax1, double ay1, double r2, TryPlace& try_place) const {
    using Rect = UniformScratch::Rect;
    const double* const gx = S.gx.data();
    const double* const gy = S.gy.data();
    double qx[25], qy[25];
    int count = 0;
    // Whether some point of the closed rectangle is at distance >= r from every gathered point (room for a
    // point). Exact: the free part F of the rectangle, if not empty, is compact and its lowest-leftmost point
    // is a vertex of its boundary (a point in the interior of a single arc of a disk's circle is never
    // extreme: the tangent there runs outside the disk), i.e. a corner of the rectangle, a crossing of a circle
    // with an edge or a crossing of two circles inside it; so F is empty iff each such vertex lies strictly
    // inside another disk. Rounding only errs towards "room" (a vertex counts as covered only when it is
    // inside a disk by a relative margin of 1e-9), which costs a dart, never maximality.
    auto has_room = [&](const Rect& c) {
      int near[25];
      int nn = 0;
      for (int q = 0; q < count; ++q) {
        const double nx = std::clamp(qx[q], c.x0, c.x1) - qx[q], ny = std::clamp(qy[q], c.y0, c.y1) - qy[q];
        if (nx * nx + ny * ny >= r2) continue;
        const double fx = std::max(qx[q] - c.x0, c.x1 - qx[q]), fy = std::max(qy[q] - c.y0, c.y1 - qy[q]);
        if (fx * fx + fy * fy < r2) return false;  // one disk holds the four corners, hence the rectangle
        near[nn++] = q;
      }
      if (nn == 0) return true;
      // Cheap proof first: each quarter inside a single disk.
      {
        const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
        const Rect quarters[4] = {{c.x0, c.y0, mx, my}, {mx, c.y0, c.x1, my}, {c.x0, my, mx, c.y1}, {mx, my, c.x1, c.y1}};
        bool all = true;
        for (const Rect& u : quarters) {
          bool one = false;
          for (int d = 0; d < nn && !one; ++d) {
            const double px = qx[near[d]], py = qy[near[d]];
            const double fx = std::max(px - u.x0, u.x1 - px), fy = std::max(py - u.y0, u.y1 - py);
            one = fx * fx + fy * fy < r2;
          }
          if (!one) {
            all = false;
            break;
          }
        }
        if (all) return false;
      }
      const double inside = r2 * (1.0 - 1e-9);
      auto free_vertex = [&](double x, double y, int s1, int s2) {
        for (int d = 0; d < nn; ++d) {
          if (d == s1 || d == s2) continue;
          const double dx = qx[near[d]] - x, dy = qy[near[d]] - y;
          if (dx * dx + dy * dy < inside) return false;
        }
        return true;
      };
      if (free_vertex(c.x0, c.y0, -1, -1) || free_vertex(c.x1, c.y0, -1, -1) || free_vertex(c.x0, c.y1, -1, -1) ||
          free_vertex(c.x1, c.y1, -1, -1))
        return true;
      const double tol = 1e-9 * std::sqrt(r2);
      for (int d = 0; d < nn; ++d) {
        const double px = qx[near[d]], py = qy[near[d]];
        for (const double y : {c.y0, c.y1}) {  // horizontal edges
          const double e = r2 - (y - py) * (y - py);
          if (e <= 0.0) continue;
          const double s = std::sqrt(e);
          for (const double x : {px - s, px + s})
            if (x >= c.x0 - tol && x <= c.x1 + tol && free_vertex(x, y, d, -1)) return true;
        }
        for (const double x : {c.x0, c.x1}) {  // vertical edges
          const double e = r2 - (x - px) * (x - px);
          if (e <= 0.0) continue;
          const double s = std::sqrt(e);
          for (const double y : {py - s, py + s})
            if (y >= c.y0 - tol && y <= c.y1 + tol && free_vertex(x, y, d, -1)) return true;
        }
      }
      for (int a = 0; a < nn; ++a)
        for (int b = a + 1; b < nn; ++b) {
          const double ax = qx[near[a]], ay = qy[near[a]];
          const double ux = qx[near[b]] - ax, uy = qy[near[b]] - ay;
          const double d2 = ux * ux + uy * uy;
          if (!(d2 > 0.0) || d2 >= 4.0 * r2) continue;
          const double t = std::sqrt((r2 - 0.25 * d2) / d2);
          const double mx = ax + 0.5 * ux, my = ay + 0.5 * uy;
          for (const double sgn : {-1.0, 1.0}) {
            const double x = mx - sgn * t * uy, y = my + sgn * t * ux;
            if (x >= c.x0 - tol && x <= c.x1 + tol && y >= c.y0 - tol && y <= c.y1 + tol && free_vertex(x, y, a, b))
              return true;
          }
        }
      return false;
    };
    // Cheap coverage first: each cell split into sub x sub squares (a row of the chunk's squares fits a 64-bit
    // word), a bit set where the square lies inside one disk shrunk by 1e-6 r (so the rounding of the square
    // edges cannot matter). A cell whose squares are all set is covered; only the squares left get the exact
    // test above, and the darts go into those with room.
    constexpr int kMaxSub = 5;
    const int sub = std::min(kMaxSub, 64 / m), M = m * sub;  // m = 12 (chunk 8 r): 5
    if (sub < 1) throw std::logic_error("PoissonDisk: too many grid cells per chunk");
    const double s = h / sub, inv_s = sub / h;
    const double rho = std::sqrt(r2) * (1.0 - 1e-6), rho2 = rho * rho;
    S.cover.assign(static_cast<std::size_t>(M), 0);
    std::uint64_t* const cover = S.cover.data();
    // Square indices of the disks' extents lie in (-M, 2M): floor and ceiling by truncation of a shifted value
    // (its rounding moves an edge by ~1e-14 s, well within the 1e-6 r margin).
    const double shift = 2.0 * M;
    auto floor_of = [&](double x) { return static_cast<int>(x + shift) - 2 * M; };
    auto ceil_of = [&](double x) { return 2 * M - static_cast<int>(shift - x); };
    auto cover_disk = [&](double px, double py) {
      const double u = px - ax0, v = py - ay0;
      const int b0 = std::max(0, floor_of((v - rho) * inv_s));
      const int b1 = std::min(M - 1, floor_of((v + rho) * inv_s));
      for (int b = b0; b <= b1; ++b) {
        const double fy = std::max(std::abs(b * s - v), std::abs((b + 1) * s - v));
        const double e = rho2 - fy * fy;
        if (e <= 0.0) continue;
        const double w = std::sqrt(e);
        const int a0 = std::max(0, ceil_of((u - w) * inv_s));
        const int a1 = std::min(M, floor_of((u + w) * inv_s));  // one past the last
        if (a1 > a0) cover[b] |= (~0ull >> (64 - (a1 - a0))) << a0;
      }
    };
    for (const auto& [x, y] : S.near) cover_disk(x, y);
    for (const auto& [x, y] : S.own) cover_disk(x, y);
    const std::uint64_t cell_bits = (1ull << sub) - 1;
    constexpr int kLevels = 6;  // from the squares (h / 5) down to h / 320
    constexpr int kDarts = 4;   // per open rectangle and level (a dart costs a few distances, a refinement more)
    constexpr int kFirstDarts = 2;  // per square left by the bitmask, before any exact test
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const int c0 = (j + kPad) * n + (i + kPad);
        if (gx[c0] != kEmpty) continue;  // a point covers its cell
        std::uint64_t open[kMaxSub];
        std::uint64_t any = 0;
        for (int t = 0; t < sub; ++t) {
          open[t] = ~cover[j * sub + t] & (cell_bits << (i * sub));
          any |= open[t];
        }
        if (!any) continue;
        // The disks that reach the cell (every point that can conflict with a point of the cell), gathered
        // without branches from its 5 x 5 neighbourhood (its own cell is empty).
        count = 0;
        const Rect cell{ax0 + i * h, ay0 + j * h, i + 1 == m ? ax1 : ax0 + (i + 1) * h, j + 1 == m ? ay1 : ay0 + (j + 1) * h};
        for (int dj = -2; dj <= 2; ++dj)
          for (int di = -2; di <= 2; ++di) {
            const int c = c0 + dj * n + di;
            const double x = gx[c], y = gy[c];
            const double nx = std::clamp(x, cell.x0, cell.x1) - x, ny = std::clamp(y, cell.y0, cell.y1) - y;
            qx[count] = x;
            qy[count] = y;
            count += nx * nx + ny * ny < r2;  // kEmpty is far
          }
        // A dart: rejected cheaply by the disks that reach the cell, then placed through the full check (its
        // float rounding may leave the cell; it still covers it, the cell's diagonal being below r).
        auto dart = [&](double x, double y) {
          const double fx = to_float(x), fy = to_float(y);
          for (int q = 0; q < count; ++q) {
            const double dx = qx[q] - fx, dy = qy[q] - fy;
            if (dx * dx + dy * dy < r2) return false;
          }
          if (!try_place(fx, fy)) return false;
          cover_disk(S.own.back().first, S.own.back().second);
          return true;
        };
        Rect squares[64];
        int ns = 0;
        for (int t = 0; t < sub; ++t)
          for (std::uint64_t bits = open[t]; bits; bits &= bits - 1) {
            const int a = std::countr_zero(bits), b = j * sub + t;
            squares[ns++] = {ax0 + a * s, ay0 + b * s, a + 1 == M ? ax1 : ax0 + (a + 1) * s, b + 1 == M ? ay1 : ay0 + (b + 1) * s};
          }
        // Darts first, uniform over the squares left (a gap is most often wide enough to be hit), and only then
        // the exact test, which proves the other cells covered or finds the squares the finer darts go to.
        bool done = false;
        for (int t = 0; t < kFirstDarts * ns && !done; ++t) {
          double u, v;
          draw.next2(u, v);
          const Rect& c = squares[std::min(ns - 1, static_cast<int>(draw.next() * ns))];
          done = dart(c.x0 + u * (c.x1 - c.x0), c.y0 + v * (c.y1 - c.y0));
        }
        if (done) continue;
        S.cells.clear();
        for (int q = 0; q < ns; ++q)
          if (has_room(squares[q])) S.cells.push_back(squares[q]);
        if (S.cells.empty()) continue;
        for (int level = 0; level <= kLevels && !done && !S.cells.empty(); ++level) {
          for (const Rect& c : S.cells) {
            for (int t = 0; t < kDarts && !done; ++t) {
              double u, v;
              draw.next2(u, v);
              done = dart(c.x0 + u * (c.x1 - c.x0), c.y0 + v * (c.y1 - c.y0));
            }
            if (done) break;
          }
          if (done) break;
          if (level == kLevels) {
            for (const Rect& c : S.cells)
              if (dart(0.5 * (c.x0 + c.x1), 0.5 * (c.y0 + c.y1))) break;
            break;
          }
          S.next.clear();
          for (const Rect& c : S.cells) {
            const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
            const Rect q[4] = {{c.x0, c.y0, mx, my}, {mx, c.y0, c.x1, my}, {c.x0, my, mx, c.y1}, {mx, my, c.x1, c.y1}};
            for (const Rect& part : q)
              if (has_room(part)) S.next.push_back(part);
          }
          std::swap(S.cells, S.next);
        }
      }
  }

  // Ebeida et al. (2011): darts into the cells not yet covered by an exclusion disk, then into their quarters.
  void fill(Local& L, int k, scatter::Draws& draw) const {
    struct Rect {
      double x0, y0, x1, y1;
    };
    const double h = cell[k];
    const int n = static_cast<int>(std::ceil(chunk[k] / h));
    // No point of class k fits at (x, y): excluded by the density or within a placed point's exclusion.
    auto point_blocked = [&](double x, double y) {
      const double r = varies ? local_radius(k, x, y) : p.classes[k].radius;
      return r <= 0.0 || !free_at(L, k, x, y, r);
    };
    // Whether a cell may still hold a point: not inside one exclusion disk and, once cells are small (from
    // level 5, a 32nd of the class cell across and less), not blocked at its corners and centre.
    auto excluded = [&](double x, double y) { return local_radius(k, x, y) <= 0.0; };
    auto open = [&](const Rect& c, int level) {
      // Where the density admits no point at the corners and the centre the cell is dropped (masks: their
      // borders are resolved to the cell size, not beyond).
      if (varies) {
        const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
        if (excluded(mx, my) && excluded(c.x0, c.y0) && excluded(c.x1, c.y0) && excluded(c.x0, c.y1) &&
            excluded(c.x1, c.y1))
          return false;
      }
      if (covered(L, k, c.x0, c.y0, c.x1, c.y1)) return false;
      if (level < 5) return true;
      const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
      return !(point_blocked(mx, my) && point_blocked(c.x0, c.y0) && point_blocked(c.x1, c.y0) &&
               point_blocked(c.x0, c.y1) && point_blocked(c.x1, c.y1));
    };
    std::vector<Rect> cells, next;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Rect c{L.ax0 + i * h, L.ay0 + j * h, std::min(L.ax0 + (i + 1) * h, L.ax1),
               std::min(L.ay0 + (j + 1) * h, L.ay1)};
        if (c.x1 > c.x0 && c.y1 > c.y0 && open(c, 0)) cells.push_back(c);
      }
    constexpr int kLevels = 8;
    for (int level = 0; level <= kLevels && !cells.empty(); ++level) {
      for (const Rect& c : cells) try_place(L, k, c.x0 + draw.next() * (c.x1 - c.x0), c.y0 + draw.next() * (c.y1 - c.y0));
      if (level == kLevels) {
        for (const Rect& c : cells) try_place(L, k, 0.5 * (c.x0 + c.x1), 0.5 * (c.y0 + c.y1));
        break;
      }
      next.clear();
      for (const Rect& c : cells) {
        if (covered(L, k, c.x0, c.y0, c.x1, c.y1)) continue;
        const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
        const Rect q[4] = {{c.x0, c.y0, mx, my}, {mx, c.y0, c.x1, my}, {c.x0, my, mx, c.y1}, {mx, my, c.x1, c.y1}};
        for (const Rect& sub : q)
          if (open(sub, level + 1)) next.push_back(sub);
      }
      std::swap(cells, next);
      // Safety: a pathological field could keep cells open at every level; stop refining then.
      if (cells.size() > 4 * (static_cast<std::size_t>(n) * n + 16)) break;
    }
  }
};

}  // namespace

double poisson_conflict_distance(const PoissonParams& p, int a, double ra, int b, double rb) {
  return a == b ? std::max(ra, rb) : p.cross_separation * 0.5 * (ra + rb);
}

double poisson_local_radius(const PoissonParams& p, int k, double x, double y) {
  Sampler s(p);
  return s.local_radius(k, x, y);
}

namespace {

// Per-class chunk sides, reaches and final margins (see poisson_disk).
void setup(Sampler& s, const PoissonParams& p) {
  const std::size_t K = p.classes.size();
  s.order.resize(K);
  std::iota(s.order.begin(), s.order.end(), 0);
  std::stable_sort(s.order.begin(), s.order.end(),
                   [&](int a, int b) { return p.classes[a].radius > p.classes[b].radius; });
  s.rank.assign(K, 0);
  for (std::size_t o = 0; o < K; ++o) s.rank[s.order[o]] = static_cast<int>(o);
  const bool varies = p.density || p.mask ||
                      std::any_of(p.classes.begin(), p.classes.end(), [](const auto& c) { return c.density; });
  s.rmax.clear();
  s.cell.clear();
  for (std::size_t k = 0; k < K; ++k) {
    const double r = p.classes[k].radius;
    s.rmax.push_back(varies ? r / std::sqrt(p.min_density) : r);
    s.cell.push_back(r / std::sqrt(2.0) * (1.0 - 1e-6));
  }
  s.varies = varies;
  s.uniform = !varies && K == 1;
  s.make_offsets();
  s.chunk.assign(K, 0.0);
  s.reach.assign(K, 0.0);
  for (std::size_t o = 0; o < K; ++o) {
    const int k = s.order[o];
    double d = s.rmax[k];
    for (std::size_t e = 0; e < o; ++e) d = std::max(d, s.conflict(k, s.rmax[k], s.order[e], s.rmax[s.order[e]]));
    s.reach[k] = d;
    s.chunk[k] = std::max(2.0 * s.rmax[k], 8.0 * p.classes[k].radius);
  }
}

// Metres around the request within which class order[o] must be final: a later class computes chunks up to
// four of its chunks beyond its own final rectangle and reads earlier classes within its reach of them.
std::vector<double> margins(const Sampler& s) {
  const std::size_t K = s.order.size();
  std::vector<double> m(K, 0.0);
  for (std::size_t o = K - 1; o-- > 0;) {
    const int next = s.order[o + 1];
    m[o] = (m[o + 1] + 4.0 * s.chunk[next] + s.reach[next]) * (1.0 + 1e-9) + 1e-9;
  }
  return m;
}

}  // namespace

PoissonLayout poisson_layout(const PoissonParams& p) {
  Sampler s(p);
  setup(s, p);
  PoissonLayout l;
  for (double r : s.reach) l.interaction = std::max(l.interaction, r);
  for (double c : s.chunk) l.chunk = std::max(l.chunk, c);
  const auto m = margins(s);
  l.halo = m.empty() ? 0.0 : m[0] + 4.0 * s.chunk[s.order[0]];
  return l;
}

Points poisson_disk(glm::dvec2 lo, glm::dvec2 hi, const PoissonParams& p, const ExecContext* ctx) {
  if (p.classes.empty()) throw std::invalid_argument("PoissonDisk: no classes");
  for (const auto& c : p.classes)
    if (!(c.radius > 0.0) || !std::isfinite(c.radius)) throw std::invalid_argument("PoissonDisk: radius must be > 0");
  if (!(p.min_density > 0.0 && p.min_density <= 1.0))
    throw std::invalid_argument("PoissonDisk: min_density must be in (0, 1]");
  if (!(p.cross_separation >= 0.0 && p.cross_separation <= 1.0))
    throw std::invalid_argument("PoissonDisk: cross_separation must be in [0, 1]");
  if (p.attempts < 1) throw std::invalid_argument("PoissonDisk: attempts must be >= 1");

  Sampler s(p);
  setup(s, p);
  const std::size_t K = p.classes.size();
  const auto margin = margins(s);

  // Requests the sampler cannot honour: float positions too coarse for the radius, or too many points.
  double rmin = INFINITY;
  for (const auto& c : p.classes) rmin = std::min(rmin, c.radius);
  const double halo = margin[0] + 5.0 * s.chunk[s.order[0]];
  const double extent = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y)}) + halo;
  if (!(extent * 0x1.0p-23 <= 0.01 * rmin))
    throw std::runtime_error("PoissonDisk: coordinates up to " + std::to_string(extent) +
                             " m are too large for float positions at radius " + std::to_string(rmin) + " m");
  double estimate = 0.0;
  for (std::size_t o = 0; o < K; ++o) {
    const int k = s.order[o];
    const double grow = 2.0 * (margin[o] + 5.0 * s.chunk[k]);
    estimate += (hi.x - lo.x + grow) * (hi.y - lo.y + grow) / (0.6 * p.classes[k].radius * p.classes[k].radius);
  }
  if (!(estimate <= static_cast<double>(p.max_points)))
    throw std::runtime_error("PoissonDisk: the request would place about " + std::to_string(estimate) +
                             " points (limit " + std::to_string(p.max_points) + "); raise the radius");

  s.grids.resize(K);
  std::vector<std::pair<std::int64_t, std::int64_t>> todo;
  for (std::size_t o = 0; o < K; ++o) {
    const int k = s.order[o];
    ClassChunks& g = s.grids[k];
    g.C = s.chunk[k];
    const double M = margin[o];
    g.core_x0 = static_cast<std::int64_t>(std::floor((lo.x - M) / g.C));
    g.core_y0 = static_cast<std::int64_t>(std::floor((lo.y - M) / g.C));
    g.core_x1 = static_cast<std::int64_t>(std::floor((hi.x + M) / g.C));
    g.core_y1 = static_cast<std::int64_t>(std::floor((hi.y + M) / g.C));
    // Three rings of phase dependencies and one of empty chunks, so neighbour lookups stay in the window.
    g.cx0 = g.core_x0 - 4;
    g.cy0 = g.core_y0 - 4;
    g.nx = static_cast<int>(g.core_x1 - g.core_x0) + 9;
    g.ny = static_cast<int>(g.core_y1 - g.core_y0) + 9;
    g.chunks.resize(static_cast<std::size_t>(g.nx) * g.ny);
    for (int phase = 0; phase < 4; ++phase) {
      const int ring = 3 - phase;
      todo.clear();
      for (auto cy = g.core_y0 - ring; cy <= g.core_y1 + ring; ++cy)
        for (auto cx = g.core_x0 - ring; cx <= g.core_x1 + ring; ++cx)
          if (static_cast<int>((cx & 1) + 2 * (cy & 1)) == phase) todo.emplace_back(cx, cy);
      const double step = static_cast<double>(o * 4 + phase);
      for_each_row(ctx, static_cast<int>(todo.size()), [&](int t) {
                     if (s.uniform)
                       s.process_uniform(todo[t].first, todo[t].second, k);
                     else
                       s.process(todo[t].first, todo[t].second, k);
                   },
                   step / (4.0 * K), (step + 1.0) / (4.0 * K));
    }
  }

  // Output: the points inside [lo, hi], class by class (largest first), chunk rows first. Counted per chunk,
  // then written in parallel at the prefix offsets (the yaw costs a hash, a sine and a cosine per point).
  Points out;
  auto& radius = out.attribute("radius");
  for (int k : s.order) {
    const ClassChunks& g = s.grids[k];
    const auto i0 = static_cast<std::int64_t>(std::floor(lo.x / g.C)), i1 = static_cast<std::int64_t>(std::floor(hi.x / g.C));
    const auto j0 = static_cast<std::int64_t>(std::floor(lo.y / g.C)), j1 = static_cast<std::int64_t>(std::floor(hi.y / g.C));
    const int w = static_cast<int>(i1 - i0 + 1), rows = static_cast<int>(j1 - j0 + 1);
    auto keep = [&](const Pt& q) {
      const double x = q.x, y = q.y;
      return !(x < lo.x || x > hi.x || y < lo.y || y > hi.y);
    };
    std::vector<std::size_t> offset(static_cast<std::size_t>(rows) + 1, 0);
    for_each_row(nullptr, rows, [&](int r) {
      std::size_t c = 0;
      for (int i = 0; i < w; ++i)
        for (const Pt& q : g.at(i0 + i, j0 + r)) c += keep(q);
      offset[r + 1] = c;
    });
    const std::size_t base = out.position.size();
    for (int r = 0; r < rows; ++r) offset[r + 1] += offset[r];
    const std::size_t total = base + offset[rows];
    out.position.resize(total);
    out.rotation.resize(total);
    out.scale.resize(total, glm::vec3(1.0f));
    out.class_id.resize(total);
    radius.resize(total);
    for_each_row(nullptr, rows, [&](int r) {
      std::size_t o = base + offset[r];
      for (int i = 0; i < w; ++i)
        for (const Pt& q : g.at(i0 + i, j0 + r)) {
          if (!keep(q)) continue;
          out.position[o] = glm::vec3(q.x, q.y, 0.0f);
          const double yaw =
              2.0 * kPi * scatter::unit(scatter::hash(p.seed, 0x7A3ull, scatter::bits(q.x), scatter::bits(q.y)));
          out.rotation[o] = glm::angleAxis(static_cast<float>(yaw), glm::vec3(0.0f, 0.0f, 1.0f));
          out.class_id[o] = p.classes[q.cls].class_id;
          radius[o] = q.r;
          ++o;
        }
    });
  }
  return out;
}

}  // namespace orogen
