#include "nodes/scatter/poisson_disk.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/scatter/poisson_plan.h"
#include "nodes/scatter/scatter_hash.h"

// The driver: checks, the plan, the chunks filled by one of the two samplers, the output.
namespace orogen {

double poisson_conflict_distance(const PoissonParams& p, int a, double ra, int b, double rb) {
  return a == b ? std::max(ra, rb) : p.cross_separation * 0.5 * (ra + rb);
}

double poisson_local_radius(const PoissonParams& p, int k, double x, double y) {
  return poisson::PoissonPlan(p).local_radius(k, x, y);
}

namespace poisson {

PoissonPlan make_plan(const PoissonParams& p) {
  PoissonPlan s(p);
  const std::size_t K = p.classes.size();
  s.order.resize(K);
  std::iota(s.order.begin(), s.order.end(), 0);
  std::stable_sort(s.order.begin(), s.order.end(),
                   [&](int a, int b) { return p.classes[a].radius > p.classes[b].radius; });
  s.rank.assign(K, 0);
  for (std::size_t o = 0; o < K; ++o) s.rank[s.order[o]] = static_cast<int>(o);
  const bool varies =
      p.density || p.mask || std::any_of(p.classes.begin(), p.classes.end(), [](const auto& c) { return c.density; });
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
  return s;
}

std::vector<double> final_margins(const PoissonPlan& s) {
  const std::size_t K = s.order.size();
  std::vector<double> m(K, 0.0);
  for (std::size_t o = K - 1; o-- > 0;) {
    const int next = s.order[o + 1];
    m[o] = (m[o + 1] + 4.0 * s.chunk[next] + s.reach[next]) * (1.0 + 1e-9) + 1e-9;
  }
  return m;
}

}  // namespace poisson

PoissonLayout poisson_layout(const PoissonParams& p) {
  const poisson::PoissonPlan s = poisson::make_plan(p);
  PoissonLayout l;
  for (double r : s.reach) l.interaction = std::max(l.interaction, r);
  for (double c : s.chunk) l.chunk = std::max(l.chunk, c);
  const auto m = poisson::final_margins(s);
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
  if (p.bounded && !(p.bounds_lo.x <= p.bounds_hi.x && p.bounds_lo.y <= p.bounds_hi.y && std::isfinite(p.bounds_lo.x) &&
                     std::isfinite(p.bounds_lo.y) && std::isfinite(p.bounds_hi.x) && std::isfinite(p.bounds_hi.y)))
    throw std::invalid_argument("PoissonDisk: the sampled rectangle must be finite and not inverted");

  poisson::PoissonPlan s = poisson::make_plan(p);
  const std::size_t K = p.classes.size();
  const auto margin = poisson::final_margins(s);

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

  s.grids =
      s.uniform ? poisson::sample_uniform(s, lo, hi, margin, ctx) : poisson::sample_general(s, lo, hi, margin, ctx);

  // Output: the points inside [lo, hi], class by class (largest first), chunk rows first. Counted per chunk,
  // then written in parallel at the prefix offsets (the yaw costs a hash, a sine and a cosine per point).
  Points out;
  auto& radius = out.attribute("radius");
  for (int k : s.order) {
    const poisson::ClassChunks& g = s.grids[k];
    const auto i0 = static_cast<std::int64_t>(std::floor(lo.x / g.C)),
               i1 = static_cast<std::int64_t>(std::floor(hi.x / g.C));
    const auto j0 = static_cast<std::int64_t>(std::floor(lo.y / g.C)),
               j1 = static_cast<std::int64_t>(std::floor(hi.y / g.C));
    const int w = static_cast<int>(i1 - i0 + 1), rows = static_cast<int>(j1 - j0 + 1);
    auto keep = [&](const poisson::Pt& q) {
      const double x = q.x, y = q.y;
      return !(x < lo.x || x > hi.x || y < lo.y || y > hi.y);
    };
    std::vector<std::size_t> offset(static_cast<std::size_t>(rows) + 1, 0);
    for_each_row(nullptr, rows, [&](int r) {
      std::size_t c = 0;
      for (int i = 0; i < w; ++i)
        for (const poisson::Pt& q : g.at(i0 + i, j0 + r)) c += keep(q);
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
        for (const poisson::Pt& q : g.at(i0 + i, j0 + r)) {
          if (!keep(q)) continue;
          out.position[o] = glm::vec3(q.x, q.y, 0.0f);
          const double yaw = 2.0 * poisson::kPi *
                             scatter::unit(scatter::hash(p.seed, 0x7A3ull, scatter::bits(q.x), scatter::bits(q.y)));
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
