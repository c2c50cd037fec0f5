// The general Poisson-disk sampler (poisson_disk.h): several classes, radii varying with density fields and
// masks. Bridson's growth per chunk (Bridson 2007) with Ebeida et al.'s gap filling (2011) on a quadtree of
// cells.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "nodes/common/work_poll.h"
#include "nodes/scatter/poisson_plan.h"

namespace orogen::poisson {
namespace {

struct GeneralChunkSampler : PoissonPlan {
  explicit GeneralChunkSampler(const PoissonPlan& plan) : PoissonPlan(plan) {}

  // Per-chunk working state.
  struct Local {
    double ax0, ay0, ax1, ay1;  // the chunk [ax0, ax1) x [ay0, ay1)
    double gx0, gy0;            // origin of the local grids (the chunk minus the interaction distance)
    std::vector<double> x, y;   // gathered and new points (double copies of the float positions)
    std::vector<float> r;
    std::vector<int> cls;
    std::vector<int> own;  // indices of the points placed in this chunk
    struct Grid {
      double h = 0;
      int n = 0;
      std::vector<int> cells;  // point index or -1
    };
    std::vector<Grid> grids;  // per class
    // Polled per placement try: one chunk of a tiny radius among huge ones holds millions of tries.
    WorkPoll poll{nullptr, 256};
  };
  const ExecContext* ctx = nullptr;

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
      const int ci0 = static_cast<int>(std::floor((x0 - L.gx0) / g.h)),
                ci1 = static_cast<int>(std::floor((x1 - L.gx0) / g.h));
      const int cj0 = static_cast<int>(std::floor((y0 - L.gy0) / g.h)),
                cj1 = static_cast<int>(std::floor((y1 - L.gy0) / g.h));
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
    L.poll();
    const float fx = static_cast<float>(x), fy = static_cast<float>(y);
    const double dx = fx, dy = fy;
    if (!(dx >= L.ax0 && dx < L.ax1 && dy >= L.ay0 && dy < L.ay1)) return -1;
    if (p.bounded && !(dx >= p.bounds_lo.x && dx <= p.bounds_hi.x && dy >= p.bounds_lo.y && dy <= p.bounds_hi.y))
      return -1;
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
    L.poll = WorkPoll(ctx, 256);
    L.ax0 = static_cast<double>(gcx) * C;
    L.ax1 = static_cast<double>(gcx + 1) * C;
    L.ay0 = static_cast<double>(gcy) * C;
    L.ay1 = static_cast<double>(gcy + 1) * C;
    if (p.bounded &&
        !(L.ax0 <= p.bounds_hi.x && L.ax1 > p.bounds_lo.x && L.ay0 <= p.bounds_hi.y && L.ay1 > p.bounds_lo.y))
      return;  // outside the sampled rectangle
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
    scatter::Draws draw{
        scatter::hash(p.seed, 0x5CA77E5ull, static_cast<std::uint64_t>(k), scatter::bits(gcx), scatter::bits(gcy))};
    // Bridson: one initial dart into the chunk (its part inside the sampled rectangle), then grow from the
    // active points (neighbours' included).
    const double sx0 = p.bounded ? std::max(L.ax0, p.bounds_lo.x) : L.ax0;
    const double sy0 = p.bounded ? std::max(L.ay0, p.bounds_lo.y) : L.ay0;
    const double sw = p.bounded ? std::min(L.ax1, p.bounds_hi.x) - sx0 : C;
    const double sh = p.bounded ? std::min(L.ay1, p.bounds_hi.y) - sy0 : C;
    for (int t = 0; t < 4; ++t) {
      const int idx = try_place(L, k, sx0 + draw.next() * sw, sy0 + draw.next() * sh);
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
    // Whether a cell may still hold a point: not inside one exclusion disk (or two), and where the density
    // admits points. Cells that need three disks to be covered refine to the last level (a dart at each
    // remaining cell's centre ends them); once small (from level 5, a 32nd of the class cell across), a cell
    // that reaches a border of the density's support is dropped when its corners and centre are blocked, so
    // masks' borders are resolved to that size and do not double the cells at every level.
    auto excluded = [&](double x, double y) { return local_radius(k, x, y) <= 0.0; };
    auto open = [&](const Rect& c, int level) {
      const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
      bool border = false;
      if (varies) {
        const bool e[5] = {excluded(mx, my), excluded(c.x0, c.y0), excluded(c.x1, c.y0), excluded(c.x0, c.y1),
                           excluded(c.x1, c.y1)};
        if (e[0] && e[1] && e[2] && e[3] && e[4]) return false;  // no point admitted at the corners and centre
        border = e[0] || e[1] || e[2] || e[3] || e[4];
      }
      if (covered(L, k, c.x0, c.y0, c.x1, c.y1)) return false;
      if (level < 5 || !border) return true;
      return !(point_blocked(mx, my) && point_blocked(c.x0, c.y0) && point_blocked(c.x1, c.y0) &&
               point_blocked(c.x0, c.y1) && point_blocked(c.x1, c.y1));
    };
    std::vector<Rect> cells, next;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Rect c{L.ax0 + i * h, L.ay0 + j * h, std::min(L.ax0 + (i + 1) * h, L.ax1),
               std::min(L.ay0 + (j + 1) * h, L.ay1)};
        if (p.bounded) {  // clipped to the sampled rectangle, whose edges are filled too
          c = {std::max(c.x0, p.bounds_lo.x), std::max(c.y0, p.bounds_lo.y), std::min(c.x1, p.bounds_hi.x),
               std::min(c.y1, p.bounds_hi.y)};
          if (c.x1 >= c.x0 && c.y1 >= c.y0 && open(c, 0)) cells.push_back(c);
          continue;
        }
        if (c.x1 > c.x0 && c.y1 > c.y0 && open(c, 0)) cells.push_back(c);
      }
    constexpr int kLevels = 10;  // down to a 1024th of the class cell
    for (int level = 0; level <= kLevels && !cells.empty(); ++level) {
      for (const Rect& c : cells)
        try_place(L, k, c.x0 + draw.next() * (c.x1 - c.x0), c.y0 + draw.next() * (c.y1 - c.y0));
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

std::vector<ClassChunks> sample_general(const PoissonPlan& plan, glm::dvec2 lo, glm::dvec2 hi,
                                        const std::vector<double>& margin, const ExecContext* ctx) {
  GeneralChunkSampler s(plan);
  s.ctx = ctx;
  run_chunk_phases(s, lo, hi, margin, ctx, [&](std::int64_t cx, std::int64_t cy, int k) { s.process(cx, cy, k); });
  return std::move(s.grids);
}

}  // namespace orogen::poisson
