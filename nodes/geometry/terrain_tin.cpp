#include "nodes/geometry/terrain_tin.h"

#include "nodes/geometry/tin_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

namespace orogen {
namespace {

using i64 = std::int64_t;

// Twice the signed area of (a, b, p) on the grid: positive when counter-clockwise (y = j up). Exact.
inline i64 orient(int ax, int ay, int bx, int by, int px, int py) {
  return static_cast<i64>(bx - ax) * (py - ay) - static_cast<i64>(by - ay) * (px - ax);
}

// Whether d lies strictly inside the circumcircle of the counter-clockwise triangle (a, b, c). Exact.
inline bool in_circle(int ax, int ay, int bx, int by, int cx, int cy, int dx, int dy) {
  const i64 adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy, cdx = cx - dx, cdy = cy - dy;
  using i128 = __int128;
  const i128 det = i128(adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                   i128(bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                   i128(cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
  return det > 0;
}

inline i64 floor_div(i64 n, i64 d) {
  const i64 q = n / d;
  return (n % d != 0 && ((n < 0) != (d < 0))) ? q - 1 : q;
}
inline i64 ceil_div(i64 n, i64 d) { return -floor_div(-n, d); }

struct Scan {
  double error = 0.0;        // largest vertical distance of a sample under the triangle
  std::int32_t sample = -1;  // where (-1 if the triangle holds no sample, which cannot happen)
};

// The samples of the grid inside the counter-clockwise grid triangle (a, b, c), edges included, row by row,
// and their largest vertical distance to the triangle's plane. With kStopAbove, stops as soon as a row
// exceeds `limit` (then error > limit, sample undefined).
class Scanner {
 public:
  // With `single`, scan() runs the SIMD single-precision scan (tin_scan.h), whose errors are within
  // float_margin() of the exact ones; otherwise the double-precision scalar scan below.
  Scanner(int width, const float* z, std::size_t size, bool single)
      : width_(width), z_(z), size_(size), single_(single) {}

  template <bool kStopAbove>
  Scan scan(int ax, int ay, int bx, int by, int cx, int cy, double limit = 0.0) const {
    if (!single_) return scan_exact<kStopAbove>(ax, ay, bx, by, cx, cy, limit);
    tin::ScanRequest r;
    r.z = z_;
    r.size = size_;
    r.width = width_;
    r.ax = ax, r.ay = ay, r.bx = bx, r.by = by, r.cx = cx, r.cy = cy;
    r.stop_above = kStopAbove;
    r.limit = static_cast<float>(limit);
    const tin::ScanResult s = tin::scan_triangle(r);
    return {static_cast<double>(s.error), s.sample};
  }

  float height(int x, int y) const { return z_[static_cast<std::size_t>(y) * width_ + x]; }

  // The vertical distance of sample (px, py), height zp, to the plane of grid triangle (a, b, c) with heights
  // za, zb, zc, as scan() computes it.
  static double point_error(int ax, int ay, double za, int bx, int by, double zb, int cx, int cy, double zc, int px,
                            int py, double zp) {
    const double det = static_cast<double>(orient(ax, ay, bx, by, cx, cy));
    const double ux = bx - ax, uy = by - ay, vx = cx - ax, vy = cy - ay, uz = zb - za, vz = zc - za;
    const double gx = (uz * vy - vz * uy) / det, gy = (ux * vz - vx * uz) / det;
    const double base = za - gx * ax + gy * (py - ay);
    return std::abs(zp - (base + gx * static_cast<double>(px)));
  }

  template <bool kStopAbove>
  Scan scan_exact(int ax, int ay, int bx, int by, int cx, int cy, double limit = 0.0) const {
    const double za = z_[ay * width_ + ax], zb = z_[by * width_ + bx], zc = z_[cy * width_ + cx];
    const double det = static_cast<double>(orient(ax, ay, bx, by, cx, cy));
    const double ux = bx - ax, uy = by - ay, vx = cx - ax, vy = cy - ay, uz = zb - za, vz = zc - za;
    const double gx = (uz * vy - vz * uy) / det, gy = (ux * vz - vx * uz) / det;
    const int ymin = std::min({ay, by, cy}), ymax = std::max({ay, by, cy});
    const int xmin = std::min({ax, bx, cx}), xmax = std::max({ax, bx, cx});
    // Each non-horizontal edge bounds the rows on one side: x <= px + floor(dx (y - py) / dy) for dy > 0, x >=
    // px + ceil(dx (y - py) / dy) for dy < 0. The quotients are stepped exactly from row to row (quotient q
    // and remainder r of n / d with d > 0), without a division per row.
    struct Walk {
      i64 q, r, d, step_q, step_r;
      int px;
      bool right;
    } walks[3];
    int n_walks = 0;
    const int ex[3] = {ax, bx, cx}, ey[3] = {ay, by, cy};
    for (int k = 0; k < 3; ++k) {
      const int px = ex[k], py = ey[k];
      const i64 dy = ey[(k + 1) % 3] - py, dx = ex[(k + 1) % 3] - px;
      if (dy == 0) continue;
      Walk& w = walks[n_walks++];
      w.right = dy > 0;
      w.d = dy > 0 ? dy : -dy;
      const i64 s = dy > 0 ? dx : -dx;  // n grows by s per row
      const i64 n = s * (ymin - py);
      w.q = floor_div(n, w.d);
      w.r = n - w.q * w.d;
      w.step_q = floor_div(s, w.d);
      w.step_r = s - w.step_q * w.d;
      w.px = px;
    }
    Scan best;
    best.error = -1.0;
    for (int y = ymin; y <= ymax; ++y) {
      i64 xl = xmin, xr = xmax;
      for (int k = 0; k < n_walks; ++k) {
        Walk& w = walks[k];
        if (w.right)
          xr = std::min(xr, w.px + w.q);
        else
          xl = std::max(xl, w.px + w.q + (w.r != 0 ? 1 : 0));
        w.q += w.step_q;
        w.r += w.step_r;
        if (w.r >= w.d) {
          ++w.q;
          w.r -= w.d;
        }
      }
      if (xl > xr) continue;
      const float* row = z_ + static_cast<std::ptrdiff_t>(y) * width_;
      const double base = za - gx * ax + gy * (y - ay);
      double m = 0.0;
      for (i64 x = xl; x <= xr; ++x) {
        const double e = std::abs(static_cast<double>(row[x]) - (base + gx * static_cast<double>(x)));
        m = e > m ? e : m;
      }
      if (m > best.error) {
        best.error = m;
        if constexpr (kStopAbove) {
          if (m > limit) return best;
        } else {
          for (i64 x = xl; x <= xr; ++x)
            if (std::abs(static_cast<double>(row[x]) - (base + gx * static_cast<double>(x))) == m) {
              best.sample = static_cast<std::int32_t>(static_cast<i64>(y) * width_ + x);
              break;
            }
        }
      }
    }
    return best;
  }

 private:
  int width_;
  const float* z_;
  std::size_t size_;
  bool single_;
};

inline int next_edge(int e) { return e % 3 == 2 ? e - 2 : e + 1; }
inline int prev_edge(int e) { return e % 3 == 0 ? e + 2 : e - 1; }

// Stage 1: greedy insertion into a Delaunay triangulation. Triangles are stored as three vertices and three
// half-edges; half-edge 3t + k runs from vertex k to vertex k + 1 of triangle t, and twin_[h] is the
// opposite half-edge in the neighbouring triangle (-1 on the border of the rectangle).
class GreedyInsertion {
 public:
  GreedyInsertion(const Heightfield& h, const Scanner& scanner)
      : width_(h.width()), height_(h.height()), scanner_(scanner) {}

  void run(double bound, std::size_t target, double tiny, const TinOptions& options, double progress_share) {
    // A triangle within this error is never refined: it need not enter the queue.
    keep_above_ = target > 0 ? tiny : bound;  // (bound >= tiny)
    const int w = width_ - 1, hh = height_ - 1;
    add_vertex(0, 0);
    add_vertex(w, 0);
    add_vertex(w, hh);
    add_vertex(0, hh);
    const int t0 = new_triangle(), t1 = new_triangle();
    set_triangle(t0, 0, 1, 2);
    set_triangle(t1, 0, 2, 3);
    link(3 * t0 + 2, 3 * t1 + 0);
    faces_ = 2;
    touched_ = {t0, t1};
    rescan();
    double first_error = -1.0;
    std::size_t steps = 0;
    while (!queue_.empty()) {
      const Entry top = queue_.top();
      if (top.version != version_[top.triangle]) {
        queue_.pop();
        continue;
      }
      if (first_error < 0.0) first_error = top.error;
      const bool refine = top.error > bound || (target > 0 && faces_ + 2 <= target && top.error > tiny);
      if (!refine) break;
      queue_.pop();
      insert(top.triangle);
      rescan();
      if ((++steps & 1023) == 0) {
        if (options.should_stop && options.should_stop()) return;
        if (options.progress && first_error > bound && bound > 0.0 && top.error > 0.0)
          options.progress(progress_share *
                           std::clamp(std::log(first_error / top.error) / std::log(first_error / bound), 0.0, 1.0));
      }
    }
  }

  std::vector<int> vx_, vy_;          // vertex grid coordinates
  std::vector<std::int32_t> corner_;  // 3 vertices per triangle
  std::vector<float> error_;          // per triangle: its largest error, as the scan found it
  std::vector<std::int32_t> twin_;    // 3 half-edges per triangle
  std::size_t faces_ = 0;

 private:
  struct Entry {
    double error;
    std::int32_t triangle;
    std::uint32_t version;
    bool operator<(const Entry& o) const {
      return error != o.error ? error < o.error : triangle > o.triangle;  // max-heap, ties: lowest index
    }
  };

  int add_vertex(int x, int y) {
    vx_.push_back(x);
    vy_.push_back(y);
    return static_cast<int>(vx_.size()) - 1;
  }
  int new_triangle() {
    const int t = static_cast<int>(corner_.size() / 3);
    corner_.insert(corner_.end(), 3, -1);
    twin_.insert(twin_.end(), 3, -1);
    candidate_.push_back(-1);
    error_.push_back(0.0f);
    version_.push_back(0);
    stamp_.push_back(0);
    return t;
  }
  void set_triangle(int t, int a, int b, int c) {
    corner_[3 * t] = a;
    corner_[3 * t + 1] = b;
    corner_[3 * t + 2] = c;
    twin_[3 * t] = twin_[3 * t + 1] = twin_[3 * t + 2] = -1;
    touch(t);
  }
  void link(int a, int b) {
    twin_[a] = b;
    if (b >= 0) twin_[b] = a;
  }
  void touch(int t) {
    if (stamp_[t] != round_) {
      stamp_[t] = round_;
      touched_.push_back(t);
    }
  }

  void rescan() {
    for (int t : touched_) {
      const int a = corner_[3 * t], b = corner_[3 * t + 1], c = corner_[3 * t + 2];
      const Scan s = scanner_.scan<false>(vx_[a], vy_[a], vx_[b], vy_[b], vx_[c], vy_[c]);
      candidate_[t] = s.sample;
      error_[t] = static_cast<float>(s.error);
      ++version_[t];
      if (s.error > keep_above_) queue_.push({s.error, t, version_[t]});
    }
    touched_.clear();
    ++round_;
  }

  void insert(int t) {
    const int s = candidate_[t];
    const int px = s % width_, py = s / width_;
    const int p = add_vertex(px, py);
    const int a = corner_[3 * t], b = corner_[3 * t + 1], c = corner_[3 * t + 2];
    const int on_edge = orient(vx_[a], vy_[a], vx_[b], vy_[b], px, py) == 0   ? 0
                        : orient(vx_[b], vy_[b], vx_[c], vy_[c], px, py) == 0 ? 1
                        : orient(vx_[c], vy_[c], vx_[a], vy_[a], px, py) == 0 ? 2
                                                                              : -1;
    if (on_edge < 0) {
      const int o0 = twin_[3 * t], o1 = twin_[3 * t + 1], o2 = twin_[3 * t + 2];
      const int t1 = new_triangle(), t2 = new_triangle();
      set_triangle(t, a, b, p);
      set_triangle(t1, b, c, p);
      set_triangle(t2, c, a, p);
      link(3 * t, o0);
      link(3 * t + 1, 3 * t1 + 2);
      link(3 * t + 2, 3 * t2 + 1);
      link(3 * t1, o1);
      link(3 * t1 + 1, 3 * t2 + 2);
      link(3 * t2, o2);
      faces_ += 2;
      legalize(3 * t);
      legalize(3 * t1);
      legalize(3 * t2);
      return;
    }
    // p splits edge e = A -> B of t (third vertex C) and, if it is not on the border, the twin B -> A of
    // triangle u (third vertex D).
    const int e = 3 * t + on_edge;
    const int A = corner_[e], B = corner_[next_edge(e)], C = corner_[prev_edge(e)];
    const int h_bc = twin_[next_edge(e)], h_ca = twin_[prev_edge(e)];
    const int opp = twin_[e];
    const int t1 = new_triangle();
    set_triangle(t, C, A, p);
    set_triangle(t1, C, p, B);
    link(3 * t, h_ca);
    link(3 * t + 2, 3 * t1);
    link(3 * t1 + 2, h_bc);
    if (opp < 0) {
      faces_ += 1;
      legalize(3 * t);
      legalize(3 * t1 + 2);
      return;
    }
    const int u = opp / 3;
    const int D = corner_[prev_edge(opp)];
    const int h_ad = twin_[next_edge(opp)], h_db = twin_[prev_edge(opp)];
    const int t3 = new_triangle();
    set_triangle(u, D, B, p);
    set_triangle(t3, D, p, A);
    link(3 * u, h_db);
    link(3 * u + 1, 3 * t1 + 1);
    link(3 * u + 2, 3 * t3);
    link(3 * t3 + 1, 3 * t + 1);
    link(3 * t3 + 2, h_ad);
    faces_ += 2;
    legalize(3 * t);
    legalize(3 * t1 + 2);
    legalize(3 * u);
    legalize(3 * t3 + 2);
  }

  // Lawson flips from half-edge e, whose triangle's third vertex is the new point.
  void legalize(int e0) {
    stack_.push_back(e0);
    while (!stack_.empty()) {
      const int e = stack_.back();
      stack_.pop_back();
      const int opp = twin_[e];
      if (opp < 0) continue;
      const int ep = next_edge(e), em = prev_edge(e), on = next_edge(opp), om = prev_edge(opp);
      const int A = corner_[e], B = corner_[ep], P = corner_[em], D = corner_[om];
      if (!in_circle(vx_[A], vy_[A], vx_[B], vy_[B], vx_[P], vy_[P], vx_[D], vy_[D])) continue;
      const int h_em = twin_[em], h_ep = twin_[ep], h_on = twin_[on], h_om = twin_[om];
      const int t = e / 3, u = opp / 3;
      set_triangle(t, D, B, P);
      set_triangle(u, P, A, D);
      link(3 * t, h_om);
      link(3 * t + 1, h_ep);
      link(3 * t + 2, 3 * u + 2);
      link(3 * u, h_em);
      link(3 * u + 1, h_on);
      stack_.push_back(3 * t);
      stack_.push_back(3 * u + 1);
    }
  }

  int width_, height_;
  const Scanner& scanner_;
  std::vector<std::int32_t> candidate_;
  double keep_above_ = 0.0;
  std::vector<std::uint32_t> version_, stamp_;
  std::uint32_t round_ = 1;
  std::vector<int> touched_, stack_;
  std::priority_queue<Entry> queue_;
};

// Stage 2: half-edge collapses (vertex v merged into a neighbour u) in order of the error they leave, each
// checked exactly against the bound over the samples of the changed triangles.
class Collapser {
 public:
  // Vertices and triangles are renumbered along a Z-order curve of the grid: greedy insertion numbers them
  // in insertion order, scattered over the map, and an evaluation touches a vertex's whole neighbourhood,
  // which then sits in a few cache lines instead of dozens.
  Collapser(int width, int height, const Scanner& scanner, const std::vector<int>& vx, const std::vector<int>& vy,
            const std::vector<std::int32_t>& corners, const std::vector<float>& errors)
      : width_(width), height_(height), scanner_(scanner) {
    const std::size_t nv = vx.size(), nt = corners.size() / 3;
    std::vector<std::uint64_t> key(nv);
    for (std::size_t v = 0; v < nv; ++v) key[v] = (z_order(vx[v], vy[v]) << 32) | v;
    std::sort(key.begin(), key.end());
    std::vector<std::int32_t> renumber(nv);
    vx_.resize(nv);
    vy_.resize(nv);
    vz_.resize(nv);
    for (std::size_t k = 0; k < nv; ++k) {
      const std::size_t v = key[k] & 0xffffffffu;
      renumber[v] = static_cast<std::int32_t>(k);
      vx_[k] = vx[v];
      vy_[k] = vy[v];
      vz_[k] = scanner.height(vx[v], vy[v]);
    }
    std::vector<std::array<std::int32_t, 3>> tris(nt);
    for (std::size_t t = 0; t < nt; ++t)
      tris[t] = {renumber[corners[3 * t]], renumber[corners[3 * t + 1]], renumber[corners[3 * t + 2]]};
    // Triangles in the order of their lowest vertex (then their old index), so a star is a few cache lines.
    std::vector<std::uint64_t> order(nt);
    for (std::size_t t = 0; t < nt; ++t)
      order[t] = (static_cast<std::uint64_t>(std::min({tris[t][0], tris[t][1], tris[t][2]})) << 32) | t;
    std::sort(order.begin(), order.end());
    tris_.resize(nt);
    error_.resize(nt);
    for (std::size_t k = 0; k < nt; ++k) {
      tris_[k] = tris[order[k] & 0xffffffffu];
      error_[k] = errors[order[k] & 0xffffffffu];
    }
    alive_tri_.assign(nt, 1);
    star_.resize(nv);
    for (std::size_t t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) star_[static_cast<std::size_t>(tris_[t][k])].push_back(static_cast<int>(t));
    alive_vertex_.assign(vx_.size(), 1);
    version_.assign(vx_.size(), 0);
    mark_.assign(vx_.size(), 0);
    seen_.assign(vx_.size(), 0);
    into_.assign(vx_.size(), -1);
    errors_at_.assign(vx_.size(), 0);
  }

  void run(double bound, std::size_t target, const TinOptions& options) {
    bound_ = bound;
    std::size_t faces = tris_.size();
    // Lazily re-evaluated priorities: a collapse marks the vertices around it dirty instead of re-evaluating
    // them at once; a dirty vertex is re-evaluated when its (now approximate) entry comes out of the queue,
    // and dirty vertices without an entry (no legal collapse before) are swept once the queue runs dry. Most
    // vertices are disturbed several times before their turn, so this evaluates each about twice instead of
    // after every change around it, for almost the same order.
    dirty_.assign(vx_.size(), 0);
    for (int v = static_cast<int>(vx_.size()) - 1; v >= 0; --v) evaluate(v);
    std::size_t steps = 0;
    for (;;) {
      while (!queue_.empty()) {
        const Entry top = queue_.top();
        queue_.pop();
        if (top.version != version_[top.vertex] || !alive_vertex_[top.vertex]) continue;
        if (dirty_[top.vertex]) {
          evaluate(top.vertex);
          continue;
        }
        const std::size_t removed = boundary(top.vertex) ? 1 : 2;
        if (target > 0 && faces - removed < target) return;
        collapse(top.vertex, top.into);
        faces -= removed;
        if ((++steps & 1023) == 0) {
          if (options.should_stop && options.should_stop()) return;
          // Greedy insertion leaves about a third of its vertices removable: an estimate, capped below 1.
          if (options.progress)
            options.progress(
                0.6 + 0.35 * std::min(1.0, static_cast<double>(steps) / (0.35 * static_cast<double>(vx_.size()))));
        }
      }
      bool any = false;
      for (int v = static_cast<int>(vx_.size()) - 1; v >= 0; --v)
        if (alive_vertex_[v] && dirty_[v]) {
          evaluate(v);
          any = true;
        }
      if (!any) return;
    }
  }

  // The TIN, and each triangle's largest error as the scans found it.
  Tin result(Tin tin, std::vector<float>& errors) const {
    std::vector<std::int32_t> remap(vx_.size(), -1);
    tin.samples.clear();
    for (std::size_t v = 0; v < vx_.size(); ++v)
      if (alive_vertex_[v]) {
        remap[v] = static_cast<std::int32_t>(tin.samples.size());
        tin.samples.push_back(vy_[v] * width_ + vx_[v]);
      }
    tin.triangles.clear();
    errors.clear();
    for (std::size_t t = 0; t < tris_.size(); ++t)
      if (alive_tri_[t]) {
        tin.triangles.push_back({remap[tris_[t][0]], remap[tris_[t][1]], remap[tris_[t][2]]});
        errors.push_back(error_[t]);
      }
    return tin;
  }

 private:
  struct Entry {
    double error;
    std::int32_t vertex, into;
    std::uint32_t version;
    bool operator<(const Entry& o) const {
      return error != o.error ? error > o.error : vertex > o.vertex;  // min-heap, ties: lowest index
    }
  };

  // The grid position's index along a Z-order (Morton) curve: the bits of x and y interleaved (the low 16
  // bits of each: wider grids only lose some locality).
  static std::uint64_t z_order(int x, int y) {
    auto spread = [](std::uint64_t a) {
      a &= 0xffffu;
      a = (a | (a << 8)) & 0x00ff00ffu;
      a = (a | (a << 4)) & 0x0f0f0f0fu;
      a = (a | (a << 2)) & 0x33333333u;
      return (a | (a << 1)) & 0x55555555u;
    };
    return spread(static_cast<std::uint64_t>(x)) | (spread(static_cast<std::uint64_t>(y)) << 1);
  }

  // Bit mask of the rectangle's sides the vertex lies on (1 left, 2 right, 4 bottom, 8 top).
  int sides(int v) const {
    return (vx_[v] == 0 ? 1 : 0) | (vx_[v] == width_ - 1 ? 2 : 0) | (vy_[v] == 0 ? 4 : 0) |
           (vy_[v] == height_ - 1 ? 8 : 0);
  }
  bool boundary(int v) const { return sides(v) != 0; }

  // v's star as wedges: triangle (v, a, b), counter-clockwise; and its neighbours: every a, plus the b that
  // follows no a (the last of an open fan on the border).
  void gather_star(int v) {
    wedges_.clear();
    for (int t : star_[v]) {
      const auto& c = tris_[t];
      const int k = c[0] == v ? 0 : c[1] == v ? 1 : 2;
      wedges_.push_back({c[k == 2 ? 0 : k + 1], c[k == 0 ? 2 : k - 1]});
    }
    nv_.clear();
    for (const Wedge& w : wedges_) nv_.push_back(w.a);
    for (const Wedge& w : wedges_)
      if (std::none_of(wedges_.begin(), wedges_.end(), [&](const Wedge& o) { return o.a == w.b; })) nv_.push_back(w.b);
  }

  // The best collapse of v (the neighbour leaving the smallest error within the bound), queued; none if no
  // collapse is legal. Collapsing v into u turns each wedge (v, a, b) without u into the triangle (u, a, b).
  void evaluate(int v) {
    ++version_[v];
    dirty_[v] = 0;
    into_[v] = -1;
    const int sv = sides(v);
    if (sv != 0 && (sv & (sv - 1)) != 0) return;  // a corner stays
    gather_star(v);
    ++generation_;
    for (int w : nv_) mark_[w] = generation_;
    const int px = vx_[v], py = vy_[v];
    double best = bound_;
    int best_u = -1;
    for (int u : nv_) {
      if (sv != 0 && (sides(u) & sv) == 0) continue;  // a border vertex moves only along its side
      const int ux = vx_[u], uy = vy_[u];
      // Every new triangle must be counter-clockwise. The removed vertex's own sample is the likeliest to break
      // the bound: test it first, in O(1), in the new triangle that holds it ((a, b, v) is counter-clockwise by
      // construction, so two orientations decide).
      bool ok = true, v_checked = false;
      for (const Wedge& w : wedges_) {
        if (w.a == u || w.b == u) continue;
        const int ax = vx_[w.a], ay = vy_[w.a], bx = vx_[w.b], by = vy_[w.b];
        if (orient(ux, uy, ax, ay, bx, by) <= 0) {
          ok = false;
          break;
        }
        if (!v_checked && orient(ux, uy, ax, ay, px, py) >= 0 && orient(bx, by, ux, uy, px, py) >= 0) {
          v_checked = true;
          if (Scanner::point_error(ux, uy, vz_[u], ax, ay, vz_[w.a], bx, by, vz_[w.b], px, py, vz_[v]) > best) {
            ok = false;
            break;
          }
        }
      }
      if (!ok) continue;
      double worst = 0.0;
      wedge_error_.assign(wedges_.size(), 0.0f);
      for (std::size_t k = 0; k < wedges_.size(); ++k) {
        const Wedge& w = wedges_[k];
        if (w.a == u || w.b == u) continue;
        const Scan s = scanner_.scan<true>(ux, uy, vx_[w.a], vy_[w.a], vx_[w.b], vy_[w.b], best);
        wedge_error_[k] = static_cast<float>(s.error);
        worst = std::max(worst, s.error);
        if (worst > best) break;
      }
      // The topological check last: it is the dearest per candidate and most candidates fail before it.
      if (worst <= best && link_condition(u)) {
        best = worst;
        best_u = u;
        best_error_.swap(wedge_error_);  // complete scans (none stopped early): the new triangles' errors
      }
    }
    into_[v] = best_u;
    if (best_u >= 0) {
      queue_.push({best, v, best_u, version_[v]});
      errors_at_[v] = static_cast<std::uint32_t>(error_pool_.size());
      error_pool_.insert(error_pool_.end(), best_error_.begin(), best_error_.end());
    }
  }

  // The vertices adjacent to both v and u are exactly the third vertices of the wedges on edge vu (else the
  // collapse would pinch the surface). v's neighbours carry the current mark (evaluate).
  bool link_condition(int u) {
    ++link_generation_;
    int common = 0;
    for (int t : star_[u])
      for (int c : tris_[t])
        if (c != u && mark_[c] == generation_ && seen_[c] != link_generation_) {
          seen_[c] = link_generation_;
          ++common;
        }
    int shared = 0;
    for (const Wedge& w : wedges_) shared += (w.a == u || w.b == u) ? 1 : 0;
    return common == shared;
  }

  // Collapses v into u and marks for re-evaluation the vertices whose star changes (v's neighbours, u among
  // them) and those whose chosen collapse goes into one of them (its link condition may change). For any other
  // vertex nothing its evaluation read has changed, and its other candidates can only have become illegal, so
  // its queued collapse is still its best.
  void collapse(int v, int u) {
    ++generation_;
    for (int t : star_[v])
      for (int w : tris_[t])
        if (w != v) {
          mark_[w] = generation_;
          dirty_[w] = 1;
        }
    // The star is as v's evaluation saw it (else v would be dirty), so its wedges' errors apply in order.
    const float* errors = error_pool_.data() + errors_at_[v];
    for (int t : star_[v]) {
      auto& c = tris_[t];
      const float error = *errors++;
      if (c[0] == u || c[1] == u || c[2] == u) {
        alive_tri_[t] = 0;
        for (int w : c)
          if (w != v) {
            auto& s = star_[w];
            s.erase(std::find(s.begin(), s.end(), t));
          }
      } else {
        for (auto& w : c)
          if (w == v) w = u;
        error_[t] = error;
        star_[u].push_back(t);
      }
    }
    star_[v].clear();
    alive_vertex_[v] = 0;
    ++version_[v];
    for (int t : star_[u])
      for (int w : tris_[t])
        if (into_[w] >= 0 && mark_[into_[w]] == generation_) dirty_[w] = 1;
  }

  int width_, height_;
  const Scanner& scanner_;
  std::vector<int> vx_, vy_;
  std::vector<float> vz_;  // the vertices' heights (kept here: the field itself is far away in memory)
  std::vector<std::array<std::int32_t, 3>> tris_;
  std::vector<std::uint8_t> alive_tri_, alive_vertex_;
  std::vector<std::vector<int>> star_;
  std::vector<std::uint32_t> version_;
  std::priority_queue<Entry> queue_;
  double bound_ = 0.0;
  std::vector<std::uint8_t> dirty_;
  struct Wedge {
    int a, b;
  };
  std::vector<Wedge> wedges_;               // of the vertex being evaluated
  std::vector<int> nv_;                     // its neighbours
  std::vector<std::uint32_t> mark_, seen_;  // per vertex: neighbour of it (generation_), counted (link_generation_)
  std::uint32_t generation_ = 0, link_generation_ = 0;
  std::vector<int> into_;     // per vertex: the neighbour of its queued collapse, or -1
  std::vector<float> error_;  // per triangle: its largest error, as the scans found it
  // The errors of the triangles each vertex's queued collapse makes, per wedge of its star, from errors_at_[v].
  std::vector<float> error_pool_, wedge_error_, best_error_;
  std::vector<std::uint32_t> errors_at_;
};

}  // namespace

Tin heightfield_tin(const Heightfield& height, const TinOptions& options) {
  const int w = height.width(), h = height.height();
  if (w < 2 || h < 2) throw std::invalid_argument("a heightfield mesh needs at least 2 x 2 samples");
  if (static_cast<double>(w) * h > static_cast<double>(std::numeric_limits<std::int32_t>::max()) / 4)
    throw std::invalid_argument("the heightfield is too large for one mesh (" + height.domain.describe() + ")");
  double zmax = 0.0;
  for (float z : height.data) {
    if (!std::isfinite(z)) throw std::invalid_argument("the heightfield has non-finite heights");
    zmax = std::max(zmax, static_cast<double>(std::abs(z)));
  }
  // Round-off of a plane evaluation: distances below this are zero (a vertex is never inserted twice).
  const double tiny = 1e-9 * (1.0 + zmax);
  const bool bounded = options.max_error > 0.0;
  const double bound = bounded ? std::max(options.max_error, tiny)
                               : (options.target_faces > 0 ? std::numeric_limits<double>::infinity() : tiny);

  // The SIMD single-precision scan errs by at most 8 units in the last place of the largest |z| (rounding of
  // the plane's value at the row start, of the slope times the offset, of their sum and of the difference;
  // each term is at most twice that magnitude): 1e-6 |z|max covers it. Both stages then work to the bound
  // minus this margin, so the exact error stays within the bound. Bounds too tight for it (below 16 margins)
  // use the double-precision scan throughout.
  const double margin = 1e-6 * zmax;
  const bool single = std::isfinite(bound) && bound > 16.0 * margin;
  const Scanner scanner(w, height.data.data(), height.data.size(), single);
  const double working_bound = single ? bound - margin : bound;
  GreedyInsertion greedy(height, scanner);
  const bool simplify = options.simplify && bounded;
  // A vertex's own sample may show a float error up to the margin: never refine on less than twice that.
  greedy.run(working_bound, options.target_faces, single ? std::max(tiny, 2.0 * margin) : tiny, options,
             simplify ? 0.6 : 1.0);

  Tin tin;
  tin.width = w;
  tin.height = h;
  std::vector<float> errors;  // per triangle of tin, as the scans found it
  if (simplify && !(options.should_stop && options.should_stop())) {
    Collapser collapser(w, h, scanner, greedy.vx_, greedy.vy_, greedy.corner_, greedy.error_);
    collapser.run(working_bound, options.target_faces, options);
    tin = collapser.result(std::move(tin), errors);
  } else {
    tin.samples.reserve(greedy.vx_.size());
    for (std::size_t v = 0; v < greedy.vx_.size(); ++v) tin.samples.push_back(greedy.vy_[v] * w + greedy.vx_[v]);
    tin.triangles.reserve(greedy.corner_.size() / 3);
    for (std::size_t t = 0; t < greedy.corner_.size(); t += 3)
      tin.triangles.push_back({greedy.corner_[t], greedy.corner_[t + 1], greedy.corner_[t + 2]});
    errors = greedy.error_;
  }
  // The exact largest error: the double-precision scan of only the triangles whose fast error (known from the
  // stages) comes within two margins of the largest (no other can hold the exact maximum).
  const double fast_worst = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
  auto corners = [&](const std::array<std::int32_t, 3>& t) {
    std::array<int, 6> p{};
    for (int k = 0; k < 3; ++k) p[2 * k] = tin.samples[t[k]] % w, p[2 * k + 1] = tin.samples[t[k]] / w;
    return p;
  };
  double worst = 0.0;
  for (std::size_t t = 0; t < tin.triangles.size(); ++t)
    if (!single || errors[t] >= fast_worst - 2.0 * margin) {
      const auto p = corners(tin.triangles[t]);
      worst = std::max(worst, scanner.scan_exact<false>(p[0], p[1], p[2], p[3], p[4], p[5]).error);
    }
  tin.max_error = worst;
  if (options.progress) options.progress(1.0);
  return tin;
}

}  // namespace orogen
