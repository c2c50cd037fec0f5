// The fast Poisson-disk sampler (poisson_disk.h) for one class of constant radius (no density, no mask): the
// same chunks, phases and guarantees as the general sampler, with a padded background grid aligned with the
// chunk, candidates drawn in blocks and gap filling cell by cell (see below).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

#include "nodes/scatter/poisson_plan.h"

namespace orogen::poisson {
namespace {

struct UniformChunkSampler : PoissonPlan {
  explicit UniformChunkSampler(const PoissonPlan& plan) : PoissonPlan(plan) {
    if (p.bounded) {
      bx0 = p.bounds_lo.x, by0 = p.bounds_lo.y, bx1 = p.bounds_hi.x, by1 = p.bounds_hi.y;
    }
  }
  // The closed rectangle sampled (PoissonParams::bounded), or the whole plane.
  double bx0 = -INFINITY, by0 = -INFINITY, bx1 = INFINITY, by1 = INFINITY;

  // ---------------------------------------------------------------------------------------------------------
  // Fast path: one class of constant radius (no density, no mask), the common case and the benchmark's.
  // Same chunks and phases as the general sampler (poisson_general.cpp), with:
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
  //   what has room until one lands (then the cell is covered) or none is left; a gap the darts still miss
  //   (narrower than h / 40) gets a point at its farthest spot from the points, found exactly (a circumcentre,
  //   a bisector crossing an edge, or a corner), so no spot of the cell stays free by more than the float
  //   rounding of that point (the maximality of poisson_disk.h). Before this step, darts alone left about one
  //   spot in 2,300 points free by up to 0.07% of r.
  // - a bounded request (PoissonParams::bounded): no point outside the rectangle, cells clipped to it, chunks
  //   outside it skipped.
  // Distances are compared exactly as the general path does (double, on the stored float positions).
  static constexpr double kEmpty = 1e150;
  static constexpr float kFar = 1e15f;  // float sentinel: squared distances stay finite
  static constexpr int kPad = 4;        // cells around the chunk: 2 for the reach r, 2 for the 5 x 5 window
  static constexpr int kBlock = 8;      // Bridson's candidates drawn at once

  struct UniformScratch {
    std::vector<double> gx, gy;  // grid cells: position or kEmpty
    std::vector<float> lx, ly;   // the same relative to the grid origin, in float (filter)
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
    if (!(ax0 <= bx1 && ax1 > bx0 && ay0 <= by1 && ay1 > by0)) return;  // outside the sampled rectangle
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
    // The chunk [ax0, ax1) x [ay0, ay1) within the closed sampled rectangle, as one half-open test (v <= b iff
    // v < the double after b).
    const double ex0 = std::max(ax0, bx0), ex1 = std::min(ax1, std::nextafter(bx1, INFINITY));
    const double ey0 = std::max(ay0, by0), ey1 = std::min(ay1, std::nextafter(by1, INFINITY));
    // Rounds a candidate to float; places it if inside the chunk and the sampled rectangle, and free.
    auto try_place = [&](double x, double y) {
      const double fx = to_float(x), fy = to_float(y);
      if (!(fx >= ex0 && fx < ex1 && fy >= ey0 && fy < ey1)) return false;
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
    FastDraws draw{
        scatter::hash(p.seed, 0x5CA77E5ull, static_cast<std::uint64_t>(k), scatter::bits(gcx), scatter::bits(gcy))};
    // The first dart lands in the part of the chunk inside the sampled rectangle.
    const double sx0 = std::max(ax0, bx0), sy0 = std::max(ay0, by0);
    const double sw = p.bounded ? std::min(ax1, bx1) - sx0 : C, sh = p.bounded ? std::min(ay1, by1) - sy0 : C;
    for (int t = 0; t < 4; ++t)
      if (try_place(sx0 + draw.next() * sw, sy0 + draw.next() * sh)) {
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
  void fill_uniform(UniformScratch& S, FastDraws& draw, int m, int n, double h, double ax0, double ay0, double ax1,
                    double ay1, double r2, TryPlace& try_place) const {
    using Rect = UniformScratch::Rect;
    auto clip = [&](Rect c) {
      return Rect{std::max(c.x0, bx0), std::max(c.y0, by0), std::min(c.x1, bx1), std::min(c.y1, by1)};
    };
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
        const Rect quarters[4] = {
            {c.x0, c.y0, mx, my}, {mx, c.y0, c.x1, my}, {c.x0, my, mx, c.y1}, {mx, my, c.x1, c.y1}};
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
    // The spot of the closed rectangle c farthest from the gathered points, and its squared distance to the
    // nearest of them, exactly as far as it matters: the distance to the nearest point peaks at a Voronoi
    // vertex (a circumcentre of three points), where a Voronoi edge (on the bisector of two) crosses an edge of
    // c, or at a corner. Candidates closer than r to the points defining them are skipped (they cannot be
    // free), so the result is exact when it is >= r^2 and only says "covered" below.
    auto farthest = [&](const Rect& c, double& bx, double& by) {
      double best = -1.0;
      auto consider = [&](double x, double y) {
        double d2 = INFINITY;
        for (int q = 0; q < count; ++q) {
          const double dx = qx[q] - x, dy = qy[q] - y;
          d2 = std::min(d2, dx * dx + dy * dy);
        }
        if (d2 > best) best = d2, bx = x, by = y;
      };
      consider(c.x0, c.y0);
      consider(c.x1, c.y0);
      consider(c.x0, c.y1);
      consider(c.x1, c.y1);
      for (int a = 0; a < count; ++a)
        for (int b = a + 1; b < count; ++b) {
          const double mx = 0.5 * (qx[a] + qx[b]), my = 0.5 * (qy[a] + qy[b]);
          const double ux = qx[b] - qx[a], uy = qy[b] - qy[a];  // bisector: (p - m) . u = 0
          auto on_bisector = [&](double x, double y) {
            const double dx = x - qx[a], dy = y - qy[a];
            if (dx * dx + dy * dy >= r2) consider(x, y);
          };
          if (uy != 0.0)
            for (const double x : {c.x0, c.x1}) {
              const double y = my - (x - mx) * ux / uy;
              if (y >= c.y0 && y <= c.y1) on_bisector(x, y);
            }
          if (ux != 0.0)
            for (const double y : {c.y0, c.y1}) {
              const double x = mx - (y - my) * uy / ux;
              if (x >= c.x0 && x <= c.x1) on_bisector(x, y);
            }
          for (int e = b + 1; e < count; ++e) {
            const double px = ux, py = uy, qx2 = qx[e] - qx[a], qy2 = qy[e] - qy[a];
            const double d = 2.0 * (px * qy2 - py * qx2);
            if (d == 0.0) continue;
            const double p2 = px * px + py * py, q2 = qx2 * qx2 + qy2 * qy2;
            const double cx = (qy2 * p2 - py * q2) / d, cy = (px * q2 - qx2 * p2) / d;
            if (cx * cx + cy * cy < r2) continue;  // circumradius below r
            const double x = qx[a] + cx, y = qy[a] + cy;
            if (x >= c.x0 && x <= c.x1 && y >= c.y0 && y <= c.y1) consider(x, y);
          }
        }
      return best;
    };
    // Places a point at the float nearest (x, y) inside the chunk and the sampled rectangle, or else at one of
    // the 8 floats around it (the spot's clearance may be below the rounding).
    auto place_near = [&](double x, double y) {
      auto snap = [](double v, double lo, double below, double atmost) {
        float f = static_cast<float>(to_float(v));
        while (static_cast<double>(f) < lo) f = std::nextafter(f, INFINITY);
        while (static_cast<double>(f) >= below || static_cast<double>(f) > atmost) f = std::nextafter(f, -INFINITY);
        return f;
      };
      const float fx = snap(x, std::max(ax0, bx0), ax1, bx1), fy = snap(y, std::max(ay0, by0), ay1, by1);
      for (const int dj : {0, -1, 1})
        for (const int di : {0, -1, 1}) {
          const float x1 = di == 0 ? fx : std::nextafter(fx, di * INFINITY);
          const float y1 = dj == 0 ? fy : std::nextafter(fy, dj * INFINITY);
          if (try_place(x1, y1)) return true;
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
    constexpr int kLevels = 3;      // from the squares (h / 5) down to h / 40
    constexpr int kDarts = 4;       // per open rectangle and level (a dart costs a few distances, a refinement more)
    constexpr int kFirstDarts = 2;  // per square left by the bitmask, before any exact test
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const int c0 = (j + kPad) * n + (i + kPad);
        if (gx[c0] != kEmpty) continue;  // a point covers its cell
        // The cell, clipped to the sampled rectangle (closed: its edges are filled too).
        const Rect cell = clip(
            {ax0 + i * h, ay0 + j * h, i + 1 == m ? ax1 : ax0 + (i + 1) * h, j + 1 == m ? ay1 : ay0 + (j + 1) * h});
        if (!(cell.x0 <= cell.x1 && cell.y0 <= cell.y1)) continue;
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
            const Rect q = clip(
                {ax0 + a * s, ay0 + b * s, a + 1 == M ? ax1 : ax0 + (a + 1) * s, b + 1 == M ? ay1 : ay0 + (b + 1) * s});
            if (q.x0 <= q.x1 && q.y0 <= q.y1) squares[ns++] = q;
          }
        if (ns == 0) continue;
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
            // The darts missed a gap narrower than the finest squares: its farthest spot from the points,
            // if free, takes the point (or, when rounding to float makes it conflict, a neighbouring float).
            double fx = 0.0, fy = 0.0;
            if (farthest(cell, fx, fy) >= r2) place_near(fx, fy);
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
};

}  // namespace

std::vector<ClassChunks> sample_uniform(const PoissonPlan& plan, glm::dvec2 lo, glm::dvec2 hi,
                                        const std::vector<double>& margin, const ExecContext* ctx) {
  UniformChunkSampler s(plan);
  run_chunk_phases(s, lo, hi, margin, ctx,
                   [&](std::int64_t cx, std::int64_t cy, int k) { s.process_uniform(cx, cy, k); });
  return std::move(s.grids);
}

}  // namespace orogen::poisson
