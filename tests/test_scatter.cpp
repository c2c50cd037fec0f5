// The scatter family: Poisson-disk placement, ecosystem rules, shade, life cycle, scene export.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <random>

#include <glm/geometric.hpp>
#include <tbb/global_control.h>
#include <tiny_gltf.h>

#include "evaluator/domain_crop.h"
#include "evaluator/run_node.h"
#include "evaluator/value_serialization.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/mesh.h"
#include "graph/points.h"
#include "graph/registry.h"
#include "graph/table_json.h"
#include "nodes/climate/sun.h"
#include "nodes/scatter/forest.h"
#include "nodes/scatter/merge_points.h"
#include "nodes/scatter/mesh_surface.h"
#include "nodes/scatter/project_to_terrain.h"
#include "nodes/scatter/instance.h"
#include "nodes/scatter/poisson_disk.h"
#include "nodes/scatter/scatter_rules.h"
#include "nodes/scatter/scene_gltf.h"
#include "support/empty_circles.h"
#include "support/key_checks.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

int class_index(const PoissonParams& p, int class_id) {
  for (std::size_t k = 0; k < p.classes.size(); ++k)
    if (p.classes[k].class_id == class_id) return static_cast<int>(k);
  return -1;
}

// Every pair of points keeps the sampler's conflict distance (brute force, double precision on the stored
// float positions).
void expect_min_distance(const Points& pts, const PoissonParams& p) {
  const auto& radius = pts.attributes.at("radius");
  std::size_t violations = 0;
  for (std::size_t a = 0; a < pts.size(); ++a)
    for (std::size_t b = a + 1; b < pts.size(); ++b) {
      const double dx = static_cast<double>(pts.position[a].x) - pts.position[b].x;
      const double dy = static_cast<double>(pts.position[a].y) - pts.position[b].y;
      const double c = poisson_conflict_distance(p, class_index(p, pts.class_id[a]), radius[a],
                                                 class_index(p, pts.class_id[b]), radius[b]);
      if (dx * dx + dy * dy < c * c) ++violations;
    }
  EXPECT_EQ(violations, 0u) << "of " << pts.size() << " points";
}

// Number of random probes in [lo, hi] where a point of class index k could still be placed.
int free_probes(const Points& pts, const PoissonParams& p, int k, glm::dvec2 lo, glm::dvec2 hi, int probes,
                unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y);
  const auto& radius = pts.attributes.at("radius");
  int free = 0;
  for (int t = 0; t < probes; ++t) {
    const double x = static_cast<float>(ux(rng)), y = static_cast<float>(uy(rng));
    const double rk = poisson_local_radius(p, k, x, y);
    if (rk <= 0.0) continue;
    bool ok = true;
    for (std::size_t q = 0; q < pts.size() && ok; ++q) {
      const double dx = pts.position[q].x - x, dy = pts.position[q].y - y;
      const double c =
          poisson_conflict_distance(p, k, static_cast<float>(rk), class_index(p, pts.class_id[q]), radius[q]);
      if (dx * dx + dy * dy < c * c) ok = false;
    }
    free += ok;
  }
  return free;
}

PoissonParams one_class(double r, std::uint64_t seed = 7) {
  PoissonParams p;
  p.classes = {{r, 0, nullptr}};
  p.seed = seed;
  return p;
}

bool same_points(const Points& a, const Points& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.position[i] != b.position[i] || a.class_id[i] != b.class_id[i] || a.rotation[i] != b.rotation[i])
      return false;
  return true;
}

Points inside(const Points& pts, glm::dvec2 lo, glm::dvec2 hi) {
  Points out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& q = pts.position[i];
    if (q.x < lo.x || q.x > hi.x || q.y < lo.y || q.y > hi.y) continue;
    const auto k = out.add(q, pts.class_id[i]);
    out.rotation[k] = pts.rotation[i];
  }
  return out;
}

std::vector<glm::dvec2> positions(const Points& pts) {
  std::vector<glm::dvec2> out;
  out.reserve(pts.size());
  for (const auto& q : pts.position) out.emplace_back(q.x, q.y);
  return out;
}

// A smooth density over a large world rectangle (covers every request and its halo).
std::shared_ptr<Heightfield> density_field(double lo_value, double hi_value) {
  auto h = std::make_shared<Heightfield>(Domain::from_extent({-2000, -2000}, {4000, 4000}, {401, 401}));
  for (int j = 0; j < h->height(); ++j)
    for (int i = 0; i < h->width(); ++i) {
      const double x = h->domain.x(i);
      h->at(i, j) = static_cast<float>(x < 100.0 ? lo_value : hi_value);
    }
  return h;
}

TEST(PoissonDisk, MinimumDistanceHoldsForEveryPair) {
  const auto p = one_class(4.0);
  const Points pts = poisson_disk({0, 0}, {240, 180}, p);
  EXPECT_GT(pts.size(), 1500u);
  expect_min_distance(pts, p);
}

TEST(PoissonDisk, MinimumDistanceHoldsWithVariableRadiusAndClasses) {
  auto dens = std::make_shared<Heightfield>(Domain::from_extent({-1000, -1000}, {2000, 2000}, {201, 201}));
  for (int j = 0; j < dens->height(); ++j)
    for (int i = 0; i < dens->width(); ++i)
      dens->at(i, j) =
          static_cast<float>(0.55 + 0.45 * std::sin(dens->domain.x(i) / 37.0) * std::cos(dens->domain.y(j) / 23.0));
  PoissonParams p;
  p.classes = {{3.0, 0, nullptr}, {8.0, 1, nullptr}, {1.5, 2, nullptr}};
  p.density = dens.get();
  p.cross_separation = 0.6;
  p.seed = 11;
  const Points pts = poisson_disk({-50, -30}, {150, 120}, p);
  std::map<int, int> counts;
  for (int c : pts.class_id) ++counts[c];
  EXPECT_EQ(counts.size(), 3u);
  expect_min_distance(pts, p);
}

TEST(PoissonDisk, MaximalNoPointCanBeAdded) {
  const auto p = one_class(3.0, 3);
  const glm::dvec2 lo{0, 0}, hi{150, 150};
  const Points pts = poisson_disk(lo, hi, p);
  // Probes away from the request's edges (points beyond them exist but are not returned).
  EXPECT_EQ(free_probes(pts, p, 0, lo + 6.0, hi - 6.0, 20000, 1), 0);
  // Without gap filling Bridson leaves room: the probe test can fail.
  auto q = p;
  q.fill_gaps = false;
  q.attempts = 2;
  const Points sparse = poisson_disk(lo, hi, q);
  EXPECT_GT(free_probes(sparse, q, 0, lo + 6.0, hi - 6.0, 20000, 1), 0);
}

TEST(PoissonDisk, MaximalForEveryClassAndWithDensity) {
  PoissonParams p;
  auto dens = density_field(0.3, 1.0);
  p.classes = {{2.0, 0, nullptr}, {5.0, 1, nullptr}};
  p.density = dens.get();
  p.cross_separation = 0.5;
  p.seed = 5;
  const glm::dvec2 lo{40, 0}, hi{160, 120};
  const Points pts = poisson_disk(lo, hi, p);
  const double margin = 2.0 * 5.0 / std::sqrt(0.1);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(free_probes(pts, p, k, lo + margin, hi - margin, 8000, 2 + k), 0) << k;
}

TEST(PoissonDisk, TileInvariantBitForBit) {
  PoissonParams p;
  auto dens = density_field(0.4, 0.9);
  p.classes = {{2.5, 0, nullptr}, {6.0, 1, nullptr}};
  p.density = dens.get();
  p.seed = 42;
  const glm::dvec2 lo{-300, -200}, hi{300, 250};
  const Points full = poisson_disk(lo, hi, p);
  for (const auto& [a, b] : std::vector<std::pair<glm::dvec2, glm::dvec2>>{{{-37.5, 12.25}, {61.0, 99.0}},
                                                                           {{-300, -200}, {-250, -120}},
                                                                           {{200, 100}, {300, 250}},
                                                                           {{0, 0}, {40, 40}}}) {
    const Points part = poisson_disk(a, b, p);
    const Points expected = inside(full, a, b);
    EXPECT_GT(part.size(), 10u);
    EXPECT_TRUE(same_points(part, expected)) << "tile [" << a.x << "," << a.y << "]-[" << b.x << "," << b.y
                                             << "]: " << part.size() << " vs " << expected.size();
  }
}

// One class of constant radius takes the sampler's fast path (chunk-aligned flat grid, cell-by-cell gap
// filling): the same guarantees, checked on it separately.
TEST(PoissonDisk, ConstantRadiusPathTileInvariantDeterministicAndMaximal) {
  const auto p = one_class(2.0, 19);
  const glm::dvec2 lo{-210, -130}, hi{190, 170};
  Points full;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    full = poisson_disk(lo, hi, p);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    EXPECT_TRUE(same_points(full, poisson_disk(lo, hi, p)));
  }
  for (const auto& [a, b] : std::vector<std::pair<glm::dvec2, glm::dvec2>>{
           {{-37.5, 12.25}, {61.0, 99.0}}, {{-210, -130}, {-150, -60}}, {{100, 100}, {190, 170}}, {{0, 0}, {16, 16}}}) {
    const Points part = poisson_disk(a, b, p);
    EXPECT_GT(part.size(), 10u);
    EXPECT_TRUE(same_points(part, inside(full, a, b))) << "tile [" << a.x << "," << a.y << "]";
  }
  const glm::dvec2 plo{-60, -60}, phi{60, 60};
  const Points part = poisson_disk(plo - 4.0, phi + 4.0, p);
  expect_min_distance(part, p);
  EXPECT_EQ(free_probes(part, p, 0, plo, phi, 20000, 9), 0);
  // Maximal Poisson-disk sampling covers about 0.7 points per r^2.
  const double per_r2 = static_cast<double>(inside(full, plo, phi).size()) / (120.0 * 120.0) * 4.0;
  EXPECT_GT(per_r2, 0.64);
  EXPECT_LT(per_r2, 0.76);
}

// fill_border off: the plane's sampling cropped to the domain, tile invariant. On (the default): the domain is
// sampled up to its edges, so a tile's points differ from the whole domain's near the tile's edges only.
TEST(PoissonDisk, NodeIsResolutionIndependentAndTileInvariant) {
  const Domain coarse = Domain::from_extent({1000, -500}, {400, 300}, {65, 49});
  const Domain fine = Domain::from_extent({1000, -500}, {400, 300}, {257, 193});
  const Domain tile = fine.subdomain(40, 30, 100, 80);
  for (const bool border : {false, true}) {
    const std::map<std::string, ParamValue> params{{"class_count", std::int64_t{2}},
                                                   {"radius_0", 6.0},
                                                   {"radius_1", 2.0},
                                                   {"seed", std::uint64_t{9}},
                                                   {"fill_border", border}};
    const auto a = run_node("PoissonDisk", coarse, params).get<Points>();
    const auto b = run_node("PoissonDisk", fine, params).get<Points>();
    EXPECT_GT(a->size(), 1000u);
    EXPECT_TRUE(same_points(*a, *b)) << border;
    const auto t = run_node("PoissonDisk", tile, params).get<Points>();
    const glm::dvec2 lo = tile.min_corner(), hi = tile.max_corner();
    if (!border) {
      EXPECT_TRUE(same_points(*t, inside(*b, lo, hi)));
      continue;
    }
    // The tile is sampled on its own up to its edges: its points stay inside, keep their distances, and are
    // more than the whole domain's sampling has inside the tile (those leave the tile's edges uncovered).
    for (const auto& q : t->position) EXPECT_TRUE(q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y);
    PoissonParams p;
    p.classes = {{6.0, 0, nullptr}, {2.0, 1, nullptr}};
    expect_min_distance(*t, p);
    EXPECT_GT(t->size(), inside(*b, lo, hi).size());
  }
}

// The node with one class: maximal on its domain, edges included (fill_border, the default).
TEST(PoissonDisk, NodeFillsItsDomainUpToTheEdges) {
  const Domain d = Domain::from_extent({-40, 25}, {90, 70}, {131, 71});
  const auto pts = run_node("PoissonDisk", d, {{"radius_0", 1.5}, {"seed", std::uint64_t{4}}}).get<Points>();
  EXPECT_GT(pts->size(), 1500u);
  const auto c = testing::empty_circles(positions(*pts), 1.5, d.min_corner(), d.max_corner(), testing::float_tolerance);
  EXPECT_EQ(c.interior + c.border, 0u) << c.worst_interior << " " << c.worst_border;
  EXPECT_GE(c.shortest, 1.5);
}

TEST(PoissonDisk, CrossClassSeparation) {
  PoissonParams p;
  p.classes = {{2.0, 0, nullptr}, {6.0, 1, nullptr}};
  p.seed = 3;
  auto closest_cross = [&](const Points& pts) {
    double best = INFINITY;
    for (std::size_t a = 0; a < pts.size(); ++a)
      for (std::size_t b = a + 1; b < pts.size(); ++b)
        if (pts.class_id[a] != pts.class_id[b])
          best =
              std::min(best, static_cast<double>(glm::length(glm::vec2(pts.position[a]) - glm::vec2(pts.position[b]))));
    return best;
  };
  for (double cross : {1.0, 0.5}) {
    p.cross_separation = cross;
    const Points pts = poisson_disk({0, 0}, {120, 120}, p);
    const double d = closest_cross(pts);
    EXPECT_GE(d, cross * 4.0) << cross;
    EXPECT_LT(d, cross * 4.0 * 1.5) << cross << ": maximal placement fills up to the separation";
    expect_min_distance(pts, p);
  }
  p.cross_separation = 0.0;
  EXPECT_LT(closest_cross(poisson_disk({0, 0}, {120, 120}, p)), 1.0);
  // Large classes first: the big class alone and with a small class has the same points.
  PoissonParams big = p;
  big.classes = {{6.0, 1, nullptr}};
  p.cross_separation = 1.0;
  const Points both = poisson_disk({0, 0}, {120, 120}, p);
  Points big_of_both;
  for (std::size_t i = 0; i < both.size(); ++i)
    if (both.class_id[i] == 1) big_of_both.add(both.position[i], 1);
  const Points alone = poisson_disk({0, 0}, {120, 120}, big);
  EXPECT_GT(alone.size(), 100u);
  EXPECT_GT(big_of_both.size(), alone.size() / 2);
}

TEST(PoissonDisk, CountsFollowTheDensity) {
  PoissonParams p = one_class(2.0, 8);
  auto dens = density_field(0.25, 1.0);  // x < 100: 0.25, else 1
  p.density = dens.get();
  const Points pts = poisson_disk({0, 0}, {200, 200}, p);
  int left = 0, right = 0;
  for (const auto& q : pts.position) {
    if (q.x > 10 && q.x < 90) ++left;
    if (q.x > 110 && q.x < 190) ++right;
  }
  const double ratio = static_cast<double>(left) / right;
  EXPECT_GT(right, 2000);
  EXPECT_NEAR(ratio, 0.25, 0.03) << left << " / " << right;
  // Uniform density 1: about 0.7 points per r^2 for maximal Poisson-disk sampling.
  const double per_r2 = right / (80.0 * 200.0) * 4.0;
  EXPECT_GT(per_r2, 0.6);
  EXPECT_LT(per_r2, 0.8);
}

TEST(PoissonDisk, MaskAndMinDensityRespected) {
  auto mask = density_field(0.0, 1.0);
  PoissonParams p = one_class(3.0);
  p.mask = mask.get();
  const Points pts = poisson_disk({0, 0}, {200, 100}, p);
  EXPECT_GT(pts.size(), 300u);
  for (const auto& q : pts.position) EXPECT_GE(mask->sample_world(q.x, q.y), 0.5f);
  auto low = density_field(0.05, 1.0);
  p.mask = nullptr;
  p.density = low.get();
  const Points dense_only = poisson_disk({0, 0}, {200, 100}, p);
  EXPECT_GT(dense_only.size(), 300u);
  for (const auto& q : dense_only.position) {
    EXPECT_GE(low->sample_world(q.x, q.y), 0.1f);  // min_density
    EXPECT_GT(q.x, 90.0f);
  }
}

TEST(PoissonDisk, DeterministicForAnyThreadCountAndSeedMatters) {
  PoissonParams p;
  auto dens = density_field(0.5, 1.0);
  p.classes = {{3.0, 0, nullptr}, {1.0, 1, nullptr}};
  p.density = dens.get();
  p.seed = 77;
  Points one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = poisson_disk({0, 0}, {300, 200}, p);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = poisson_disk({0, 0}, {300, 200}, p);
  }
  EXPECT_TRUE(same_points(one, many));
  p.seed = 78;
  EXPECT_FALSE(same_points(one, poisson_disk({0, 0}, {300, 200}, p)));
}

TEST(PoissonDisk, GuaranteeHoldsAtLargeCoordinates) {
  // 10 km from the origin a float step is ~1 mm: the radius still holds exactly on the stored floats.
  const auto p = one_class(0.5, 4);
  const Points pts = poisson_disk({10000, 10000}, {10030, 10020}, p);
  EXPECT_GT(pts.size(), 1000u);
  expect_min_distance(pts, p);
}

// Maximal sampling checked exactly, on the Delaunay triangulation of the output (testing::empty_circles): no
// spot of the rectangle, its edges included, is r or farther from every point, up to two float steps at the
// spot (the sampler stores float positions; a spot free by less may hold no free float). The fast path
// (one radius), bounded to the rectangle and unbounded (the plane's sampling, checked inside the request).
// The sampler before the farthest-spot step and the bounded mode failed this: the plane's sampling had 6 free
// interior spots here (by up to 0.63 mm at r = 1 m: gaps the darts missed), its crop 29 interior and 133
// border ones (by up to 0.56 m: the points that covered them lay beyond the edges).
TEST(PoissonDisk, MaximalOnTheDelaunayTriangulation) {
  const glm::dvec2 lo{-61.5, 20.25}, hi{58.5, 110.75};
  PoissonParams p = one_class(1.0, 23);
  const Points plane = poisson_disk(lo - 2.0, hi + 2.0, p);
  const auto a = testing::empty_circles(positions(plane), 1.0, lo, hi, testing::float_tolerance);
  EXPECT_EQ(a.interior, 0u) << "worst excess " << a.worst_interior << " m";
  EXPECT_EQ(a.border, 0u) << "worst excess " << a.worst_border << " m";
  EXPECT_GE(a.shortest, 1.0);
  p.bounded = true;
  p.bounds_lo = lo;
  p.bounds_hi = hi;
  const Points bounded = poisson_disk(lo, hi, p);
  EXPECT_GT(bounded.size(), 7000u);
  for (const auto& q : bounded.position) {
    EXPECT_TRUE(q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y);
  }
  const auto b = testing::empty_circles(positions(bounded), 1.0, lo, hi, testing::float_tolerance);
  EXPECT_EQ(b.interior, 0u) << "worst excess " << b.worst_interior << " m";
  EXPECT_EQ(b.border, 0u) << "worst excess " << b.worst_border << " m";
  EXPECT_GE(b.shortest, 1.0);
  // The cropped plane's sampling leaves the border free; the bounded one fills it, with more points.
  const auto crop = testing::empty_circles(positions(inside(plane, lo, hi)), 1.0, lo, hi, testing::float_tolerance);
  EXPECT_GT(crop.border, 0u);
  EXPECT_GT(bounded.size(), inside(plane, lo, hi).size());
  // Requests inside the same bounds get the bounded sampling's points there.
  const glm::dvec2 a0{-20.0, 30.0}, a1{10.0, 70.0};
  EXPECT_TRUE(same_points(poisson_disk(a0, a1, p), inside(bounded, a0, a1)));
}

// The checker itself: it finds a free spot in the interior, on an edge and at a corner.
TEST(PoissonDisk, EmptyCircleCheckFindsFreeSpots) {
  std::vector<glm::dvec2> grid;
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i) grid.emplace_back(i, j);  // spacing 1: empty circles of radius 0.707
  auto none = [](double, double) { return 0.0; };
  auto c = testing::empty_circles(grid, 0.75, {0, 0}, {10, 10}, none);
  EXPECT_EQ(c.interior + c.border, 0u);
  EXPECT_NEAR(c.worst_interior, std::sqrt(0.5) - 0.75, 1e-12);
  EXPECT_DOUBLE_EQ(c.shortest, 1.0);
  auto hole = grid;
  hole.erase(hole.begin() + 5 * 11 + 5);  // (5, 5): the circle through its 4 neighbours has radius 1
  c = testing::empty_circles(hole, 0.75, {0, 0}, {10, 10}, none);
  EXPECT_GE(c.interior, 1u);
  EXPECT_EQ(c.border, 0u);
  EXPECT_NEAR(c.worst_interior, 0.25, 1e-12);
  auto edge = grid;
  edge.erase(edge.begin() + 5);  // (5, 0): the spot (5, 0) is 1 from its neighbours
  c = testing::empty_circles(edge, 0.75, {0, 0}, {10, 10}, none);
  EXPECT_GE(c.border, 1u);
  EXPECT_NEAR(c.worst_border, 0.25, 1e-12);
  auto corner = grid;
  corner.erase(corner.begin());  // (0, 0)
  c = testing::empty_circles(corner, 0.75, {0, 0}, {10, 10}, none);
  EXPECT_GE(c.border, 1u);
  EXPECT_NEAR(c.worst_border, 1.0 - 0.75, 1e-12);
}

// Measurement (run by hand): free spots of the fast path's output on a square of side OROGEN_POISSON_SIDE
// (default 2000 m) at r = 5 m, seed 1 (the benchmark's parameters), cropped and bounded.
TEST(PoissonDisk, DISABLED_MeasureFreeSpots) {
  const char* env = std::getenv("OROGEN_POISSON_SIDE");
  const double side = env ? std::atof(env) : 2000.0, r = 5.0;
  PoissonParams p = one_class(r, 1);
  const glm::dvec2 lo{0, 0}, hi{side, side};
  auto report = [&](const char* what, const Points& pts, glm::dvec2 a, glm::dvec2 b) {
    const auto pos = positions(pts);
    const auto raw = testing::empty_circles(pos, r, a, b, [](double, double) { return 0.0; });
    const auto tol = testing::empty_circles(pos, r, a, b, testing::float_tolerance);
    std::printf(
        "%s: %zu points; free (>= r): %zu interior, %zu border; free by 2 float steps: %zu interior, %zu "
        "border; worst excess %.3g m interior, %.3g m border; shortest %.9g m\n",
        what, pts.size(), raw.interior, raw.border, tol.interior, tol.border, raw.worst_interior, raw.worst_border,
        raw.shortest);
  };
  const Points plane = poisson_disk(lo - 2.0 * r, hi + 2.0 * r, p);
  report("plane, checked inside [0, side]", plane, lo, hi);
  report("plane cropped to [0, side]", inside(plane, lo, hi), lo, hi);
  p.bounded = true;
  p.bounds_lo = lo;
  p.bounds_hi = hi;
  report("bounded to [0, side]", poisson_disk(lo, hi, p), lo, hi);
  // The general sampler: the same radius through a density field of 1 (radius constant, not the fast path).
  auto one = std::make_shared<Heightfield>(Domain::from_extent(lo - 400.0, hi - lo + 800.0, {65, 65}));
  for (float& v : one->data) v = 1.0f;
  p.density = one.get();
  report("general sampler, bounded to [0, side]", poisson_disk(lo, hi, p), lo, hi);
  // Its speed with a mask and two classes (CPU time of this thread, one thread).
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  auto mask = density_field(0.0, 1.0);
  PoissonParams q;
  q.classes = {{r, 0, nullptr}, {0.4 * r, 1, nullptr}};
  q.mask = mask.get();
  q.seed = 1;
  const std::clock_t t0 = std::clock();
  const std::size_t n = poisson_disk({0, 0}, {side / 4, side / 4}, q).size();
  std::printf("general sampler, 2 classes and a mask on [0, side / 4]: %zu points in %.0f ms of CPU\n", n,
              1000.0 * static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC);
}

TEST(PoissonDisk, RefusesWhatItCannotHonour) {
  EXPECT_THROW(poisson_disk({0, 0}, {1e5, 1e5}, one_class(0.01)), std::runtime_error);
  EXPECT_THROW(poisson_disk({9e11, 0}, {9e11 + 100, 100}, one_class(1.0)), std::runtime_error);
  EXPECT_THROW(poisson_disk({0, 0}, {10, 10}, one_class(0.0)), std::invalid_argument);
}

// A terrain: flat at 0 m for x < 0, flat at 200 m for x > 100, a ramp in between (slope 2).
std::shared_ptr<Heightfield> step_terrain() {
  auto h = std::make_shared<Heightfield>(Domain::from_extent({-300, -300}, {700, 600}, {141, 121}));
  for (int j = 0; j < h->height(); ++j)
    for (int i = 0; i < h->width(); ++i) h->at(i, j) = static_cast<float>(std::clamp(h->domain.x(i), 0.0, 100.0) * 2.0);
  return h;
}

// ScatterRules' ecosystems from its two tables, written as in a graph file.
std::vector<Ecosystem> ecosystems(const char* rows, const char* plants) {
  return ecosystems_from_tables(table_from_json_text(rows, ecosystem_schema()),
                                table_from_json_text(plants, ecosystem_plant_schema()));
}

TEST(ScatterRules, TableSelectsTheEcosystemByElevationAndSlope) {
  const auto h = step_terrain();
  EcosystemParams p;
  // Slopes in degrees: the flats are 0 deg, the ramp (rise 2 over run 1) atan(2) = 63.4 deg.
  p.ecosystems = ecosystems(
      R"([{"name": "low", "elevation": [-10, 10], "elevation_sharpness": 1e9, "slope": [0, 26.6],
           "slope_sharpness": 1e9},
          {"name": "high", "elevation": [150, 250], "elevation_sharpness": 1e9, "slope": [0, 26.6],
           "slope_sharpness": 1e9},
          {"name": "ramp", "slope": [56.3, 68.2], "slope_sharpness": 1e9}])",
      R"([{"ecosystem": "low", "class": 1, "density": 0.02, "scale": [1, 1]},
          {"ecosystem": "high", "class": 2, "density": 0.01, "scale": [2, 3]},
          {"ecosystem": "high", "class": 3, "density": 0.005, "scale": [0.5, 0.5]},
          {"ecosystem": "ramp", "class": 4, "density": 0.02, "scale": [1, 1]}])");
  p.seed = 1;
  TerrainVariables vars{h.get(), nullptr, nullptr};
  const Points pts = scatter_ecosystems({-200, -200}, {300, 200}, vars, p);
  std::map<int, int> counts;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& q = pts.position[i];
    const int c = pts.class_id[i];
    ++counts[c];
    if (c == 1) {
      EXPECT_LT(q.x, 0.5f);
    }
    if (c == 2 || c == 3) {
      EXPECT_GT(q.x, 99.5f);
    }
    if (c == 4) {
      EXPECT_TRUE(q.x > -0.5f && q.x < 100.5f) << q.x;
    }
    if (c == 2) {
      EXPECT_TRUE(pts.scale[i].x >= 2.0f && pts.scale[i].x <= 3.0f);
    }
    EXPECT_FLOAT_EQ(q.z, h->sample_world(q.x, q.y));
    // The ecosystem's ranges hold at every point.
    const auto& e = p.ecosystems[static_cast<std::size_t>(pts.attributes.at("ecosystem")[i])];
    EXPECT_GT(e.membership(vars.elevation(q.x, q.y), 0.0, vars.slope_at(q.x, q.y), 0.0), 0.0);
  }
  // Expected counts: density * area of the region each ecosystem covers (within 5 sigma of a Poisson count).
  auto near = [](int n, double expected) { EXPECT_NEAR(n, expected, 5.0 * std::sqrt(expected)) << expected; };
  near(counts[1], 0.02 * 200 * 400);
  near(counts[2], 0.01 * 200 * 400);
  near(counts[3], 0.005 * 200 * 400);
  near(counts[4], 0.02 * 100 * 400);
}

TEST(ScatterRules, OverlapSharesCandidatesByMembership) {
  // Two ecosystems that both hold everywhere: each keeps half of its candidates.
  auto h = step_terrain();
  EcosystemParams p;
  p.ecosystems = ecosystems(R"([{"name": "a"}, {"name": "b"}])",
                            R"([{"ecosystem": "a", "class": 0, "density": 0.02, "scale": [1, 1]},
                                {"ecosystem": "b", "class": 1, "density": 0.02, "scale": [1, 1]}])");
  TerrainVariables vars{h.get(), nullptr, nullptr};
  const Points pts = scatter_ecosystems({-200, -200}, {-100, 200}, vars, p);
  int a = 0;
  for (int c : pts.class_id) a += c == 0;
  const double expected = 0.5 * 0.02 * 100 * 400;
  EXPECT_NEAR(a, expected, 5.0 * std::sqrt(expected));
  EXPECT_NEAR(static_cast<double>(pts.size() - a), expected, 5.0 * std::sqrt(expected));
}

TEST(ScatterRules, SoftEdgesReachOnlyTheMargin) {
  const auto h = step_terrain();
  EcosystemParams p;
  p.ecosystems = ecosystems(R"([{"name": "mid", "elevation": [80, 120], "elevation_sharpness": 2}])",  // margin 20 m
                            R"([{"ecosystem": "mid", "class": 0, "density": 0.05, "scale": [1, 1]}])");
  TerrainVariables vars{h.get(), nullptr, nullptr};
  const Points pts = scatter_ecosystems({-200, -200}, {300, 200}, vars, p);
  for (const auto& q : pts.position) EXPECT_TRUE(q.z > 60.0f && q.z < 140.0f) << q.z;
  int inner = 0;
  for (const auto& q : pts.position) inner += q.z >= 80.0f && q.z <= 120.0f;
  EXPECT_GT(inner, 0);
  EXPECT_LT(inner, static_cast<int>(pts.size()));
}

TEST(ScatterRules, TileInvariantAndDeterministic) {
  const auto h = step_terrain();
  EcosystemParams p;
  p.ecosystems = ecosystems_from_tables(default_ecosystems(), default_ecosystem_plants());
  p.seed = 5;
  TerrainVariables vars{h.get(), nullptr, nullptr};
  const Points full = scatter_ecosystems({-200, -200}, {300, 200}, vars, p);
  EXPECT_GT(full.size(), 100u);
  const Points part = scatter_ecosystems({-13.3, 7}, {121, 88}, vars, p);
  EXPECT_TRUE(same_points(part, inside(full, {-13.3, 7}, {121, 88})));
  Points one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = scatter_ecosystems({-200, -200}, {300, 200}, vars, p);
  }
  EXPECT_TRUE(same_points(one, full));
  p.seed = 6;
  EXPECT_FALSE(same_points(full, scatter_ecosystems({-200, -200}, {300, 200}, vars, p)));
}

// The message of the std::invalid_argument `fn` throws ("" if none).
template <class Fn>
std::string invalid_argument_of(Fn&& fn) {
  try {
    fn();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ScatterRules, BadTablesAreClearErrors) {
  EXPECT_EQ(invalid_argument_of([] {
              ecosystems(R"([{"name": "a"}])", R"([{"ecosystem": "b", "class": 0, "density": 0.1, "scale": [1, 1]}])");
            }),
            "plants[0].ecosystem: 'b' is not an ecosystem of the ecosystems table");
  EXPECT_EQ(invalid_argument_of([] { ecosystems(R"([{"name": "a"}, {"name": "b", "skew_sharpness": 2}])", "[]"); }),
            "ecosystems[1].skew_sharpness: given without the range skew");
  EXPECT_EQ(invalid_argument_of([] {
              biome_entries_from_tables(
                  table_from_json_text(R"([{"biome": 1, "density": 0.5}])", biome_density_schema()),
                  table_from_json_text(R"([{"biome": 1, "class": 0, "weight": 1},
                                                                 {"biome": 2, "class": 1, "weight": 1}])",
                                       biome_species_schema()));
            }),
            "species[1].biome: 2 is not a biome of the biomes table");
  // Through the node: the same message, as a NodeError.
  const auto h = step_terrain();
  const TableValue stray = table_from_json_text(R"([{"ecosystem": "x", "class": 0, "density": 0.1, "scale": [1, 1]}])",
                                                ecosystem_plant_schema());
  try {
    run_node("ScatterRules", h->domain, {{"plants", stray}}, {{"in", PortValue(HeightfieldPtr(h))}});
    ADD_FAILURE() << "no error";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("plants[0].ecosystem: 'x'"), std::string::npos) << e.what();
  }
}

TEST(BiomeScatter, CountsAndSpeciesFollowTheBiomeTable) {
  // Biome 1 for x < 0, biome 2 for x >= 0.
  auto biome = std::make_shared<Heightfield>(Domain::from_extent({-200, -200}, {400, 400}, {101, 101}));
  for (int j = 0; j < biome->height(); ++j)
    for (int i = 0; i < biome->width(); ++i) biome->at(i, j) = biome->domain.x(i) < 0 ? 1.0f : 2.0f;
  BiomeScatterParams p;
  p.table = biome_entries_from_tables(
      table_from_json_text(R"([{"biome": 1, "density": 0.2}, {"biome": 2, "density": 0.5}])", biome_density_schema()),
      table_from_json_text(R"([{"biome": 1, "class": 0, "weight": 1}, {"biome": 1, "class": 1, "weight": 3},
                               {"biome": 2, "class": 2, "weight": 1}])",
                           biome_species_schema()));
  p.factor = 0.8;
  p.cell_size = 2.0;
  const Points pts = scatter_biomes({-150, -150}, {150, 150}, *biome, nullptr, p);
  std::map<int, int> counts;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ++counts[pts.class_id[i]];
    if (pts.class_id[i] == 2)
      EXPECT_GE(pts.position[i].x, -4.0f);
    else
      EXPECT_LE(pts.position[i].x, 4.0f);
  }
  const double cells_left = 75.0 * 150.0;  // 150 m x 300 m in 2 m cells
  auto near = [](int n, double expected) { EXPECT_NEAR(n, expected, 5.0 * std::sqrt(expected)) << expected; };
  near(counts[0], cells_left * 0.16 * 0.25);
  near(counts[1], cells_left * 0.16 * 0.75);
  near(counts[2], cells_left * 0.4);
}

Points scene_points() {
  Points pts;
  for (int i = 0; i < 30; ++i) {
    const auto k = pts.add({10.0f * i, -5.0f * i, 100.0f + i}, i % 3);
    pts.rotation[k] = glm::angleAxis(0.1f * i, glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f)));
    pts.scale[k] = glm::vec3(1.0f + 0.1f * i, 1.0f, 2.0f);
  }
  return pts;
}

tinygltf::Model load_gltf(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? loader.LoadBinaryFromFile(&m, &err, &warn, path.string())
                                             : loader.LoadASCIIFromFile(&m, &err, &warn, path.string());
  EXPECT_TRUE(ok) << err;
  EXPECT_TRUE(err.empty()) << err;
  return m;
}

const float* accessor_floats(const tinygltf::Model& m, int index) {
  const auto& a = m.accessors.at(index);
  const auto& v = m.bufferViews.at(a.bufferView);
  return reinterpret_cast<const float*>(m.buffers.at(v.buffer).data.data() + v.byteOffset + a.byteOffset);
}

// A scene from points and class meshes, through the Instance node.
ScenePtr instance(const std::shared_ptr<Points>& pts, const std::map<int, MeshPtr>& meshes,
                  std::map<std::string, ParamValue> params = {}) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {3, 3});
  std::map<std::string, PortValue> inputs{{"in", PortValue(PointsPtr(pts))}};
  for (const auto& [cls, mesh] : meshes) inputs["mesh_" + std::to_string(cls)] = PortValue(mesh);
  return run_node("Instance", d, params, inputs).get<Scene>();
}

TEST(Instance, OneInstancePerPointWithItsTransformAndClassMesh) {
  const auto pts = std::make_shared<Points>(scene_points());
  pts->attribute("age", 0.0f)[4] = 7.0f;
  const MeshPtr a = proxy_mesh(), b = std::make_shared<Mesh>();
  const auto scene = instance(
      pts, {{0, a}, {1, b}, {2, a}, {5, b}},
      {{"names",
        table_from_json_text(R"([{"class": 0, "name": "tree"}, {"class": 2, "name": "rock"}])", class_name_schema())}});
  ASSERT_NO_THROW(scene->check_consistent());
  // Nothing filtered: the instances are the points themselves, shared, not copied.
  EXPECT_EQ(scene->instances.get(), pts.get());
  ASSERT_EQ(scene->size(), pts->size());
  for (std::size_t i = 0; i < pts->size(); ++i) {
    EXPECT_EQ(scene->instances->position[i], pts->position[i]);
    EXPECT_EQ(scene->instances->rotation[i], pts->rotation[i]);
    EXPECT_EQ(scene->instances->scale[i], pts->scale[i]);
    EXPECT_EQ(scene->instances->class_id[i], pts->class_id[i]);
  }
  EXPECT_EQ(scene->instances->attributes.at("age")[4], 7.0f);
  // Every connected mesh is a class, under its slot's class id, named as given or class_<id>.
  ASSERT_EQ(scene->classes.size(), 4u);
  EXPECT_EQ(scene->classes.at(0).mesh, a);
  EXPECT_EQ(scene->classes.at(1).mesh, b);
  EXPECT_EQ(scene->classes.at(2).mesh, a);
  EXPECT_EQ(scene->classes.at(5).mesh, b);
  EXPECT_EQ(scene->classes.at(0).name, "tree");
  EXPECT_EQ(scene->classes.at(1).name, "class_1");
  EXPECT_EQ(scene->classes.at(2).name, "rock");
  EXPECT_EQ(scene->classes.at(5).name, "class_5");
  for (const auto& [cls, c] : scene->classes) EXPECT_FALSE(c.proxy) << cls;
  EXPECT_EQ(scene->count(0), 10u);
  EXPECT_EQ(scene->count(5), 0u);
}

TEST(Instance, ClassWithoutAMeshIsAnErrorAProxyOrLeftOut) {
  const auto pts = std::make_shared<Points>(scene_points());  // classes 0, 1, 2; ten points each
  const MeshPtr rock = proxy_mesh();
  try {
    instance(pts, {{0, rock}, {2, rock}});
    FAIL() << "class 1 has no mesh";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("class 1 has 10 points but no mesh: connect mesh_1"), std::string::npos)
        << e.what();
  }
  const auto proxied = instance(pts, {{0, rock}}, {{"missing_mesh", std::string("proxy")}});
  EXPECT_EQ(proxied->size(), 30u);
  ASSERT_EQ(proxied->classes.size(), 3u);
  EXPECT_FALSE(proxied->classes.at(0).proxy);
  EXPECT_TRUE(proxied->classes.at(1).proxy);
  EXPECT_TRUE(proxied->classes.at(2).proxy);
  EXPECT_EQ(proxied->classes.at(1).mesh->vertex_count(), 6u);
  const auto skipped = instance(pts, {{2, rock}}, {{"missing_mesh", std::string("skip")}});
  ASSERT_EQ(skipped->size(), 10u);
  EXPECT_EQ(skipped->classes.size(), 1u);
  std::size_t j = 0;
  for (std::size_t i = 0; i < pts->size(); ++i) {
    if (pts->class_id[i] != 2) continue;
    EXPECT_EQ(skipped->instances->position[j], pts->position[i]);
    EXPECT_EQ(skipped->instances->rotation[j], pts->rotation[i]);
    EXPECT_EQ(skipped->instances->scale[j], pts->scale[i]);
    ++j;
  }
  ASSERT_NO_THROW(skipped->check_consistent());
  // No points at all: an empty scene, not an error.
  EXPECT_EQ(instance(std::make_shared<Points>(), {})->size(), 0u);
}

TEST(Instance, SceneSurvivesTheCacheSerialization) {
  const auto pts = std::make_shared<Points>(scene_points());
  const auto scene = instance(
      pts, {{0, proxy_mesh()}},
      {{"missing_mesh", std::string("proxy")},
       {"names",
        table_from_json_text(R"([{"class": 0, "name": "a"}, {"class": 1, "name": "b"}])", class_name_schema())}});
  const PortValue back = deserialize_value(serialize_value(PortValue(scene)));
  const auto& s = *std::get<ScenePtr>(back);
  ASSERT_EQ(s.size(), pts->size());
  EXPECT_EQ(s.instances->position, pts->position);
  EXPECT_EQ(s.instances->class_id, pts->class_id);
  ASSERT_EQ(s.classes.size(), 3u);
  EXPECT_EQ(s.classes.at(1).name, "b");
  EXPECT_EQ(s.classes.at(2).name, "class_2");
  EXPECT_TRUE(s.classes.at(2).proxy);
  EXPECT_FALSE(s.classes.at(0).proxy);
  EXPECT_EQ(s.classes.at(0).mesh->face_count(), 8u);
  // A scene whose instances name a class it has no mesh for is refused.
  Scene broken;
  broken.instances = pts;
  broken.classes[0] = SceneClass{"a", proxy_mesh(), false};
  EXPECT_THROW(deserialize_value(serialize_value(PortValue(ScenePtr(std::make_shared<Scene>(broken))))),
               SerializationError);
}

TEST(WriteScene, GpuInstancesLoadBackWithTheirTransforms) {
  const auto dir = test::scratch_dir("scatter-scene");
  OutputPolicy policy;
  policy.output_dir = dir;
  const auto pts = std::make_shared<Points>(scene_points());
  const MeshPtr rock = proxy_mesh();
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {3, 3});
  const auto scene = instance(pts, {{0, rock}, {2, rock}}, {{"missing_mesh", std::string("skip")}});
  for (const std::string file : {"s.glb", "s.gltf"}) {
    run_node("WriteScene", d, {{"path", file}, {"ground", std::string("keep")}},
             {{"in", PortValue(scene)}, {"terrain", PortValue(rock)}}, policy);
    const auto m = load_gltf(dir / file);
    ASSERT_EQ(m.scenes.size(), 1u);
    EXPECT_EQ(std::count(m.extensionsUsed.begin(), m.extensionsUsed.end(), "EXT_mesh_gpu_instancing"), 1);
    // Required: a viewer without it must not show each class's mesh once at the origin (glTF's fallback).
    EXPECT_EQ(std::count(m.extensionsRequired.begin(), m.extensionsRequired.end(), "EXT_mesh_gpu_instancing"), 1);
    int instanced_nodes = 0;
    std::size_t instances = 0;
    for (const auto& n : m.nodes) {
      const auto it = n.extensions.find("EXT_mesh_gpu_instancing");
      if (it == n.extensions.end()) continue;
      ++instanced_nodes;
      const int cls = n.extras.Get("class_id").GetNumberAsInt();
      EXPECT_EQ(n.name, "class_" + std::to_string(cls));
      const auto& attrs = it->second.Get("attributes");
      const int t = attrs.Get("TRANSLATION").GetNumberAsInt();
      const int r = attrs.Get("ROTATION").GetNumberAsInt();
      const int sc = attrs.Get("SCALE").GetNumberAsInt();
      const std::size_t count = m.accessors[t].count;
      EXPECT_EQ(m.accessors[r].count, count);
      EXPECT_EQ(m.accessors[sc].count, count);
      const float* tp = accessor_floats(m, t);
      const float* rp = accessor_floats(m, r);
      const float* sp = accessor_floats(m, sc);
      std::size_t j = 0;
      for (std::size_t i = 0; i < pts->size(); ++i) {
        if (pts->class_id[i] != cls) continue;
        ASSERT_LT(j, count);
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(tp[3 * j + c], pts->position[i][c]);
          EXPECT_EQ(sp[3 * j + c], pts->scale[i][c]);
        }
        EXPECT_EQ(rp[4 * j + 0], pts->rotation[i].x);
        EXPECT_EQ(rp[4 * j + 1], pts->rotation[i].y);
        EXPECT_EQ(rp[4 * j + 2], pts->rotation[i].z);
        EXPECT_EQ(rp[4 * j + 3], pts->rotation[i].w);
        ++j;
      }
      EXPECT_EQ(j, count);
      instances += count;
    }
    EXPECT_EQ(instanced_nodes, 2);  // classes 0 and 2; class 1 has no mesh and was skipped
    EXPECT_EQ(instances, 20u);
  }
}

TEST(WriteScene, NodeInstancesOnePerPointNamedByClass) {
  const auto dir = test::scratch_dir("scatter-scene-nodes");
  OutputPolicy policy;
  policy.output_dir = dir;
  const auto pts = std::make_shared<Points>(scene_points());
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {3, 3});
  const auto scene =
      instance(pts, {{1, proxy_mesh()}},
               {{"missing_mesh", std::string("proxy")},
                {"names", table_from_json_text(R"([{"class": 0, "name": "tree"}, {"class": 1, "name": "bush"},
                                                                   {"class": 2, "name": "rock"}])",
                                               class_name_schema())}});
  run_node("WriteScene", d, {{"path", std::string("n.gltf")}, {"instancing", std::string("nodes")}},
           {{"in", PortValue(scene)}}, policy);
  const auto m = load_gltf(dir / "n.gltf");
  std::size_t instance_nodes = 0;
  for (const auto& n : m.nodes)
    if (n.mesh >= 0 && n.translation.size() == 3) ++instance_nodes;
  EXPECT_EQ(instance_nodes, pts->size());  // proxies for classes 0 and 2
  std::map<std::string, std::size_t> groups;
  for (const auto& n : m.nodes)
    if (n.extras.Has("class_id")) groups[n.name] = n.children.size();
  EXPECT_EQ(groups, (std::map<std::string, std::size_t>{{"bush", 10}, {"rock", 10}, {"tree", 10}}));
  ASSERT_EQ(m.meshes.size(), 3u);
  // The root turns z-up into y-up.
  const auto& root = m.nodes[m.scenes[0].nodes[0]];
  ASSERT_EQ(root.rotation.size(), 4u);
  EXPECT_NEAR(root.rotation[0], -std::sqrt(0.5), 1e-12);
}

TEST(SceneNodes, EveryParameterAndInputChangesTheKey) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  for (const char* type : {"Instance", "WriteScene"}) {
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
}

TEST(ProjectToTerrain, SetsHeightAndAlignsToTheNormal) {
  auto h = std::make_shared<Heightfield>(Domain::from_extent({0, 0}, {100, 100}, {51, 51}));
  for (int j = 0; j < h->height(); ++j)
    for (int i = 0; i < h->width(); ++i)
      h->at(i, j) = static_cast<float>(0.5 * h->domain.x(i) + 3.0);  // slope 0.5 in x
  auto pts = std::make_shared<Points>();
  pts->add({20, 30, 0});
  pts->add({70, 10, 0});
  const auto out = run_node("ProjectToTerrain", h->domain, {{"align", 1.0}, {"offset", 1.0}},
                            {{"in", PortValue(PointsPtr(pts))}, {"height", PortValue(HeightfieldPtr(h))}})
                       .get<Points>();
  EXPECT_NEAR(out->position[0].z, 0.5 * 20 + 3 + 1, 1e-4);
  EXPECT_NEAR(out->position[1].z, 0.5 * 70 + 3 + 1, 1e-4);
  const glm::vec3 up = out->rotation[0] * glm::vec3(0, 0, 1);
  const glm::vec3 n = glm::normalize(glm::vec3(-0.5f, 0.0f, 1.0f));
  EXPECT_NEAR(glm::dot(up, n), 1.0f, 1e-5f);
}

TEST(MergePoints, ConcatenatesWithAttributes) {
  auto a = std::make_shared<Points>();
  a->add({1, 2, 3}, 4);
  a->attribute("age")[0] = 7;
  auto b = std::make_shared<Points>();
  b->add({5, 6, 7}, 1);
  b->add({8, 9, 10}, 2);
  b->attribute("radius", 2.0f);
  const auto out =
      run_node("MergePoints", Domain{}, {}, {{"a", PortValue(PointsPtr(a))}, {"b", PortValue(PointsPtr(b))}})
          .get<Points>();
  out->check_consistent();
  ASSERT_EQ(out->size(), 3u);
  EXPECT_EQ(out->class_id[2], 2);
  EXPECT_EQ(out->attributes.at("age")[0], 7.0f);
  EXPECT_EQ(out->attributes.at("age")[1], 0.0f);
  EXPECT_EQ(out->attributes.at("radius")[0], 0.0f);
  EXPECT_EQ(out->attributes.at("radius")[2], 2.0f);
}

TEST(ProjectToTerrain, FunctionOnAPlaneKeepsOffTerrainPointsAndBlendsTheTilt) {
  // z = 0.25 x - 0.5 y + 2 on [0, 40]^2: normal (-0.25, 0.5, 1) normalized.
  Heightfield h(Domain::from_extent({0, 0}, {40, 40}, {41, 41}));
  for (int j = 0; j < 41; ++j)
    for (int i = 0; i < 41; ++i) h.at(i, j) = static_cast<float>(0.25 * h.domain.x(i) - 0.5 * h.domain.y(j) + 2.0);
  Points in;
  in.add({10, 20, 5}, 1);
  in.add({33.5f, 7.25f, 0}, 2);
  in.add({500, 500, 9}, 3);  // beyond the terrain: the height at the nearest border, a flat gradient
  in.attribute("age")[1] = 4.0f;
  ProjectParams p;
  p.offset = -1.5;
  const Points flat = project_to_terrain(in, h, p);
  flat.check_consistent();
  EXPECT_NEAR(flat.position[0].z, 0.25 * 10 - 0.5 * 20 + 2 - 1.5, 1e-5);
  EXPECT_NEAR(flat.position[1].z, 0.25 * 33.5 - 0.5 * 7.25 + 2 - 1.5, 1e-5);
  EXPECT_NEAR(flat.position[2].z, 0.25 * 40 - 0.5 * 40 + 2 - 1.5, 1e-5);
  EXPECT_EQ(flat.position[1].x, 33.5f);
  EXPECT_EQ(flat.class_id, in.class_id);
  EXPECT_EQ(flat.attributes.at("age")[1], 4.0f);
  for (const auto& r : flat.rotation) EXPECT_EQ(r, glm::quat(1, 0, 0, 0)) << "align 0 keeps the rotation";
  const glm::dvec3 n = glm::normalize(glm::dvec3(-0.25, 0.5, 1.0));
  const double full = std::acos(n.z);  // angle between up and the normal
  for (double align : {0.5, 1.0}) {
    p.align = align;
    const Points tilted = project_to_terrain(in, h, p);
    const glm::vec3 up = tilted.rotation[0] * glm::vec3(0, 0, 1);
    // The up axis turns by align x the full angle, in the plane of +z and the normal.
    EXPECT_NEAR(std::acos(std::clamp(static_cast<double>(up.z), -1.0, 1.0)), align * full, 1e-5) << align;
    EXPECT_NEAR(glm::dot(glm::dvec3(up), glm::cross(glm::dvec3(0, 0, 1), n)), 0.0, 1e-6) << align;
    const glm::vec3 beyond = tilted.rotation[2] * glm::vec3(0, 0, 1);
    EXPECT_NEAR(beyond.z, 1.0f, 1e-6f) << "no slope beyond the border: upright";
  }
  // A point's own rotation is kept under the tilt (applied after it).
  in.rotation[0] = glm::angleAxis(0.7f, glm::vec3(0, 0, 1));
  p.align = 1.0;
  const Points yawed = project_to_terrain(in, h, p);
  const glm::vec3 up = yawed.rotation[0] * glm::vec3(0, 0, 1);
  EXPECT_NEAR(glm::dot(glm::dvec3(up), n), 1.0, 1e-6);
  const glm::vec3 fwd = yawed.rotation[0] * glm::vec3(1, 0, 0);
  EXPECT_GT(fwd.y, 0.5f) << "the yaw of 0.7 rad survives";
}

TEST(MergePoints, FunctionKeepsOrderSkipsNullAndFillsMissingAttributesWithZero) {
  Points a, b, c;
  a.add({1, 2, 3}, 4);
  a.attribute("age")[0] = 7;
  b.add({5, 6, 7}, 1);
  b.add({8, 9, 10}, 2);
  b.rotation[1] = glm::quat(0, 1, 0, 0);
  b.scale[0] = {2, 3, 4};
  b.attribute("radius", 2.0f);
  c.add({-1, -2, -3}, 9);
  c.attribute("age")[0] = 11;
  const Points out = merge_points({&a, nullptr, &b, &c});
  out.check_consistent();
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out.position[0], glm::vec3(1, 2, 3));
  EXPECT_EQ(out.position[2], glm::vec3(8, 9, 10));
  EXPECT_EQ(out.position[3], glm::vec3(-1, -2, -3));
  EXPECT_EQ(out.class_id, (std::vector<std::int32_t>{4, 1, 2, 9}));
  EXPECT_EQ(out.rotation[2], glm::quat(0, 1, 0, 0));
  EXPECT_EQ(out.scale[1], glm::vec3(2, 3, 4));
  EXPECT_EQ(out.attributes.at("age"), (std::vector<float>{7, 0, 0, 11}));
  EXPECT_EQ(out.attributes.at("radius"), (std::vector<float>{0, 2, 2, 0}));
  EXPECT_EQ(merge_points({}).size(), 0u);
}

TEST(ShadePlacement, FunctionKeepsByPreferenceCarriesPointDataAndShadesAllAtNight) {
  Points tree;
  tree.add({0, 0, 0});
  Points cand;
  cand.add({0, 10, 0}, 5);   // in the shadow (sun in the south at 45 degrees, crown 10 m up)
  cand.add({0, -10, 0}, 6);  // lit
  cand.add({2, 10, 0}, 7);   // in the shadow
  cand.scale[2] = {3, 3, 3};
  cand.rotation[2] = glm::quat(0, 0, 0, 1);
  cand.attribute("age")[2] = 12.0f;
  cand.attribute("shade")[0] = 0.5f;  // an input shade attribute is replaced
  const Domain d = Domain::from_extent({-20, -20}, {40, 40}, {41, 41});
  ShadePlacementParams p;
  p.canopy.crown_radius = 3.0;
  p.canopy.crown_height = 10.0;
  p.canopy.sun = sun_direction(180.0, 45.0);
  const ShadePlacementResult shade = shade_placement(cand, tree, d, nullptr, p);
  shade.points.check_consistent();
  ASSERT_EQ(shade.points.size(), 2u);
  EXPECT_EQ(shade.points.class_id, (std::vector<std::int32_t>{5, 7}));
  EXPECT_EQ(shade.points.scale[1], glm::vec3(3, 3, 3));
  EXPECT_EQ(shade.points.rotation[1], glm::quat(0, 0, 0, 1));
  EXPECT_EQ(shade.points.attributes.at("age")[1], 12.0f);
  EXPECT_EQ(shade.points.attributes.at("shade"), (std::vector<float>{1, 1}));
  // The map: 1 exactly where a candidate at that sample would be shaded.
  const Canopy canopy(tree, p.canopy);
  ASSERT_EQ(shade.shade.domain.resolution, d.resolution);
  for (int j = 0; j < 41; ++j)
    for (int i = 0; i < 41; ++i)
      EXPECT_EQ(shade.shade.at(i, j), canopy.shaded(d.x(i), d.y(j), 0.0) ? 1.0f : 0.0f) << i << "," << j;
  p.preference = ShadePreference::Sun;
  const ShadePlacementResult sun = shade_placement(cand, tree, d, nullptr, p);
  ASSERT_EQ(sun.points.size(), 1u);
  EXPECT_EQ(sun.points.class_id[0], 6);
  EXPECT_EQ(sun.points.attributes.at("shade")[0], 0.0f);
  p.preference = ShadePreference::Any;
  EXPECT_EQ(shade_placement(cand, tree, d, nullptr, p).points.attributes.at("shade"), (std::vector<float>{1, 0, 1}));
  // A sun under the horizon: night, every candidate and every sample shaded.
  p.canopy.sun = glm::dvec3(0.0, -1.0, -0.2);
  const ShadePlacementResult night = shade_placement(cand, tree, d, nullptr, p);
  EXPECT_EQ(night.points.attributes.at("shade"), (std::vector<float>{1, 1, 1}));
  for (float v : night.shade.data) EXPECT_EQ(v, 1.0f);
}

TEST(ShadePlacement, ShadowOfOneCrownIsTheExpectedEllipse) {
  // One crown of radius 3 m centred 10 m above the origin; sun in the south at 45 degrees: on flat ground the
  // shadow is an ellipse centred 10 m north, semi-axes 3 m (east) and 3 / sin 45 = 4.243 m (north).
  Points tree;
  tree.add({0, 0, 0});
  CanopyParams cp;
  cp.crown_radius = 3.0;
  cp.crown_height = 10.0;
  cp.sun = sun_direction(180.0, 45.0);
  const Canopy canopy(tree, cp);
  EXPECT_TRUE(canopy.shaded(0, 10, 0));
  EXPECT_FALSE(canopy.shaded(0, -10, 0));
  EXPECT_TRUE(canopy.shaded(0, 10 + 4.1, 0));
  EXPECT_FALSE(canopy.shaded(0, 10 + 4.4, 0));
  EXPECT_TRUE(canopy.shaded(0, 10 - 4.1, 0));
  EXPECT_FALSE(canopy.shaded(0, 10 - 4.4, 0));
  EXPECT_TRUE(canopy.shaded(2.9, 10, 0));
  EXPECT_FALSE(canopy.shaded(3.1, 10, 0));
  // Higher ground is closer to the crown: at z = 5 the shadow centre is 5 m north.
  EXPECT_TRUE(canopy.shaded(0, 5, 5));
  EXPECT_FALSE(canopy.shaded(0, 10, 5 + 4.0));
}

// Crowns of random sizes and heights over rolling ground; candidates among them.
struct Grove {
  Points casters, candidates;
};
Grove random_grove(std::uint32_t seed, double extent, int casters, int candidates) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(0.0f, static_cast<float>(extent)), size(0.3f, 1.6f), ground(0.0f, 12.0f);
  Grove g;
  for (int k = 0; k < casters; ++k) {
    const std::size_t i = g.casters.add({at(rng), at(rng), ground(rng)});
    const float s = size(rng);
    g.casters.scale[i] = {s, s, size(rng)};
  }
  for (int k = 0; k < candidates; ++k) g.candidates.add({at(rng), at(rng), ground(rng)});
  return g;
}

// max_shadow_distance: a point is shaded exactly when a crown whose center lies within that horizontal distance
// meets the ray toward the sun (0: any crown), checked against every crown in turn.
TEST(ShadePlacement, ShadowDistanceKeepsTheCrownsWithinItAndNoOther) {
  const Grove g = random_grove(5, 200.0, 120, 3000);
  std::vector<std::size_t> counts;  // shaded candidates at each distance
  for (const double distance : {0.0, 6.0, 25.0}) {
    ShadePlacementParams p;
    p.preference = ShadePreference::Any;
    p.canopy.crown_radius = 3.0;
    p.canopy.crown_height = 9.0;
    p.canopy.sun = sun_direction(200.0, 20.0);
    p.canopy.max_shadow_distance = distance;
    const Domain d = Domain::from_extent({0, 0}, {200, 200}, {21, 21});
    const auto r = shade_placement(g.candidates, g.casters, d, nullptr, p);
    ASSERT_EQ(r.points.size(), g.candidates.size());
    const glm::dvec3 sun = glm::normalize(p.canopy.sun);
    std::size_t shaded = 0;
    for (std::size_t i = 0; i < g.candidates.size(); ++i) {
      const glm::dvec3 q = g.candidates.position[i];
      bool expected = false;
      for (std::size_t c = 0; c < g.casters.size() && !expected; ++c) {
        const glm::dvec3 centre(g.casters.position[c].x, g.casters.position[c].y,
                                g.casters.position[c].z + p.canopy.crown_height * g.casters.scale[c].z);
        const double radius = p.canopy.crown_radius * std::abs(g.casters.scale[c].x);
        const glm::dvec3 w = centre - q;
        if (distance > 0 && w.x * w.x + w.y * w.y > distance * distance) continue;
        const double along = glm::dot(w, sun);
        expected = (along < 0.0 ? glm::dot(w, w) : glm::dot(w, w) - along * along) < radius * radius;
      }
      ASSERT_EQ(r.points.attributes.at("shade")[i], expected ? 1.0f : 0.0f) << "candidate " << i << " at " << distance;
      shaded += expected;
    }
    counts.push_back(shaded);
  }
  // Shadows longer than 6 m are cut (the sun at 20 degrees casts a crown 9 m up about 25 m away); 25 m keeps most.
  EXPECT_GT(counts[1], 20u);
  EXPECT_LT(counts[1], counts[2]);
  EXPECT_LT(counts[2], counts[0]);
  EXPECT_GT(counts[2], counts[0] / 2);
}

// With max_shadow_distance the node has a local reach: a tile expanded by its halo, given the points inside the
// expansion as a tiled build gives them, computes the tile's shadow map and the shade of its candidates as the
// whole domain does, bit for bit.
TEST(ShadePlacement, ATileWithItsHaloShadesAsTheWholeDomain) {
  const Grove g = random_grove(9, 300.0, 300, 4000);
  const Domain whole = Domain::from_extent({0, 0}, {300, 300}, {151, 151});
  auto height = std::make_shared<Heightfield>(whole);
  for (int j = 0; j < whole.height(); ++j)
    for (int i = 0; i < whole.width(); ++i)
      height->at(i, j) = static_cast<float>(6.0 + 5.0 * std::sin(whole.x(i) / 37.0) * std::cos(whole.y(j) / 53.0));
  const std::map<std::string, ParamValue> params{{"crown_radius", 3.0},         {"crown_height", 9.0},
                                                 {"sun_elevation", 25.0},       {"sun_azimuth", 160.0},
                                                 {"max_shadow_distance", 30.0}, {"preference", std::string("any")}};
  const NodeType& type = *NodeRegistry::instance().find("ShadePlacement");
  std::vector<ParamValue> effective;
  for (const auto& decl : type.params)
    effective.push_back(params.count(decl.name) ? params.at(decl.name) : decl.default_value);
  const Reach reach = type.reach_for(effective);
  ASSERT_EQ(reach.kind, ReachKind::Local);
  EXPECT_EQ(type.distribution_for(effective), Distribution::PerTile);
  const glm::ivec2 halo = reach.halo(whole.spacing);
  const auto points = [](const Points& p) { return PortValue(PointsPtr(std::make_shared<Points>(p))); };
  const auto all = run_node("ShadePlacement", whole, params,
                            {{"in", points(g.candidates)}, {"casters", points(g.casters)}, {"height", height}});
  const auto& all_map = *all.get<Heightfield>(1);
  const auto& all_points = *all.get<Points>(0);
  double shaded = 0;
  for (const float v : all_map.data) shaded += v;
  EXPECT_GT(shaded, 0.05 * static_cast<double>(all_map.data.size()));
  const glm::ivec2 tile{50, 50}, size{50, 50};
  const Domain expanded = whole.subdomain(tile.x - halo.x, tile.y - halo.y, size.x + 2 * halo.x, size.y + 2 * halo.y);
  const auto crop = [&](const Points& p) { return crop_points_to_domain(points(p), whole, expanded); };
  const auto part = run_node("ShadePlacement", expanded, params,
                             {{"in", crop(g.candidates)}, {"casters", crop(g.casters)}, {"height", height}});
  const auto& part_map = *part.get<Heightfield>(1);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i)
      ASSERT_EQ(part_map.at(halo.x + i, halo.y + j), all_map.at(tile.x + i, tile.y + j)) << i << "," << j;
  // The tile's candidates carry the shade the whole domain gives them.
  const Domain own = whole.subdomain(tile.x, tile.y, size.x, size.y);
  std::map<std::pair<float, float>, float> expected;
  for (std::size_t i = 0; i < all_points.size(); ++i)
    if (all_points.position[i].x >= own.min_corner().x && all_points.position[i].x <= own.max_corner().x &&
        all_points.position[i].y >= own.min_corner().y && all_points.position[i].y <= own.max_corner().y)
      expected[{all_points.position[i].x, all_points.position[i].y}] = all_points.attributes.at("shade")[i];
  const auto& part_points = *part.get<Points>(0);
  std::size_t matched = 0;
  for (std::size_t i = 0; i < part_points.size(); ++i) {
    const auto it = expected.find({part_points.position[i].x, part_points.position[i].y});
    if (it == expected.end()) continue;
    EXPECT_EQ(part_points.attributes.at("shade")[i], it->second);
    ++matched;
  }
  EXPECT_EQ(matched, expected.size());
  EXPECT_GT(matched, 50u);
}

TEST(ShadePlacement, NodeKeepsShadeLoversInShadeAndOthersInSun) {
  auto trees = std::make_shared<Points>();
  trees->add({0, 0, 0});
  trees->add({40, 40, 0});
  auto cand = std::make_shared<Points>();
  for (int j = 0; j <= 70; ++j)
    for (int i = 0; i <= 70; ++i) cand->add({-10.0f + i, -10.0f + j, 0.0f}, 3);
  const Domain d = Domain::from_extent({-10, -10}, {70, 70}, {71, 71});
  const std::map<std::string, PortValue> in{{"in", PortValue(PointsPtr(cand))},
                                            {"casters", PortValue(PointsPtr(trees))}};
  const std::map<std::string, ParamValue> params{{"crown_radius", 3.0}, {"crown_height", 10.0}};
  const auto shade = run_node("ShadePlacement", d, params, in);
  auto sun_params = params;
  sun_params["preference"] = std::string("sun");
  const auto sun = run_node("ShadePlacement", d, sun_params, in);
  const auto shaded = shade.get<Points>(0);
  const auto lit = sun.get<Points>(0);
  EXPECT_EQ(shaded->size() + lit->size(), cand->size());
  // Two ellipses of area pi * 3 * 4.243 on a 1 m lattice.
  EXPECT_NEAR(static_cast<double>(shaded->size()), 2 * 3.14159 * 3 * 4.243, 12.0);
  for (const auto& q : shaded->position) {
    const bool near_a = std::hypot(q.x / 3.0, (q.y - 10.0) / 4.243) < 1.0 + 1e-3;
    const bool near_b = std::hypot((q.x - 40) / 3.0, (q.y - 50.0) / 4.243) < 1.0 + 1e-3;
    EXPECT_TRUE(near_a || near_b) << q.x << "," << q.y;
  }
  for (float v : shaded->attributes.at("shade")) EXPECT_EQ(v, 1.0f);
  for (float v : lit->attributes.at("shade")) EXPECT_EQ(v, 0.0f);
  // The shadow map agrees with the point test.
  const auto map = shade.get<Heightfield>(1);
  double sum = 0;
  for (float v : map->data) sum += v;
  EXPECT_EQ(sum, static_cast<double>(shaded->size()));
}

Points initial_forest(int n, std::uint64_t seed) {
  Points p;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 200.0);
  for (int i = 0; i < n; ++i) p.add({static_cast<float>(u(rng)), static_cast<float>(u(rng)), 0.0f}, i % 2);
  return p;
}

TEST(ForestLifeCycle, AgesScalesAndCompetitionHold) {
  LifeCycleParams p;
  p.years = 60;
  p.lo = {0, 0};
  p.hi = {200, 200};
  p.seed = 3;
  p.seed_probability = 0.3;
  const Points forest = forest_life_cycle(initial_forest(150, 1), p);
  forest.check_consistent();
  ASSERT_GT(forest.size(), 50u);
  const auto& age = forest.attributes.at("age");
  bool young = false;
  for (std::size_t i = 0; i < forest.size(); ++i) {
    EXPECT_LE(age[i], p.max_age);
    EXPECT_GE(forest.scale[i].x, p.min_scale - 1e-6);
    EXPECT_LE(forest.scale[i].x, p.max_scale + 1e-6);
    EXPECT_NEAR(forest.scale[i].x, p.min_scale + std::min(1.0, age[i] / p.maturity_age) * (p.max_scale - p.min_scale),
                1e-5);
    young = young || age[i] < 60;
    const auto& q = forest.position[i];
    EXPECT_TRUE(q.x >= 0 && q.x <= 200 && q.y >= 0 && q.y <= 200);
  }
  EXPECT_TRUE(young) << "seeds germinated during the run";
  // Survivors keep the competition spacing (so the population is bounded by a disk packing).
  for (std::size_t a = 0; a < forest.size(); ++a)
    for (std::size_t b = a + 1; b < forest.size(); ++b) {
      const double d = glm::length(glm::dvec2(forest.position[a]) - glm::dvec2(forest.position[b]));
      EXPECT_GE(d, p.competition * 0.5 * (forest.scale[a].x + forest.scale[b].x) - 1e-3);
    }
  const double spacing = p.competition * p.min_scale;
  EXPECT_LT(forest.size(), 200.0 * 200.0 / (0.5 * spacing * spacing));
}

TEST(ForestLifeCycle, SameSeedSameForestAndSuitabilityRespected) {
  LifeCycleParams p;
  p.years = 40;
  p.lo = {0, 0};
  p.hi = {200, 200};
  p.seed_probability = 0.5;
  auto suit = std::make_shared<Heightfield>(Domain::from_extent({0, 0}, {200, 200}, {41, 41}));
  for (int j = 0; j < suit->height(); ++j)
    for (int i = 0; i < suit->width(); ++i) suit->at(i, j) = suit->domain.x(i) < 100 ? 1.0f : 0.0f;
  p.suitability = suit.get();
  const Points initial = initial_forest(100, 2);
  const Points a = forest_life_cycle(initial, p);
  const Points b = forest_life_cycle(initial, p);
  EXPECT_TRUE(same_points(a, b));
  EXPECT_EQ(a.attributes.at("age"), b.attributes.at("age"));
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.attributes.at("age")[i] < 40) {
      EXPECT_LT(a.position[i].x, 100.5f) << "a seedling on unsuitable ground";
    }
  p.seed = 1;
  EXPECT_FALSE(same_points(a, forest_life_cycle(initial, p)));
  // Without seeds the population only shrinks.
  p.seed_probability = 0.0;
  p.max_age = 1000;
  EXPECT_LE(forest_life_cycle(initial, p).size(), initial.size());
}

TEST(ShadePlacement, SunFromPlaceAndTimeMatchesItsAnglesAndNightShadesEverything) {
  // Cooper's declination: about +23.45 deg at the June solstice, -23.45 at the December one, 0 near the equinoxes.
  EXPECT_NEAR(climate::declination_for_day(172), 23.45, 0.05);
  EXPECT_NEAR(climate::declination_for_day(355), -23.45, 0.05);
  EXPECT_NEAR(climate::declination_for_day(81), 0.0, 0.5);
  auto trees = std::make_shared<Points>();
  trees->add({0, 0, 0});
  auto cand = std::make_shared<Points>();
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i) cand->add({-20.0f + i, -20.0f + j, 0.0f}, 3);
  const Domain d = Domain::from_extent({-20, -20}, {40, 40}, {41, 41});
  const std::map<std::string, PortValue> in{{"in", PortValue(PointsPtr(cand))},
                                            {"casters", PortValue(PointsPtr(trees))}};
  // At solar noon at 45 N on day 100 the sun is due south at 90 - 45 + declination degrees.
  const double decl = climate::declination_for_day(100);
  const std::map<std::string, ParamValue> by_time{{"crown_radius", 3.0},
                                                  {"crown_height", 10.0},
                                                  {"sun", std::string("time")},
                                                  {"latitude", 45.0},
                                                  {"day_of_year", std::int64_t{100}},
                                                  {"hour", 12.0}};
  const std::map<std::string, ParamValue> by_angles{
      {"crown_radius", 3.0}, {"crown_height", 10.0}, {"sun_azimuth", 180.0}, {"sun_elevation", 45.0 + decl}};
  const auto a = run_node("ShadePlacement", d, by_time, in).get<Points>(0);
  const auto b = run_node("ShadePlacement", d, by_angles, in).get<Points>(0);
  ASSERT_GT(a->size(), 10u);
  ASSERT_EQ(a->size(), b->size());
  for (std::size_t k = 0; k < a->size(); ++k) EXPECT_EQ(a->position[k], b->position[k]);
  // The shadow falls north of the tree (the sun in the south).
  for (const auto& q : a->position) EXPECT_GT(q.y, 0.0f);
  // At midnight there is no direct sun: every candidate is in the shade, and so is the whole map.
  auto night = by_time;
  night["hour"] = 0.0;
  const auto n = run_node("ShadePlacement", d, night, in);
  EXPECT_EQ(n.get<Points>(0)->size(), cand->size());
  for (float v : n.get<Heightfield>(1)->data) EXPECT_EQ(v, 1.0f);
}
// A 100 m square mesh tilted as z = 0.2 x + 10 with a skirt 50 m down its west edge, and instances placed on a
// flat heightfield at 0 (one sunk by 0.3 m): grounded, each follows the plane, keeping its offset when the
// heightfield is given; one outside the mesh keeps its z.
TEST(MeshSurface, GroundsInstancesOnTheTopSurfaceKeepingTheirOffsets) {
  TriMesh m;
  const auto a = m.add_vertex({0, 0, 10}), b = m.add_vertex({100, 0, 30}), c = m.add_vertex({100, 100, 30}),
             d = m.add_vertex({0, 100, 10}), e = m.add_vertex({0, 0, -40}), f = m.add_vertex({0, 100, -40});
  m.add_face(a, b, c);
  m.add_face(a, c, d);
  m.add_face(a, d, f);  // the skirt: vertical, covers no area
  m.add_face(a, f, e);
  const MeshSurface surface(m);
  EXPECT_NEAR(*surface.height_at(50, 50), 20.0, 1e-9);
  EXPECT_NEAR(*surface.height_at(0, 37), 10.0, 1e-9);  // on the edge above the skirt: the top
  EXPECT_NEAR(*surface.height_at(100, 100), 30.0, 1e-9);
  EXPECT_FALSE(surface.height_at(101, 50));
  Points pts;
  pts.add({25, 60, 0});
  pts.add({75, 10, -0.3f});
  pts.add({150, 10, 5});
  Heightfield flat(Domain::from_extent({0, 0}, {100, 100}, {11, 11}));
  const Points kept = ground_on_surface(pts, surface, &flat);
  EXPECT_NEAR(kept.position[0].z, 15.0, 1e-4);
  EXPECT_NEAR(kept.position[1].z, 25.0 - 0.3, 1e-4);
  EXPECT_EQ(kept.position[2].z, 5.0f);
  const Points onto = ground_on_surface(pts, surface, nullptr);
  EXPECT_NEAR(onto.position[1].z, 25.0, 1e-4);
  EXPECT_EQ(onto.position[1].x, 75.0f);
}
}  // namespace
}  // namespace orogen
