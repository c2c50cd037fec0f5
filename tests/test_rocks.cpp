// Hull rocks: convex, closed (V - E + F = 2), hull vertices among the input points, at most N vertices,
// outward faces, deterministic per seed; refinement keeps the surface closed; RockSet makes K closed rocks.
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "evaluator/run_node.h"
#include "graph/mesh.h"
#include "graph/points.h"
#include "nodes/rocks/hull_rock.h"
#include "nodes/rocks/rock_set.h"
#include "support/key_checks.h"

namespace orogen::rocks {
namespace {

struct Check {
  long euler = 0;
  bool closed = true;
  double max_outside = 0.0;  // largest distance of a vertex in front of a face plane (convexity)
  double min_outward = 1e9;  // smallest (face normal . (face centre - centroid)) (outward faces)
};

Check check(const Hull& h) {
  Check c;
  std::set<std::pair<int, int>> directed;
  for (const auto& f : h.faces)
    for (int k = 0; k < 3; ++k)
      if (!directed.insert({f[k], f[(k + 1) % 3]}).second) c.closed = false;  // an edge used twice the same way
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) c.closed = false;  // every edge has its twin
  c.euler =
      static_cast<long>(h.vertices.size()) - static_cast<long>(directed.size() / 2) + static_cast<long>(h.faces.size());
  glm::dvec3 centroid(0.0);
  for (const auto& v : h.vertices) centroid += v;
  centroid /= static_cast<double>(h.vertices.size());
  for (const auto& f : h.faces) {
    const glm::dvec3 a = h.vertices[f[0]], b = h.vertices[f[1]], cc = h.vertices[f[2]];
    const glm::dvec3 n = glm::normalize(glm::cross(b - a, cc - a));
    for (const auto& v : h.vertices) c.max_outside = std::max(c.max_outside, glm::dot(n, v - a));
    c.min_outward = std::min(c.min_outward, glm::dot(n, (a + b + cc) / 3.0 - centroid));
  }
  return c;
}

TEST(HullRock, ConvexClosedOutwardAndMadeOfInputPoints) {
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    HullRockOptions o;
    o.seed = seed;
    o.points = 20 + static_cast<int>(seed % 3) * 40;
    const auto pts = rock_points(o);
    ASSERT_EQ(pts.size(), static_cast<std::size_t>(o.points));
    const Hull h = hull_rock(o);
    const Check c = check(h);
    EXPECT_TRUE(c.closed) << seed;
    EXPECT_EQ(c.euler, 2) << seed;
    EXPECT_LE(c.max_outside, 1e-9) << seed;
    EXPECT_GT(c.min_outward, 0.0) << seed;
    EXPECT_LE(h.vertices.size(), pts.size());
    for (const auto& v : h.vertices) EXPECT_NE(std::find(pts.begin(), pts.end(), v), pts.end()) << seed;
    // Points not on the hull are inside it.
  }
}

TEST(HullRock, PointsLieOnTheEllipsoidWithoutNoise) {
  HullRockOptions o;
  o.sigma = 0.0;
  o.radii = {2.0, 1.0, 0.5};
  o.points = 2000;
  const auto pts = rock_points(o);
  double mean_abs_z = 0.0;
  for (const auto& p : pts) {
    EXPECT_NEAR(p.x * p.x / 4.0 + p.y * p.y + p.z * p.z / 0.25, 1.0, 1e-9);
    mean_abs_z += std::abs(p.z);
  }
  // Area-uniform: the mean |z| over the surface of this ellipsoid is 0.29304 (numerical quadrature of
  // |z| dA / A); a uniform direction mapped by the radii would give c / 2 = 0.25. Standard error ~ 0.003.
  EXPECT_NEAR(mean_abs_z / pts.size(), 0.29304, 0.012);
}

TEST(HullRock, DeterministicPerSeed) {
  HullRockOptions a, b;
  a.seed = b.seed = 17;
  EXPECT_EQ(hull_rock(a).vertices, hull_rock(b).vertices);
  b.seed = 18;
  EXPECT_NE(hull_rock(a).vertices, hull_rock(b).vertices);
  b.seed = 17;
  b.variant = 1;
  EXPECT_NE(hull_rock(a).vertices, hull_rock(b).vertices);
}

TEST(HullRock, RefinementStaysClosed) {
  HullRockOptions o;
  o.subdivisions = 2;
  o.displacement = 0.08;
  o.wavelength = 0.3;
  const Hull h = hull_rock(o);
  const Check c = check(h);
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.euler, 2);
  HullRockOptions flat = o;
  flat.displacement = 0.0;
  flat.subdivisions = 0;
  EXPECT_EQ(h.faces.size(), hull_rock(flat).faces.size() * 16);
}

TEST(HullRock, DegenerateInputIsRejected) {
  std::vector<glm::dvec3> plane;
  for (int k = 0; k < 10; ++k) plane.emplace_back(std::cos(k), std::sin(k), 0.0);
  EXPECT_THROW(convex_hull_cgal(plane), std::invalid_argument);
  EXPECT_THROW(convex_hull_cgal({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), std::invalid_argument);
}

double volume(const Hull& h) {
  double v = 0.0;
  for (const auto& f : h.faces) v += glm::dot(h.vertices[f[0]], glm::cross(h.vertices[f[1]], h.vertices[f[2]])) / 6.0;
  return v;
}

std::vector<glm::dvec3> sorted(std::vector<glm::dvec3> v) {
  std::sort(v.begin(), v.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
  });
  return v;
}

// The small-set hull against CGAL on 10^5 sets: random in a cube and rock samples (80%) (general position: the
// same vertices and face count), lattice points with duplicates and coplanar runs, and flat sets
// (degenerate: the same volume, every input inside, or both rejected).
TEST(SmallHull, MatchesCgalOn100kSets) {
  std::uint64_t state = 88172645463325252ull;
  auto next = [&] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  int general = 0, degenerate = 0, rejected = 0;
  for (int k = 0; k < 100000; ++k) {
    std::vector<glm::dvec3> pts;
    const int kind = k % 10 < 4 ? 0 : k % 10 < 8 ? 1 : k % 10 == 8 ? 2 : 3;  // CGAL is slow on degenerate sets
    const int n = 4 + static_cast<int>(next() * (kind == 1 ? 37 : 21));
    if (kind == 0) {
      for (int i = 0; i < n; ++i) pts.emplace_back(next() * 2 - 1, next() * 2 - 1, next() * 2 - 1);
    } else if (kind == 1) {
      HullRockOptions o;
      o.points = n;
      o.seed = static_cast<std::uint64_t>(k);
      pts = rock_points(o);
    } else if (kind == 2) {
      for (int i = 0; i < n; ++i)  // a 3x3x3 lattice: coplanar faces, collinear edges, duplicates
        pts.emplace_back(std::floor(next() * 3), std::floor(next() * 3), std::floor(next() * 3));
    } else {
      const bool flat = next() < 0.3;
      for (int i = 0; i < n; ++i) {
        const double x = next(), y = next();
        pts.emplace_back(x, y, flat ? 0.5 * x - 0.25 * y : (i % 3 == 0 ? next() : 0.0));
      }
      if (next() < 0.5) pts.push_back(pts.front());  // a duplicate
    }
    bool cgal_ok = true, small_ok = true;
    Hull a, b;
    try {
      a = convex_hull_cgal(pts);
    } catch (const std::invalid_argument&) {
      cgal_ok = false;
    }
    try {
      b = convex_hull_small(pts);
    } catch (const std::invalid_argument&) {
      small_ok = false;
    }
    ASSERT_EQ(cgal_ok, small_ok) << "set " << k << " n " << pts.size() << " cgal volume "
                                 << (cgal_ok ? volume(a) : -1.0) << " faces " << a.faces.size() << " vertices "
                                 << a.vertices.size();
    if (!cgal_ok) {
      ++rejected;
      continue;
    }
    if (k % 16 < 4) {  // the full check on a sample (it costs more than the hulls)
      const Check c = check(b);
      ASSERT_TRUE(c.closed) << "set " << k;
      ASSERT_EQ(c.euler, 2) << "set " << k;
      ASSERT_LE(c.max_outside, 1e-9) << "set " << k;
    }
    ASSERT_NEAR(volume(a), volume(b), 1e-9 * std::max(1.0, std::abs(volume(a)))) << "set " << k;
    if (kind <= 1) {
      ++general;
      ASSERT_EQ(sorted(a.vertices), sorted(b.vertices)) << "set " << k;
      ASSERT_EQ(a.faces.size(), b.faces.size()) << "set " << k;
    } else {
      ++degenerate;
      if (k % 16 < 4)
        for (const auto& q : pts)  // every input inside the small hull
          for (const auto& f : b.faces) {
            const glm::dvec3 nrm =
                glm::normalize(glm::cross(b.vertices[f[1]] - b.vertices[f[0]], b.vertices[f[2]] - b.vertices[f[0]]));
            ASSERT_LE(glm::dot(nrm, q - b.vertices[f[0]]), 1e-9) << "set " << k;
          }
    }
  }
  EXPECT_EQ(general, 80000);
  EXPECT_GT(degenerate, 15000);
  EXPECT_GT(rejected, 1000);
}

TEST(RockSet, VariantsInARowWithoutOverlapCentersAndRadiiInThePlacements) {
  RockSetParams p;
  p.count = 6;
  p.variation = 0.4;
  p.spacing = 0.25;
  p.rock.points = 24;
  p.rock.seed = 17;
  p.color = {0.1f, 0.2f, 0.3f, 1.0f};
  TriMesh mesh;
  Points places;
  append_rock_set(mesh, places, p);
  places.check_consistent();
  ASSERT_EQ(places.size(), 6u);
  const long euler =
      static_cast<long>(mesh.n_vertices()) - static_cast<long>(mesh.n_edges()) + static_cast<long>(mesh.n_faces());
  EXPECT_EQ(euler, 12) << "six closed rocks";
  double previous_right = -1e9;
  for (int k = 0; k < 6; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    EXPECT_EQ(places.class_id[uk], k);
    EXPECT_EQ(places.position[uk].y, 0.0f);
    EXPECT_EQ(places.position[uk].z, 0.0f);
    // The radii are the base radii scaled by the variant's factors, within 1 +- variation.
    glm::dvec3 radii = p.rock.radii;
    for (int a = 0; a < 3; ++a) {
      const double f = 1.0 + p.variation * (2.0 * variant_uniform(p.rock.seed, uk, a) - 1.0);
      EXPECT_GE(f, 1.0 - p.variation);
      EXPECT_LE(f, 1.0 + p.variation);
      radii[a] *= f;
    }
    EXPECT_FLOAT_EQ(places.scale[uk].x, static_cast<float>(radii.x));
    EXPECT_FLOAT_EQ(places.scale[uk].z, static_cast<float>(radii.z));
    // Each variant's extent [x - half, x + half] starts `spacing` after the previous one ends (0 first).
    const double half = std::max({radii.x, radii.y, radii.z}) + 3.0 * p.rock.sigma + p.rock.displacement;
    const double x = places.position[uk].x;
    if (k == 0) {
      EXPECT_EQ(x, 0.0);
    } else {
      EXPECT_NEAR(x - half, previous_right + p.spacing, 1e-5);
    }
    previous_right = x + half;
  }
  // Every vertex lies near its variant (within the largest radius plus 6 sigma of noise) and has the color.
  for (auto v : mesh.vertices()) {
    const auto q = mesh.point(v);
    double best = 1e9;
    for (std::size_t k = 0; k < 6; ++k) best = std::min<double>(best, std::abs(q[0] - places.position[k].x));
    EXPECT_LT(best, 1.0 * (1.0 + p.variation) + 6.0 * p.rock.sigma);
    EXPECT_EQ(mesh.color(v), TriMesh::Color(0.1f, 0.2f, 0.3f, 1.0f));
  }
  // Variant k is the hull rock keyed by k with its scaled radii: the vertex counts add up.
  std::size_t vertices = 0;
  for (int k = 0; k < 6; ++k) {
    HullRockOptions o = p.rock;
    o.variant = static_cast<std::uint64_t>(k);
    for (int a = 0; a < 3; ++a)
      o.radii[a] *= 1.0 + p.variation * (2.0 * variant_uniform(p.rock.seed, o.variant, a) - 1.0);
    vertices += hull_rock(o).vertices.size();
  }
  EXPECT_EQ(mesh.n_vertices(), vertices);
  // A variant without a hull is named.
  p.rock.sigma = 0.0;
  p.rock.radii = {1.0, 1.0, 0.0};
  TriMesh flat;
  Points flat_places;
  try {
    append_rock_set(flat, flat_places, p);
    ADD_FAILURE() << "a flat rock set was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("rock 0: ", 0), 0u) << e.what();
  }
}

TEST(RockNodes, EveryParameterChangesTheKey) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  expect_every_param_changes_key("HullRock", d);
  expect_every_param_changes_key("RockSet", d);
}

TEST(RockNodes, HullRockAndRockSet) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const auto rock = run_node("HullRock", d, {{"points", std::int64_t(30)}}).get<Mesh>();
  const long e = static_cast<long>(rock->mesh.n_vertices()) - static_cast<long>(rock->mesh.n_edges()) +
                 static_cast<long>(rock->mesh.n_faces());
  EXPECT_EQ(e, 2);
  EXPECT_LE(rock->vertex_count(), 30u);
  const auto set = run_node("RockSet", d, {{"count", std::int64_t(5)}});
  const auto mesh = set.get<Mesh>(0);
  const auto places = set.get<Points>(1);
  EXPECT_EQ(places->size(), 5u);
  const long e5 = static_cast<long>(mesh->mesh.n_vertices()) - static_cast<long>(mesh->mesh.n_edges()) +
                  static_cast<long>(mesh->mesh.n_faces());
  EXPECT_EQ(e5, 10);  // five spheres
  for (auto h : mesh->mesh.halfedges()) ASSERT_FALSE(mesh->mesh.is_boundary(h));
}

}  // namespace
}  // namespace orogen::rocks
