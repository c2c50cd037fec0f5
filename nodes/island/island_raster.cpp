#include "nodes/island/island_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/island/cell_index.h"
#include "nodes/island/island.h"
#include "nodes/island/island_random.h"
#include "nodes/noise/fbm.h"
#include "nodes/common/color_space.h"

namespace orogen::island {
namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// The bucket of coordinate u (in buckets) among n, clamped; NaN and huge values never reach an int cast.
int bucket_index(double u, int n) {
  const double f = std::floor(u);
  if (!(f >= 0.0)) return 0;
  if (f >= n - 1) return n - 1;
  return static_cast<int>(f);
}

// Grid of about `target` buckets over a rectangle of `size`, its cells as square as the aspect ratio allows
// (a map of 10 m x 10 km gets 1 x n buckets, not n x n of which all but one column are empty).
glm::ivec2 bucket_grid(glm::dvec2 size, double target, int max_side) {
  target = std::clamp(target, 1.0, static_cast<double>(max_side) * max_side);
  const double gx = std::clamp(std::round(std::sqrt(target * size.x / size.y)), 1.0, static_cast<double>(max_side));
  const double gy = std::clamp(std::round(target / gx), 1.0, static_cast<double>(max_side));
  return {static_cast<int>(gx), static_cast<int>(gy)};
}

const std::vector<float>* find_attr(const PolygonMap::Attributes& attrs, const char* name, std::size_t n) {
  const auto it = attrs.find(name);
  return it != attrs.end() && it->second.size() == n ? &it->second : nullptr;
}

// Uniform bucket grid over the segments' bounding boxes (each expanded by its half width).
struct SegmentGrid {
  struct Segment {
    glm::dvec2 a, b;
    double half_width;
  };
  std::vector<Segment> segments;
  glm::dvec2 lo{0.0}, cell{1.0};
  int gw = 1, gh = 1;
  std::vector<std::vector<int>> buckets;

  void build(glm::dvec2 map_lo, glm::dvec2 map_hi) {
    lo = map_lo;
    const glm::dvec2 size = glm::max(map_hi - map_lo, glm::dvec2(1e-9));
    // About sqrt(n) x sqrt(n) buckets on a square map (exactly as before: coverage reaches half a spacing past
    // a segment's box, so the grid shapes the result at bucket borders), stretched with the aspect ratio.
    const double target = static_cast<double>(std::max<std::size_t>(segments.size(), 1));
    const double aspect = size.x / size.y;
    gw = static_cast<int>(std::clamp(std::sqrt(target * aspect), 1.0, 512.0));
    gh = static_cast<int>(std::clamp(std::sqrt(target / aspect), 1.0, 512.0));
    cell = size / glm::dvec2(gw, gh);
    buckets.assign(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh), {});
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const auto& g = segments[s];
      const glm::dvec2 a = glm::min(g.a, g.b) - g.half_width - 1e-9, b = glm::max(g.a, g.b) + g.half_width + 1e-9;
      const glm::ivec2 i0 = bucket(a), i1 = bucket(b);
      for (int y = i0.y; y <= i1.y; ++y)
        for (int x = i0.x; x <= i1.x; ++x) buckets[static_cast<std::size_t>(y * gw + x)].push_back(static_cast<int>(s));
    }
  }
  glm::ivec2 bucket(glm::dvec2 p) const {
    const glm::dvec2 u = (p - lo) / cell;
    return {bucket_index(u.x, gw), bucket_index(u.y, gh)};
  }
  // Coverage in [0, 1] at p: the largest over segments of (half width - distance) / spacing + 0.5, clamped.
  float coverage(glm::dvec2 p, double spacing) const {
    if (segments.empty()) return 0.0f;
    const glm::ivec2 b = bucket(p);
    double best = 0.0;
    for (int s : buckets[static_cast<std::size_t>(b.y * gw + b.x)]) {
      const auto& g = segments[ix(s)];
      const glm::dvec2 d = g.b - g.a;
      const double len2 = glm::dot(d, d);
      const double t = len2 > 0.0 ? std::clamp(glm::dot(p - g.a, d) / len2, 0.0, 1.0) : 0.0;
      const double dist = glm::length(p - (g.a + t * d));
      best = std::max(best, std::clamp((g.half_width - dist) / spacing + 0.5, 0.0, 1.0));
    }
    return static_cast<float>(best);
  }
};

}  // namespace

CellLocator::CellLocator(const PolygonMap& map) : map_(map) {
  lo_ = map.min_corner;
  const glm::dvec2 size = glm::max(map.max_corner - map.min_corner, glm::dvec2(1e-9));
  const double n = static_cast<double>(std::max<std::size_t>(map.cells.size(), 1));
  const glm::ivec2 g = bucket_grid(size, n / 2.25, 4096);  // about 2 sites per bucket
  gw_ = g.x;
  gh_ = g.y;
  cell_ = size / glm::dvec2(gw_, gh_);
  std::vector<int> count(static_cast<std::size_t>(gw_) * static_cast<std::size_t>(gh_) + 1, 0);
  auto bucket_of = [&](glm::dvec2 p) {
    const glm::dvec2 u = (p - lo_) / cell_;
    return bucket_index(u.y, gh_) * gw_ + bucket_index(u.x, gw_);
  };
  for (const auto& c : map.cells) ++count[ix(bucket_of(c.centre)) + 1];
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  start_ = count;
  items_.resize(map.cells.size());
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (std::size_t c = 0; c < map.cells.size(); ++c)
    items_[ix(fill[ix(bucket_of(map.cells[c].centre))]++)] = static_cast<int>(c);
}

// The nearest site (ties: the lower index), by rings of buckets around p's bucket, visiting only each ring's
// perimeter; stops once no bucket of the ring can hold a nearer site. Each axis bounds the distance by its
// own bucket size, so elongated buckets do not make the search scan the whole grid.
int CellLocator::find(glm::dvec2 p) const {
  if (map_.cells.empty()) return -1;
  const glm::dvec2 u = (p - lo_) / cell_;
  const int bx = bucket_index(u.x, gw_), by = bucket_index(u.y, gh_);
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  const auto scan = [&](int x, int y) {
    const int b = y * gw_ + x;
    for (int k = start_[ix(b)]; k < start_[ix(b) + 1]; ++k) {
      const int c = items_[ix(k)];
      const glm::dvec2 d = map_.cells[ix(c)].centre - p;
      const double d2 = glm::dot(d, d);
      if (d2 < best_d2 || (d2 == best_d2 && c < best)) {
        best_d2 = d2;
        best = c;
      }
    }
  };
  const int max_ring = std::max({bx, gw_ - 1 - bx, by, gh_ - 1 - by});
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int ring = 0; ring <= max_ring; ++ring) {
    if (best >= 0 && ring >= 2) {
      // A bucket of this ring (or a later one) lies `ring` columns or `ring` rows away: at least ring - 1
      // bucket widths or heights from p, counting only the directions in which the grid goes on.
      const bool columns = bx - ring >= 0 || bx + ring < gw_, rows = by - ring >= 0 || by + ring < gh_;
      const double reach = std::min(columns ? (ring - 1) * cell_.x : kInf, rows ? (ring - 1) * cell_.y : kInf);
      if (reach * reach > best_d2) break;
    }
    const int x0 = std::max(bx - ring, 0), x1 = std::min(bx + ring, gw_ - 1);
    if (by - ring >= 0)
      for (int x = x0; x <= x1; ++x) scan(x, by - ring);
    if (ring == 0) continue;
    if (by + ring < gh_)
      for (int x = x0; x <= x1; ++x) scan(x, by + ring);
    const int y0 = std::max(by - ring + 1, 0), y1 = std::min(by + ring - 1, gh_ - 1);
    if (bx - ring >= 0)
      for (int y = y0; y <= y1; ++y) scan(bx - ring, y);
    if (bx + ring < gw_)
      for (int y = y0; y <= y1; ++y) scan(bx + ring, y);
  }
  return best;
}

RasterResult rasterize_polygon_map(const PolygonMap& map, const Domain& domain, const RasterParams& p,
                                   const ExecContext* ctx) {
  const std::size_t nc = map.cells.size(), nq = map.corners.size();
  const auto* q_elev = find_attr(map.corner_attributes, "elevation", nq);
  const auto* q_moist = find_attr(map.corner_attributes, "moisture", nq);
  const auto* q_river = find_attr(map.corner_attributes, "river", nq);
  const auto* q_down = find_attr(map.corner_attributes, "downstream", nq);
  const auto* c_biome = find_attr(map.cell_attributes, "biome", nc);
  const auto* c_water = find_attr(map.cell_attributes, "water", nc);
  const auto* c_ocean = find_attr(map.cell_attributes, "ocean", nc);
  const auto* c_lake = find_attr(map.cell_attributes, "lake", nc);
  // Cell centre values: the mean of the corners (as the island defines them).
  std::vector<float> centre_elev(nc, 0.0f), centre_moist(nc, 0.0f);
  for (std::size_t c = 0; c < nc; ++c) {
    double e = 0.0, m = 0.0;
    for (int q : map.cells[c].corners) {
      if (q_elev) e += (*q_elev)[ix(q)];
      if (q_moist) m += (*q_moist)[ix(q)];
    }
    const double k = static_cast<double>(std::max<std::size_t>(map.cells[c].corners.size(), 1));
    centre_elev[c] = static_cast<float>(e / k);
    centre_moist[c] = static_cast<float>(m / k);
  }

  SegmentGrid rivers;
  if (q_river && q_down)
    for (std::size_t q = 0; q < nq; ++q) {
      const int d = static_cast<int>((*q_down)[q]);
      const float v = (*q_river)[q];
      if (d < 0 || d >= static_cast<int>(nq) || !(v > 0.0f)) continue;
      rivers.segments.push_back({map.corners[q].position, map.corners[ix(d)].position,
                                 0.5 * p.river_width * std::sqrt(static_cast<double>(v))});
    }
  rivers.build(map.min_corner, map.max_corner);
  const CellLocator locator(map);
  if (ctx) ctx->check_cancelled();

  // Lookup displacement.
  Heightfield warp_x, warp_y;
  const bool warp = p.perturb_distance > 0.0;
  if (warp) {
    noise::FbmParams f;
    f.basis = noise::Basis::Perlin;
    f.feature_size = p.perturb_feature_size;
    f.amplitude = p.perturb_distance;
    f.octaves = 4;
    f.seed = hash64(p.seed, 0x57415250ull, 0);
    warp_x = noise::fbm(domain, f, {}, ctx);
    f.seed = hash64(p.seed, 0x57415250ull, 1);
    warp_y = noise::fbm(domain, f, {}, ctx);
  }

  RasterResult r;
  auto field = [&] { return std::make_shared<Heightfield>(domain); };
  r.elevation = field();
  r.moisture = field();
  r.biome = field();
  r.water = field();
  r.ocean = field();
  r.lake = field();
  r.river = field();
  r.roughness = field();
  r.amplitude = field();
  r.color = std::make_shared<Image>(domain, 4);
  r.color->channel_names = {"R", "G", "B", "A"};
  r.color->color = true;
  std::array<std::array<float, 3>, kBiomeCount> linear{};
  for (int b = 0; b < kBiomeCount; ++b)
    for (int k = 0; k < 3; ++k) linear[ix(b)][ix(k)] = srgb_to_linear(biome_info(static_cast<Biome>(b)).srgb[ix(k)]);
  const std::array<float, 3> river_color{srgb_to_linear(0x22 / 255.0f), srgb_to_linear(0x55 / 255.0f),
                                         srgb_to_linear(0x88 / 255.0f)};
  const double spacing = std::max(1e-12, std::min(domain.spacing.x, domain.spacing.y));

  const auto run = [&](int j) {
    for (int i = 0; i < domain.width(); ++i) {
      glm::dvec2 pos = domain.position(i, j);
      if (warp) pos += glm::dvec2(warp_x.at(i, j), warp_y.at(i, j));
      if (!std::isfinite(pos.x) || !std::isfinite(pos.y)) pos = domain.position(i, j);
      pos = glm::clamp(pos, map.min_corner, map.max_corner);
      const std::size_t o = r.elevation->index(i, j);
      const int c = locator.find(pos);
      if (c < 0) continue;
      const auto& cell = map.cells[ix(c)];
      // The fan triangle (centre, corner k, corner k+1) containing pos.
      float e = centre_elev[ix(c)], m = centre_moist[ix(c)];
      const glm::dvec2 d = pos - cell.centre;
      const std::size_t n = cell.corners.size();
      for (std::size_t k = 0; k < n; ++k) {
        const int qa = cell.corners[k], qb = cell.corners[(k + 1) % n];
        const glm::dvec2 a = map.corners[ix(qa)].position - cell.centre, b = map.corners[ix(qb)].position - cell.centre;
        if (cross(a, d) < 0.0 || cross(d, b) < 0.0) continue;
        const double det = cross(a, b);
        if (!(det > 0.0)) continue;
        double alpha = std::max(0.0, cross(d, b) / det), beta = std::max(0.0, cross(a, d) / det);
        if (alpha + beta > 1.0) {
          const double s = alpha + beta;
          alpha /= s;
          beta /= s;
        }
        const double g = 1.0 - alpha - beta;
        if (q_elev)
          e = static_cast<float>(g * centre_elev[ix(c)] + alpha * (*q_elev)[ix(qa)] + beta * (*q_elev)[ix(qb)]);
        if (q_moist)
          m = static_cast<float>(g * centre_moist[ix(c)] + alpha * (*q_moist)[ix(qa)] + beta * (*q_moist)[ix(qb)]);
        break;
      }
      const int biome = c_biome ? std::clamp(static_cast<int>((*c_biome)[ix(c)]), 0, kBiomeCount - 1)
                                : static_cast<int>(Biome::Ocean);
      const float river = rivers.coverage(pos, spacing);
      r.elevation->data[o] = e;
      r.moisture->data[o] = m;
      r.biome->data[o] = static_cast<float>(biome);
      r.water->data[o] = c_water ? (*c_water)[ix(c)] : 0.0f;
      r.ocean->data[o] = c_ocean ? (*c_ocean)[ix(c)] : 0.0f;
      r.lake->data[o] = c_lake ? (*c_lake)[ix(c)] : 0.0f;
      r.river->data[o] = river;
      const auto& info = biome_info(static_cast<Biome>(biome));
      r.roughness->data[o] = info.roughness;
      r.amplitude->data[o] = info.amplitude;
      float* px = r.color->pixel(i, j);
      for (int k = 0; k < 3; ++k)
        px[k] = linear[ix(biome)][ix(k)] + river * (river_color[ix(k)] - linear[ix(biome)][ix(k)]);
      px[3] = 1.0f;
    }
  };
  for_each_row(ctx, domain.height(), run);
  return r;
}

}  // namespace orogen::island
