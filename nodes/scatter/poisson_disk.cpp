#include "nodes/scatter/poisson_disk.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "nodes/field/row_loop.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pt {
  float x, y;  // the output position
  float r;     // local radius
  int cls;     // class index into PoissonParams::classes
};

double field_value(const Heightfield* f, double x, double y) {
  if (!f) return 1.0;
  const double v = f->sample_world(x, y);
  if (!(v > 0.0)) return 0.0;  // NaN too
  return std::min(v, 1.0);
}

struct Sampler {
  const PoissonParams& p;
  PoissonLayout layout;
  std::vector<int> order;       // class indices, largest radius first
  std::vector<double> rmax;     // per class: largest local radius
  std::vector<double> cell;     // per class: background grid cell (r / sqrt 2, slightly less)
  std::int64_t cx0 = 0, cy0 = 0;  // chunk index of the stored array's (0, 0)
  int nx = 0, ny = 0;
  int core_x0 = 0, core_y0 = 0, core_x1 = 0, core_y1 = 0;  // core chunks (array indices, inclusive)
  std::vector<std::vector<Pt>> chunks;

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

  std::vector<Pt>& chunk_at(int ix, int iy) { return chunks[static_cast<std::size_t>(iy) * nx + ix]; }

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

  // True if a point of class k with radius rk at (x, y) conflicts with none placed so far.
  bool free_at(const Local& L, int k, double x, double y, double rk) const {
    for (int j : order) {
      const auto& g = L.grids[j];
      if (g.n == 0) continue;
      const double reach = conflict(k, rk, j, rmax[j]);
      if (reach <= 0.0) continue;
      const int w = static_cast<int>(std::ceil(reach / g.h));
      const int ci = static_cast<int>(std::floor((x - L.gx0) / g.h));
      const int cj = static_cast<int>(std::floor((y - L.gy0) / g.h));
      const int i0 = std::max(ci - w, 0), i1 = std::min(ci + w, g.n - 1);
      const int j0 = std::max(cj - w, 0), j1 = std::min(cj + w, g.n - 1);
      for (int jj = j0; jj <= j1; ++jj) {
        const int* row = g.cells.data() + static_cast<std::size_t>(jj) * g.n;
        for (int ii = i0; ii <= i1; ++ii) {
          const int q = row[ii];
          if (q < 0) continue;
          const double dx = L.x[q] - x, dy = L.y[q] - y;
          const double c = conflict(k, rk, j, L.r[q]);
          if (dx * dx + dy * dy < c * c) return false;
        }
      }
    }
    return true;
  }

  // True if every point of the rectangle is within the exclusion of one placed point (no point of class k,
  // whatever its radius, can go there).
  bool covered(const Local& L, int k, double x0, double y0, double x1, double y1) const {
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double half_diag = 0.5 * std::hypot(x1 - x0, y1 - y0);
    // A lower bound of the radius a class-k point would have in the rectangle: the smallest at its corners and
    // centre (the class radius where none of them admits a point).
    double r0 = INFINITY;
    for (const auto& [px, py] : {std::pair{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}, {cx, cy}}) {
      const double r = local_radius(k, px, py);
      if (r > 0.0) r0 = std::min(r0, r);
    }
    if (!std::isfinite(r0)) r0 = p.classes[k].radius;
    for (int j : order) {
      const auto& g = L.grids[j];
      if (g.n == 0) continue;
      const double reach = conflict(k, r0, j, rmax[j]);
      if (reach <= 0.0) continue;
      const int w = static_cast<int>(std::ceil((reach + half_diag) / g.h));
      const int ci = static_cast<int>(std::floor((cx - L.gx0) / g.h));
      const int cj = static_cast<int>(std::floor((cy - L.gy0) / g.h));
      const int i0 = std::max(ci - w, 0), i1 = std::min(ci + w, g.n - 1);
      const int j0 = std::max(cj - w, 0), j1 = std::min(cj + w, g.n - 1);
      for (int jj = j0; jj <= j1; ++jj)
        for (int ii = i0; ii <= i1; ++ii) {
          const int q = g.cells[static_cast<std::size_t>(jj) * g.n + ii];
          if (q < 0) continue;
          const double c = conflict(k, r0, j, L.r[q]);  // the smallest exclusion a class-k point sees
          const double c2 = c * c;
          auto in = [&](double px, double py) {
            const double dx = L.x[q] - px, dy = L.y[q] - py;
            return dx * dx + dy * dy < c2;
          };
          if (in(x0, y0) && in(x1, y0) && in(x0, y1) && in(x1, y1)) return true;
        }
    }
    return false;
  }

  // Tries to place a class-k point at (x, y) (double); returns its local index or -1.
  int try_place(Local& L, int k, double x, double y) const {
    const float fx = static_cast<float>(x), fy = static_cast<float>(y);
    const double dx = fx, dy = fy;
    if (!(dx >= L.ax0 && dx < L.ax1 && dy >= L.ay0 && dy < L.ay1)) return -1;
    const double rk = local_radius(k, dx, dy);
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

  void process(int ix, int iy, int k) {
    const std::int64_t gcx = cx0 + ix, gcy = cy0 + iy;
    const double C = layout.chunk, D = layout.interaction;
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
    // Gather the neighbours' points within the interaction distance of the chunk.
    std::vector<int> active;
    const double seed_reach = 2.0 * rmax[k];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto& src = chunk_at(ix + dx, iy + dy);
        for (const Pt& q : src) {
          const double qx = q.x, qy = q.y;
          if (qx < L.ax0 - D || qx >= L.ax1 + D || qy < L.ay0 - D || qy >= L.ay1 + D) continue;
          const int idx = static_cast<int>(L.x.size());
          L.x.push_back(qx);
          L.y.push_back(qy);
          L.r.push_back(q.r);
          L.cls.push_back(q.cls);
          grid_insert(L, idx);
          if (q.cls == k && qx >= L.ax0 - seed_reach && qx < L.ax1 + seed_reach && qy >= L.ay0 - seed_reach &&
              qy < L.ay1 + seed_reach)
            active.push_back(idx);
        }
      }
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
        const double theta = 2.0 * kPi * draw.next();
        const double rho = ra * std::sqrt(1.0 + 3.0 * draw.next());  // uniform in the annulus [r, 2r]
        const int idx = try_place(L, k, L.x[a] + rho * std::cos(theta), L.y[a] + rho * std::sin(theta));
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
    auto& dst = chunk_at(ix, iy);
    for (int idx : L.own) dst.push_back({static_cast<float>(L.x[idx]), static_cast<float>(L.y[idx]), L.r[idx], k});
  }

  // Ebeida et al. (2011): darts into the cells not yet covered by an exclusion disk, then into their quarters.
  void fill(Local& L, int k, scatter::Draws& draw) const {
    struct Rect {
      double x0, y0, x1, y1;
    };
    const double h = cell[k];
    const int n = static_cast<int>(std::ceil(layout.chunk / h));
    std::vector<Rect> cells, next;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Rect c{L.ax0 + i * h, L.ay0 + j * h, std::min(L.ax0 + (i + 1) * h, L.ax1),
               std::min(L.ay0 + (j + 1) * h, L.ay1)};
        if (c.x1 > c.x0 && c.y1 > c.y0 && !covered(L, k, c.x0, c.y0, c.x1, c.y1)) cells.push_back(c);
      }
    constexpr int kLevels = 10;
    for (int level = 0; level <= kLevels && !cells.empty(); ++level) {
      for (const Rect& c : cells) try_place(L, k, c.x0 + draw.next() * (c.x1 - c.x0), c.y0 + draw.next() * (c.y1 - c.y0));
      if (level == kLevels) {
        for (const Rect& c : cells)
          if (!covered(L, k, c.x0, c.y0, c.x1, c.y1)) try_place(L, k, 0.5 * (c.x0 + c.x1), 0.5 * (c.y0 + c.y1));
        break;
      }
      next.clear();
      for (const Rect& c : cells) {
        if (covered(L, k, c.x0, c.y0, c.x1, c.y1)) continue;
        // Cells where the density excludes every probe are dropped after a few levels (mask borders).
        if (level >= 3) {
          const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
          if (local_radius(k, c.x0, c.y0) <= 0 && local_radius(k, c.x1, c.y0) <= 0 &&
              local_radius(k, c.x0, c.y1) <= 0 && local_radius(k, c.x1, c.y1) <= 0 && local_radius(k, mx, my) <= 0)
            continue;
        }
        const double mx = 0.5 * (c.x0 + c.x1), my = 0.5 * (c.y0 + c.y1);
        const Rect q[4] = {{c.x0, c.y0, mx, my}, {mx, c.y0, c.x1, my}, {c.x0, my, mx, c.y1}, {mx, my, c.x1, c.y1}};
        for (const Rect& s : q)
          if (!covered(L, k, s.x0, s.y0, s.x1, s.y1)) next.push_back(s);
      }
      std::swap(cells, next);
      // Safety: a pathological field could keep cells uncovered at every level; stop refining then.
      if (cells.size() > 16 * (static_cast<std::size_t>(n) * n + 64)) break;
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

PoissonLayout poisson_layout(const PoissonParams& p) {
  PoissonLayout l;
  const bool varies = p.density || p.mask ||
                      std::any_of(p.classes.begin(), p.classes.end(), [](const auto& c) { return c.density; });
  double rmin = INFINITY;
  for (const auto& c : p.classes) {
    const bool v = varies;
    const double rm = v ? c.radius / std::sqrt(p.min_density) : c.radius;
    l.interaction = std::max(l.interaction, rm);
    rmin = std::min(rmin, c.radius);
  }
  l.chunk = std::max(2.0 * l.interaction, 8.0 * rmin);
  l.halo_chunks = 4 * static_cast<int>(p.classes.size()) - 1;
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
  s.layout = poisson_layout(p);
  const std::size_t K = p.classes.size();
  s.order.resize(K);
  std::iota(s.order.begin(), s.order.end(), 0);
  std::stable_sort(s.order.begin(), s.order.end(),
                   [&](int a, int b) { return p.classes[a].radius > p.classes[b].radius; });
  const bool varies = p.density || p.mask ||
                      std::any_of(p.classes.begin(), p.classes.end(), [](const auto& c) { return c.density; });
  double rmin = INFINITY;
  for (std::size_t k = 0; k < K; ++k) {
    const double r = p.classes[k].radius;
    s.rmax.push_back(varies ? r / std::sqrt(p.min_density) : r);
    s.cell.push_back(r / std::sqrt(2.0) * (1.0 - 1e-6));
    rmin = std::min(rmin, r);
  }

  // Requests the sampler cannot honour: float positions too coarse for the radius, or too many points.
  const double C = s.layout.chunk, halo = s.layout.halo();
  const double extent = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y)}) + halo + C;
  if (!(extent * 0x1.0p-23 <= 0.01 * rmin))
    throw std::runtime_error("PoissonDisk: coordinates up to " + std::to_string(extent) +
                             " m are too large for float positions at radius " + std::to_string(rmin) + " m");
  const double wx = hi.x - lo.x + 2.0 * (halo + C), wy = hi.y - lo.y + 2.0 * (halo + C);
  double estimate = 0.0;
  for (const auto& c : p.classes) estimate += wx * wy / (0.6 * c.radius * c.radius);
  if (!(estimate <= static_cast<double>(p.max_points)))
    throw std::runtime_error("PoissonDisk: the request would place about " + std::to_string(estimate) +
                             " points (limit " + std::to_string(p.max_points) + "); raise the radius");

  const std::int64_t kx0 = static_cast<std::int64_t>(std::floor(lo.x / C));
  const std::int64_t ky0 = static_cast<std::int64_t>(std::floor(lo.y / C));
  const std::int64_t kx1 = static_cast<std::int64_t>(std::floor(hi.x / C));
  const std::int64_t ky1 = static_cast<std::int64_t>(std::floor(hi.y / C));
  const int H = s.layout.halo_chunks;
  // One extra ring of empty chunks around everything computed, so neighbour lookups stay in the array.
  s.cx0 = kx0 - H - 1;
  s.cy0 = ky0 - H - 1;
  s.nx = static_cast<int>(kx1 - kx0) + 2 * H + 3;
  s.ny = static_cast<int>(ky1 - ky0) + 2 * H + 3;
  s.core_x0 = H + 1;
  s.core_y0 = H + 1;
  s.core_x1 = s.core_x0 + static_cast<int>(kx1 - kx0);
  s.core_y1 = s.core_y0 + static_cast<int>(ky1 - ky0);
  s.chunks.resize(static_cast<std::size_t>(s.nx) * s.ny);

  const int steps = static_cast<int>(K) * 4;
  std::vector<std::pair<int, int>> todo;
  for (int step = 0; step < steps; ++step) {
    const int k = s.order[step / 4];
    const int phase = step % 4;
    const int ring = steps - 1 - step;
    todo.clear();
    for (int iy = s.core_y0 - ring; iy <= s.core_y1 + ring; ++iy)
      for (int ix = s.core_x0 - ring; ix <= s.core_x1 + ring; ++ix) {
        const std::int64_t gx = s.cx0 + ix, gy = s.cy0 + iy;
        if (static_cast<int>((gx & 1) + 2 * (gy & 1)) == phase) todo.emplace_back(ix, iy);
      }
    const double from = static_cast<double>(step) / steps, to = static_cast<double>(step + 1) / steps;
    for_each_row(ctx, static_cast<int>(todo.size()), [&](int t) { s.process(todo[t].first, todo[t].second, k); },
                 from, to);
  }

  // Output: the points inside [lo, hi], chunk rows first.
  Points out;
  auto& radius = out.attribute("radius");
  for (int iy = s.core_y0; iy <= s.core_y1; ++iy)
    for (int ix = s.core_x0; ix <= s.core_x1; ++ix)
      for (const Pt& q : s.chunk_at(ix, iy)) {
        const double x = q.x, y = q.y;
        if (x < lo.x || x > hi.x || y < lo.y || y > hi.y) continue;
        out.position.emplace_back(q.x, q.y, 0.0f);
        const double yaw = 2.0 * kPi * scatter::unit(scatter::hash(p.seed, 0x7A3ull, scatter::bits(q.x), scatter::bits(q.y)));
        out.rotation.push_back(glm::angleAxis(static_cast<float>(yaw), glm::vec3(0.0f, 0.0f, 1.0f)));
        out.scale.emplace_back(1.0f);
        out.class_id.push_back(p.classes[q.cls].class_id);
        radius.push_back(q.r);
      }
  return out;
}

}  // namespace orogen
