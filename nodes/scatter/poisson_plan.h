#pragma once
// The shared plan of the Poisson-disk sampler (poisson_disk.h): classes in placement order, their radii,
// grid cells, chunk sides and reaches, the chunk windows that hold the points, and the phase order in which
// chunks are processed. Two samplers fill the chunks: the general one (poisson_general.cpp: several classes,
// variable radius) and the fast one for one class of constant radius (poisson_uniform.cpp). Internal to
// the scatter family.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/scatter/poisson_disk.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen::poisson {

inline constexpr double kPi = 3.14159265358979323846;

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
  const std::uint32_t q = ((w + (1u << 29)) >> 30) & 3u;  // nearest quarter turn
  const double a = static_cast<double>(static_cast<std::int32_t>(w - (q << 30))) * (2.0 * kPi * 0x1.0p-32);
  const double a2 = a * a;
  const double s =
      a * (1.0 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 + a2 * (1.0 / 362880 - a2 / 39916800)))));
  const double c =
      1.0 +
      a2 * (-0.5 + a2 * (1.0 / 24 + a2 * (-1.0 / 720 + a2 * (1.0 / 40320 + a2 * (-1.0 / 3628800 + a2 / 479001600)))));
  // Rotated by q quarter turns: (c, s), (-s, c), (-c, -s), (s, -c).
  static constexpr double kSx[4] = {1.0, -1.0, -1.0, 1.0}, kSy[4] = {1.0, 1.0, -1.0, -1.0};
  const bool odd = q & 1u;
  ox = d * kSx[q] * (odd ? s : c);
  oy = d * kSy[q] * (odd ? c : s);
}

inline double field_value(const Heightfield* f, double x, double y) {
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

struct PoissonPlan {
  const PoissonParams& p;
  std::vector<int> order;          // class indices, largest radius first
  std::vector<int> rank;           // position of each class in `order`
  std::vector<double> rmax;        // per class: largest local radius
  std::vector<double> cell;        // per class: background grid cell (r / sqrt 2, slightly less)
  std::vector<double> chunk;       // per class: chunk side
  std::vector<double> reach;       // per class: largest conflict distance with itself and the classes before it
  std::vector<ClassChunks> grids;  // per class

  explicit PoissonPlan(const PoissonParams& params) : p(params) {}

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

  // Grid offsets (nearest first) of the cells of class j that can hold a point conflicting with a class-k
  // point anywhere in a cell: the cells whose distance to the cell is below the largest conflict distance.
  std::vector<std::vector<std::vector<std::pair<int, int>>>> offsets;  // [k][j]
  bool varies = false;
  bool uniform = false;  // one class, constant radius: the fast sampler

  static constexpr double kMaxOffsetReach = 512.0;  // cells: a table of at most 1025^2 offsets per pair (16 MB)

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
        // The table holds (2w + 1)^2 cells: radii (or min_density) far apart would make it unbounded (radii of
        // 1e4 m and 0.01 m: 1e15 cells, computed before any point and with no chance to cancel).
        const double wide = std::ceil(reach_kj / h) + 1.0;
        if (!(wide <= kMaxOffsetReach))
          throw NodeError("PoissonDisk: the classes' radii are too far apart (class " + std::to_string(k) +
                          " reaches " + std::to_string(reach_kj) + " m, class " + std::to_string(j) + "'s cells are " +
                          std::to_string(h) +
                          " m): their ratio, with min_density, may be at most about 700; bring radius_" +
                          std::to_string(k) + " and radius_" + std::to_string(j) + " closer or raise min_density");
        const int w = static_cast<int>(wide);
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
};

// The plan of a parameter set: classes ordered, per-class radii, cells, chunk sides and reaches, offsets.
PoissonPlan make_plan(const PoissonParams& p);

// Metres around the request within which class order[o] must be final: a later class computes chunks up to
// four of its chunks beyond its own final rectangle and reads earlier classes within its reach of them.
std::vector<double> final_margins(const PoissonPlan& s);

// Sets up each class's chunk window around [lo, hi] (its final chunks plus three rings of phase dependencies
// and one of empty chunks) and calls process(cx, cy, k) for its chunks, phase by phase (chunks of one phase
// in parallel).
template <class ProcessChunk>
void run_chunk_phases(PoissonPlan& s, glm::dvec2 lo, glm::dvec2 hi, const std::vector<double>& margin,
                      const ExecContext* ctx, ProcessChunk&& process) {
  const PoissonParams& p = s.p;
  const std::size_t K = p.classes.size();
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
      for_each_row(
          ctx, static_cast<int>(todo.size()), [&](int t) { process(todo[t].first, todo[t].second, k); },
          step / (4.0 * K), (step + 1.0) / (4.0 * K));
    }
  }
}

// The chunks of every class (indexed like p.classes), filled by the general sampler or the fast one.
std::vector<ClassChunks> sample_general(const PoissonPlan& plan, glm::dvec2 lo, glm::dvec2 hi,
                                        const std::vector<double>& margin, const ExecContext* ctx);
std::vector<ClassChunks> sample_uniform(const PoissonPlan& plan, glm::dvec2 lo, glm::dvec2 hi,
                                        const std::vector<double>& margin, const ExecContext* ctx);

}  // namespace orogen::poisson
