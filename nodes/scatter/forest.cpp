#include "nodes/scatter/forest.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/work_bounds.h"
#include "nodes/common/work_poll.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

glm::dvec3 sun_direction(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
  return {std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)};
}

Canopy::Canopy(const Points& casters, const CanopyParams& p)
    : max_distance_(p.max_shadow_distance), sun_(glm::normalize(p.sun)) {
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  max_top_ = -INFINITY;
  for (std::size_t i = 0; i < casters.size(); ++i) {
    const auto& q = casters.position[i];
    const auto& s = casters.scale[i];
    const Sphere sp{q.x, q.y, q.z + p.crown_height * s.z, p.crown_radius * std::abs(s.x)};
    if (!std::isfinite(sp.x) || !std::isfinite(sp.y) || !std::isfinite(sp.z) || !std::isfinite(sp.r) || sp.r <= 0.0)
      continue;
    spheres_.push_back(sp);
    xmin = std::min(xmin, sp.x);
    ymin = std::min(ymin, sp.y);
    xmax = std::max(xmax, sp.x);
    ymax = std::max(ymax, sp.y);
    max_r_ = std::max(max_r_, sp.r);
    max_top_ = std::max(max_top_, sp.z + sp.r);
  }
  if (spheres_.empty()) return;
  cell_ = std::max(2.0 * max_r_, 1e-3);
  // Keep the index to a few million cells whatever the spread, a line of crowns too (its area is 0, its cells not).
  const auto cells_for = [&](double cell) { return ((xmax - xmin) / cell + 1.0) * ((ymax - ymin) / cell + 1.0); };
  if (const double cells = cells_for(cell_); cells > 4e6) cell_ *= std::sqrt(cells / 4e6);
  while (cells_for(cell_) > 4e6) cell_ *= 2.0;
  x0_ = xmin;
  y0_ = ymin;
  nx_ = static_cast<int>((xmax - xmin) / cell_) + 1;
  ny_ = static_cast<int>((ymax - ymin) / cell_) + 1;
  cells_.resize(static_cast<std::size_t>(nx_) * ny_);
  for (std::size_t i = 0; i < spheres_.size(); ++i) {
    const int cx = std::min(static_cast<int>((spheres_[i].x - x0_) / cell_), nx_ - 1);
    const int cy = std::min(static_cast<int>((spheres_[i].y - y0_) / cell_), ny_ - 1);
    cells_[static_cast<std::size_t>(cy) * nx_ + cx].push_back(static_cast<int>(i));
  }
}

bool Canopy::shaded(double x, double y, double z, WorkPoll* poll) const {
  if (spheres_.empty() || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return false;
  const glm::dvec2 h(sun_.x, sun_.y);
  const double hl = glm::length(h);
  // Horizontal distance the ray travels before it rises above every crown.
  const double rise = std::max(0.0, max_top_ - z);
  double L = sun_.z > 1e-9 ? rise * hl / sun_.z : 1e9;
  // A crown within max_distance_ meets the ray, if at all, within its radius beyond that distance.
  if (max_distance_ > 0.0) L = std::min(L, max_distance_ + max_r_);
  const glm::dvec2 dir = hl > 0 ? h / hl : glm::dvec2(0.0);
  const double step = 0.5 * cell_;
  // Steps k = 0 .. steps at l = min(k step, L), in 64 bits (a small crown and a low sun take more than 2^31).
  const std::int64_t steps = static_cast<std::int64_t>(std::min(L, 1e7) / step) + 1;
  // Only steps whose cell lies within one cell of the index can meet a crown: the march is clipped to the
  // index's rectangle grown by two cells (the margin covers rounding), which skips exactly the steps that
  // did nothing, so the result is the same as marching all of them.
  std::int64_t k0 = 0, k1 = steps;
  {
    double la = 0.0, lb = std::numeric_limits<double>::infinity();
    const auto clip = [&](double o, double d, double lo, double hi) {
      if (d == 0.0) {
        if (!(o >= lo && o <= hi)) lb = -1.0;
        return;
      }
      double a = (lo - o) / d, b = (hi - o) / d;
      if (a > b) std::swap(a, b);
      la = std::max(la, a);
      lb = std::min(lb, b);
    };
    clip(x, dir.x, x0_ - 2.0 * cell_, x0_ + (nx_ + 2.0) * cell_);
    clip(y, dir.y, y0_ - 2.0 * cell_, y0_ + (ny_ + 2.0) * cell_);
    if (!(la <= lb)) return false;
    const double ka = std::floor(la / step) - 1.0, kb = std::ceil(lb / step) + 1.0;
    if (ka > static_cast<double>(steps)) return false;
    if (ka > 0.0) k0 = static_cast<std::int64_t>(ka);
    if (kb < static_cast<double>(steps)) k1 = std::max<std::int64_t>(k0, static_cast<std::int64_t>(kb));
  }
  int last_cx = INT32_MIN, last_cy = INT32_MIN;
  for (std::int64_t k = k0; k <= k1; ++k) {
    if (poll) (*poll)();
    const double l = std::min(static_cast<double>(k) * step, L);
    const double qx = x + dir.x * l, qy = y + dir.y * l;
    const double fx = std::floor((qx - x0_) / cell_), fy = std::floor((qy - y0_) / cell_);
    if (fx < -1.0 || fy < -1.0 || fx > nx_ || fy > ny_) {
      // Outside the canopy's extent and moving away is not certain: keep marching.
      last_cx = last_cy = INT32_MIN;
      continue;
    }
    const int cx = static_cast<int>(fx), cy = static_cast<int>(fy);
    if (cx == last_cx && cy == last_cy) continue;
    last_cx = cx;
    last_cy = cy;
    for (int j = std::max(cy - 1, 0); j <= std::min(cy + 1, ny_ - 1); ++j)
      for (int i = std::max(cx - 1, 0); i <= std::min(cx + 1, nx_ - 1); ++i)
        for (int idx : cells_[static_cast<std::size_t>(j) * nx_ + i]) {
          const Sphere& s = spheres_[idx];
          const glm::dvec3 w(s.x - x, s.y - y, s.z - z);
          if (max_distance_ > 0.0 && w.x * w.x + w.y * w.y > max_distance_ * max_distance_) continue;
          const double tc = glm::dot(w, sun_);
          const double d2 = tc < 0.0 ? glm::dot(w, w) : glm::dot(w, w) - tc * tc;
          if (d2 < s.r * s.r) return true;
        }
  }
  return false;
}

double Canopy::max_march() const {
  if (spheres_.empty()) return 0.0;
  // The clipped march crosses the index's rectangle grown by two cells: its diagonal in half cells, plus the
  // margin steps.
  return 2.0 * std::hypot(nx_ + 4.0, ny_ + 4.0) + 6.0;
}

Heightfield shade_map(const Domain& d, const Canopy& canopy, const Heightfield* height, const ExecContext* ctx) {
  Heightfield out(d);
  for_each_row(ctx, d.height(), [&](int j) {
    WorkPoll poll(ctx);
    for (int i = 0; i < d.width(); ++i) {
      const double x = d.x(i), y = d.y(j);
      double z = height ? height->sample_world(x, y) : 0.0;
      if (!std::isfinite(z)) z = 0.0;
      out.at(i, j) = canopy.shaded(x, y, z, &poll) ? 1.0f : 0.0f;
    }
  });
  return out;
}

ShadePlacementResult shade_placement(const Points& candidates, const Points& casters, const Domain& d,
                                     const Heightfield* height, const ShadePlacementParams& p, const ExecContext* ctx) {
  const bool night = !(p.canopy.sun.z > 1e-6);
  CanopyParams cp = p.canopy;
  if (night) cp.sun = glm::dvec3(0.0, 0.0, 1.0);
  const Canopy canopy(casters, cp);
  // The ceiling on marching: every candidate and every sample of the shadow map marches at most max_march
  // steps (the count is in double: it cannot overflow).
  check_work((static_cast<double>(candidates.size()) + static_cast<double>(d.sample_count())) * canopy.max_march(),
             "ShadePlacement: shadow march steps (candidates and shadow-map samples x steps per ray)",
             "raise crown_radius or the sun's elevation, or use fewer candidates or a coarser domain");
  ShadePlacementResult r;
  WorkPoll poll(ctx);
  Points& out = r.points;
  for (const auto& [name, values] : candidates.attributes) out.attribute(name);
  auto& shade_attr = out.attribute("shade");
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    poll();
    const auto& q = candidates.position[i];
    const bool s = night || canopy.shaded(q.x, q.y, q.z, &poll);
    if ((p.preference == ShadePreference::Shade && !s) || (p.preference == ShadePreference::Sun && s)) continue;
    const std::size_t k = out.add(q, candidates.class_id[i]);
    out.rotation[k] = candidates.rotation[i];
    out.scale[k] = candidates.scale[i];
    for (const auto& [name, values] : candidates.attributes)
      if (name != "shade") out.attributes[name][k] = values[i];
    shade_attr[k] = s ? 1.0f : 0.0f;
  }
  if (night) {
    r.shade = Heightfield(d);
    std::fill(r.shade.data.begin(), r.shade.data.end(), 1.0f);
  } else {
    r.shade = shade_map(d, canopy, height, ctx);
  }
  return r;
}

namespace {

struct Tree {
  double x, y;
  double age;
  std::int32_t cls;
  std::uint64_t uid;
};

double scale_of(const LifeCycleParams& p, double age) {
  const double t = p.maturity_age > 0.0 ? std::clamp(age / p.maturity_age, 0.0, 1.0) : 1.0;
  return p.min_scale + t * (p.max_scale - p.min_scale);
}

// Uniform grid of tree indices, rebuilt each year.
struct TreeGrid {
  double cell;
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  static std::uint64_t key(std::int64_t i, std::int64_t j) {
    return (static_cast<std::uint64_t>(i) << 32) ^ (static_cast<std::uint64_t>(j) & 0xFFFFFFFFull);
  }
  std::int64_t ci(double v) const { return static_cast<std::int64_t>(std::floor(v / cell)); }
  void insert(double x, double y, int idx) { cells[key(ci(x), ci(y))].push_back(idx); }
  template <class Fn>
  bool any_near(double x, double y, Fn&& conflict) const {
    const auto cx = ci(x), cy = ci(y);
    for (std::int64_t j = cy - 1; j <= cy + 1; ++j)
      for (std::int64_t i = cx - 1; i <= cx + 1; ++i) {
        const auto it = cells.find(key(i, j));
        if (it == cells.end()) continue;
        for (int idx : it->second)
          if (conflict(idx)) return true;
      }
    return false;
  }
};

}  // namespace

Points forest_life_cycle(const Points& initial, const LifeCycleParams& p, const ExecContext* ctx) {
  if (p.years < 0) throw std::invalid_argument("ForestLifeCycle: years must be >= 0");
  if (!(p.min_scale > 0.0 && p.max_scale >= p.min_scale))
    throw std::invalid_argument("ForestLifeCycle: need 0 < min_scale <= max_scale");
  if (!(p.max_age > 0.0)) throw std::invalid_argument("ForestLifeCycle: max_age must be > 0");
  const auto age_attr = initial.attributes.find("age");
  std::vector<Tree> trees;
  for (std::size_t i = 0; i < initial.size(); ++i) {
    const auto& q = initial.position[i];
    if (!std::isfinite(q.x) || !std::isfinite(q.y)) continue;
    double age = age_attr != initial.attributes.end()
                     ? age_attr->second[i]
                     : std::floor(scatter::unit(scatter::hash(p.seed, 0xA6Eull, i)) * p.max_age);
    if (!std::isfinite(age)) age = 0.0;
    trees.push_back({q.x, q.y, age, initial.class_id[i], scatter::hash(p.seed, 0x1D0ull, i)});
  }
  const double reach = p.competition * p.max_scale;  // the largest competition distance
  const auto suitable = [&](double x, double y) {
    if (x < p.lo.x || x > p.hi.x || y < p.lo.y || y > p.hi.y) return false;
    if (!p.suitability) return true;
    const double v = p.suitability->sample_world(x, y);
    return v >= 0.5;
  };
  for (int year = 0; year < p.years; ++year) {
    if (ctx) {
      ctx->check_cancelled();
      ctx->progress(static_cast<double>(year) / std::max(1, p.years));
    }
    // Ageing, deaths and seeds (in the trees' order).
    std::vector<Tree> alive, seeds;
    for (const Tree& t0 : trees) {
      Tree t = t0;
      t.age += 1.0;
      scatter::Draws draw{scatter::hash(p.seed, t.uid, static_cast<std::uint64_t>(year))};
      int n = 0;
      if (t.age > p.max_age) {
        n = 1 + (draw.next() < 0.5 ? 1 : 0);  // a dying tree drops one or two seeds
      } else {
        alive.push_back(t);
        if (t.age >= p.maturity_age && draw.next() < p.seed_probability) n = 1;
      }
      for (int k = 0; k < n; ++k) {
        const double rho = p.seed_distance * std::sqrt(draw.next()), theta = 2.0 * kPi * draw.next();
        seeds.push_back({t.x + rho * std::cos(theta), t.y + rho * std::sin(theta), 0.0, t.cls,
                         scatter::hash(t.uid, static_cast<std::uint64_t>(year), static_cast<std::uint64_t>(k))});
      }
    }
    // Competition: the larger (then older, then by uid) tree keeps its place; a tree closer than
    // competition * (s_i + s_j) / 2 to a kept one dies.
    std::vector<double> sc(alive.size());
    for (std::size_t i = 0; i < alive.size(); ++i) sc[i] = scale_of(p, alive[i].age);
    std::vector<int> order(alive.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      if (sc[a] != sc[b]) return sc[a] > sc[b];
      if (alive[a].age != alive[b].age) return alive[a].age > alive[b].age;
      return alive[a].uid < alive[b].uid;
    });
    TreeGrid grid{std::max(reach, 1e-3), {}};
    std::vector<Tree> kept;
    std::vector<double> kept_scale;
    auto conflicts = [&](double x, double y, double s) {
      return grid.any_near(x, y, [&](int idx) {
        const double dx = kept[idx].x - x, dy = kept[idx].y - y;
        const double c = p.competition * 0.5 * (s + kept_scale[idx]);
        return dx * dx + dy * dy < c * c;
      });
    };
    for (int i : order) {
      if (conflicts(alive[i].x, alive[i].y, sc[i])) continue;
      grid.insert(alive[i].x, alive[i].y, static_cast<int>(kept.size()));
      kept.push_back(alive[i]);
      kept_scale.push_back(sc[i]);
    }
    // Germination where the rules allow and there is room for a seedling.
    for (const Tree& s : seeds) {
      if (!suitable(s.x, s.y) || conflicts(s.x, s.y, p.min_scale)) continue;
      grid.insert(s.x, s.y, static_cast<int>(kept.size()));
      kept.push_back(s);
      kept_scale.push_back(p.min_scale);
    }
    // Keep a stable order: by uid.
    std::sort(kept.begin(), kept.end(), [](const Tree& a, const Tree& b) { return a.uid < b.uid; });
    trees = std::move(kept);
    if (trees.size() > 5'000'000)
      throw std::runtime_error("ForestLifeCycle: more than 5 million trees in year " + std::to_string(year + 1) +
                               "; raise competition or lower seed_probability");
  }
  Points out;
  auto& age = out.attribute("age");
  for (const Tree& t : trees) {
    const std::size_t k = out.add({static_cast<float>(t.x), static_cast<float>(t.y), 0.0f}, t.cls);
    age[k] = static_cast<float>(t.age);
    out.scale.back() = glm::vec3(static_cast<float>(scale_of(p, t.age)));
    out.rotation.back() = glm::angleAxis(static_cast<float>(2.0 * kPi * scatter::unit(scatter::hash(t.uid, 0x7A3ull))),
                                         glm::vec3(0.0f, 0.0f, 1.0f));
  }
  return out;
}

}  // namespace orogen
