// The island family: clipped Voronoi diagrams and Lloyd relaxation (against brute-force nearest-site
// references), the Voronoi island's properties (ocean, lakes, elevation distribution, rivers, moisture, biomes,
// determinism) and its rendering (bounds, resolution independence, thread-count determinism), plus the node
// contract (cache keys).
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "field_ops_fixtures.h"
#include "graph/curves.h"
#include "graph/polygon_map.h"
#include "graph/registry.h"
#include "nodes/island/island.h"
#include "nodes/island/island_raster.h"
#include "nodes/island/river_curves.h"
#include "nodes/island/river_network.h"
#include "nodes/island/voronoi.h"
#include "support/key_checks.h"

namespace orogen {
namespace {

using namespace island;

std::vector<glm::dvec2> random_sites(int n, glm::dvec2 lo, glm::dvec2 size, std::uint64_t seed) {
  IslandParams p;
  p.min_corner = lo;
  p.size = size;
  p.cells = n;
  p.distribution = SiteDistribution::Uniform;
  p.seed = seed;
  return island_sites(p);
}

int brute_nearest(const std::vector<glm::dvec2>& sites, glm::dvec2 p) {
  int best = 0;
  double bd = 1e300;
  for (std::size_t i = 0; i < sites.size(); ++i) {
    const glm::dvec2 d = sites[i] - p;
    const double d2 = glm::dot(d, d);
    if (d2 < bd) {
      bd = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

bool inside_convex(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double tol) {
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const glm::dvec2 a = poly[k], b = poly[(k + 1) % poly.size()];
    const glm::dvec2 e = b - a;
    if ((e.x * (p.y - a.y) - e.y * (p.x - a.x)) / std::max(1e-300, glm::length(e)) < -tol) return false;
  }
  return true;
}

const std::vector<float>& cattr(const PolygonMap& m, const char* n) { return m.cell_attributes.at(n); }
const std::vector<float>& qattr(const PolygonMap& m, const char* n) { return m.corner_attributes.at(n); }

// ---------------------------------------------------------------------------------------------------------
// Voronoi diagram

TEST(IslandVoronoi, CellsTileTheRectangleAndAreConvex) {
  for (const auto& [lo, size] : {std::pair{glm::dvec2(0, 0), glm::dvec2(1000, 1000)},
                                 std::pair{glm::dvec2(-3.5e6, 2e6), glm::dvec2(3000, 1200)}}) {
    const auto sites = random_sites(400, lo, size, 5);
    const PolygonMap map = voronoi_diagram(sites, lo, lo + size);
    EXPECT_NO_THROW(map.check_consistent());
    ASSERT_EQ(map.cells.size(), sites.size());
    double total = 0.0;
    for (std::size_t c = 0; c < map.cells.size(); ++c) {
      const auto poly = cell_polygon(map, static_cast<int>(c));
      ASSERT_GE(poly.size(), 3u);
      const double a = polygon_area(poly);
      EXPECT_GT(a, 0.0) << "cell " << c << " is not counter-clockwise";
      total += a;
      for (std::size_t k = 0; k < poly.size(); ++k) {  // convex: every turn is to the left
        const glm::dvec2 u = poly[(k + 1) % poly.size()] - poly[k],
                         v = poly[(k + 2) % poly.size()] - poly[(k + 1) % poly.size()];
        EXPECT_GE(u.x * v.y - u.y * v.x, -1e-9 * glm::dot(size, size)) << "cell " << c;
      }
      EXPECT_TRUE(inside_convex(poly, map.cells[c].centre, 1e-9 * size.x)) << "site outside its cell " << c;
      for (const auto& q : poly) {
        EXPECT_GE(q.x, lo.x);
        EXPECT_LE(q.x, lo.x + size.x);
        EXPECT_GE(q.y, lo.y);
        EXPECT_LE(q.y, lo.y + size.y);
      }
    }
    EXPECT_NEAR(total, size.x * size.y, 1e-9 * size.x * size.y);
    // Neighbours are symmetric; border edges lie on the rectangle.
    for (std::size_t c = 0; c < map.cells.size(); ++c)
      for (int d : map.cells[c].neighbours) {
        const auto& nb = map.cells[static_cast<std::size_t>(d)].neighbours;
        EXPECT_NE(std::find(nb.begin(), nb.end(), static_cast<int>(c)), nb.end());
      }
    for (const auto& e : map.edges)
      if (e.cells[1] < 0) {
        EXPECT_TRUE(map.corners[static_cast<std::size_t>(e.corners[0])].border);
        EXPECT_TRUE(map.corners[static_cast<std::size_t>(e.corners[1])].border);
      }
  }
}

TEST(IslandVoronoi, EveryPointLiesInTheCellOfItsNearestSite) {
  const glm::dvec2 lo(100, 50), size(800, 600);
  const auto sites = random_sites(150, lo, size, 11);
  const PolygonMap map = voronoi_diagram(sites, lo, lo + size);
  std::vector<glm::dvec2> snapped;
  for (const auto& c : map.cells) snapped.push_back(c.centre);
  const CellLocator locator(map);
  for (int j = 0; j <= 60; ++j)
    for (int i = 0; i <= 80; ++i) {
      const glm::dvec2 p = lo + size * glm::dvec2(i / 80.0, j / 60.0);
      const int c = brute_nearest(snapped, p);
      EXPECT_TRUE(inside_convex(cell_polygon(map, c), p, 1e-6)) << "point " << p.x << "," << p.y;
      const int found = locator.find(p);
      const double df = glm::length(snapped[static_cast<std::size_t>(found)] - p),
                   dc = glm::length(snapped[static_cast<std::size_t>(c)] - p);
      EXPECT_LE(df, dc + 1e-9);
    }
}

TEST(IslandVoronoi, FewSitesAndCoincidentSites) {
  const glm::dvec2 lo(0, 0), hi(10, 10);
  const std::vector<glm::dvec2> one{{3, 4}};
  const PolygonMap m1 = voronoi_diagram(one, lo, hi);
  ASSERT_EQ(m1.cells.size(), 1u);
  EXPECT_NEAR(polygon_area(cell_polygon(m1, 0)), 100.0, 1e-9);
  EXPECT_EQ(m1.cells[0].corners.size(), 4u);
  // A regular lattice: many four-point circles, still no zero-length edges.
  std::vector<glm::dvec2> grid;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) grid.push_back({(i + 0.5) * 10.0 / 6.0, (j + 0.5) * 10.0 / 6.0});
  const PolygonMap mg = voronoi_diagram(grid, lo, hi);
  for (std::size_t c = 0; c < mg.cells.size(); ++c) {
    EXPECT_EQ(mg.cells[c].corners.size(), 4u) << c;
    EXPECT_NEAR(polygon_area(cell_polygon(mg, static_cast<int>(c))), 100.0 / 36.0,
                1e-7);  // sites snap to 2^-30 of the map
  }
  for (const auto& e : mg.edges)
    EXPECT_GT(glm::length(mg.corners[static_cast<std::size_t>(e.corners[0])].position -
                          mg.corners[static_cast<std::size_t>(e.corners[1])].position),
              1e-6);
  // A thin strip: the sites' near-border mirrors alone are collinear (regression: all sites are mirrored then).
  const std::vector<glm::dvec2> strip{{0.98, 4.2e6}};
  const PolygonMap ms = voronoi_diagram(strip, {0, 0}, {1, 1e7});
  EXPECT_NEAR(polygon_area(cell_polygon(ms, 0)), 1e7, 1e-2);
  EXPECT_EQ(lloyd_relax(strip, {0, 0}, {1, 1e7}, 2).size(), 1u);
  const std::vector<glm::dvec2> twice{{3, 4}, {3, 4}};
  EXPECT_THROW(voronoi_diagram(twice, lo, hi), std::runtime_error);
  const std::vector<glm::dvec2> outside{{11, 4}};
  EXPECT_THROW(voronoi_diagram(outside, lo, hi), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------------------
// Lloyd relaxation

double area_variance(const PolygonMap& m) {
  std::vector<double> a;
  for (std::size_t c = 0; c < m.cells.size(); ++c) a.push_back(polygon_area(cell_polygon(m, static_cast<int>(c))));
  const double mean = std::accumulate(a.begin(), a.end(), 0.0) / static_cast<double>(a.size());
  double v = 0.0;
  for (double x : a) v += (x - mean) * (x - mean);
  return v / static_cast<double>(a.size());
}

double mean_centroid_distance(const PolygonMap& m) {
  double s = 0.0;
  for (std::size_t c = 0; c < m.cells.size(); ++c)
    s += glm::length(polygon_centroid(cell_polygon(m, static_cast<int>(c))) - m.cells[c].centre);
  return s / static_cast<double>(m.cells.size());
}

TEST(IslandLloyd, EnergyAreaVarianceAndCentroidDistanceDecrease) {
  const glm::dvec2 lo(0, 0), hi(2000, 1500);
  auto sites = random_sites(600, lo, hi - lo, 21);
  std::vector<double> energy;
  std::vector<double> variance, distance;
  std::vector<glm::dvec2> s = sites;
  for (int pass = 0; pass <= 4; ++pass) {
    const PolygonMap m = voronoi_diagram(s, lo, hi);
    variance.push_back(area_variance(m));
    distance.push_back(mean_centroid_distance(m));
    if (pass < 4) s = lloyd_relax(s, lo, hi, 1);
  }
  const auto relaxed = lloyd_relax(sites, lo, hi, 4, &energy);
  ASSERT_EQ(energy.size(), 5u);
  for (std::size_t k = 1; k < energy.size(); ++k) {
    EXPECT_LT(energy[k], energy[k - 1]) << "pass " << k;
    EXPECT_LT(distance[k], distance[k - 1]) << "pass " << k;
    EXPECT_LT(variance[k], variance[k - 1]) << "pass " << k;
  }
  // Relaxation in several calls equals one call with several passes.
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(glm::length(s[i] - relaxed[i]), 0.0, 1e-6);
  // The centroidal energy itself against a numerical integral over a fine grid.
  const PolygonMap m = voronoi_diagram(relaxed, lo, hi);
  double brute = 0.0;
  const int nx = 800, ny = 600;
  std::vector<glm::dvec2> centres;
  for (const auto& c : m.cells) centres.push_back(c.centre);
  const double cell_area = (hi.x - lo.x) / nx * (hi.y - lo.y) / ny;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const glm::dvec2 p = lo + (hi - lo) * glm::dvec2((i + 0.5) / nx, (j + 0.5) / ny);
      const glm::dvec2 d = centres[static_cast<std::size_t>(brute_nearest(centres, p))] - p;
      brute += glm::dot(d, d) * cell_area;
    }
  EXPECT_NEAR(centroidal_energy(m), brute, 2e-3 * brute);
}

TEST(IslandLloyd, OnePassMovesSitesToBruteForceAreaCentroids) {
  const glm::dvec2 lo(0, 0), hi(1000, 700);
  const auto sites = random_sites(40, lo, hi - lo, 4);
  const PolygonMap before = voronoi_diagram(sites, lo, hi);
  std::vector<glm::dvec2> snapped;
  for (const auto& c : before.cells) snapped.push_back(c.centre);
  const auto after = lloyd_relax(sites, lo, hi, 1);
  // Brute force: the mean of a fine grid of samples assigned to their nearest site (no polygons involved).
  const int nx = 1000, ny = 700;
  std::vector<glm::dvec2> sum(sites.size(), glm::dvec2(0.0));
  std::vector<double> count(sites.size(), 0.0);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const glm::dvec2 p = lo + (hi - lo) * glm::dvec2((i + 0.5) / nx, (j + 0.5) / ny);
      const auto k = static_cast<std::size_t>(brute_nearest(snapped, p));
      sum[k] += p;
      count[k] += 1.0;
    }
  for (std::size_t i = 0; i < sites.size(); ++i) {
    const glm::dvec2 centroid = sum[i] / count[i];
    EXPECT_LT(glm::length(after[i] - centroid), 0.6) << "site " << i;  // ~ sample spacing 1 m
    EXPECT_GT(glm::length(after[i] - snapped[i]), 0.0);
  }
}

// ---------------------------------------------------------------------------------------------------------
// The island

IslandParams test_params(std::uint64_t seed = 3) {
  IslandParams p;
  p.cells = 3000;
  p.seed = seed;
  p.shape_scale = 1.2;
  p.shape_offset = -0.25;
  p.rivers = 80;
  return p;
}

const PolygonMap& test_island() {
  static const PolygonMap map = generate_island(test_params());
  return map;
}

TEST(Island, OceanTouchesTheBorderIsConnectedAndLakesAreEnclosed) {
  const PolygonMap& m = test_island();
  EXPECT_NO_THROW(m.check_consistent());
  const auto& ocean = cattr(m, "ocean");
  const auto& lake = cattr(m, "lake");
  const auto& water = cattr(m, "water");
  std::vector<char> reached(m.cells.size(), 0);
  std::vector<int> stack;
  int n_ocean = 0, n_lake = 0, n_land = 0;
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    if (m.cells[c].border) {
      EXPECT_EQ(ocean[c], 1.0f) << "border cell " << c << " is not ocean";
      reached[c] = 1;
      stack.push_back(static_cast<int>(c));
    }
    n_ocean += ocean[c] > 0.5f;
    n_lake += lake[c] > 0.5f;
    n_land += water[c] < 0.5f;
    EXPECT_EQ(water[c], std::max(ocean[c], lake[c]));
    EXPECT_FALSE(ocean[c] > 0.5f && lake[c] > 0.5f);
  }
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    for (int d : m.cells[static_cast<std::size_t>(c)].neighbours)
      if (ocean[static_cast<std::size_t>(d)] > 0.5f && !reached[static_cast<std::size_t>(d)]) {
        reached[static_cast<std::size_t>(d)] = 1;
        stack.push_back(d);
      }
  }
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    if (ocean[c] > 0.5f) {
      EXPECT_TRUE(reached[c]) << "ocean cell " << c << " not connected to the border";
    }
    if (lake[c] > 0.5f) {
      EXPECT_FALSE(m.cells[c].border);
      for (int d : m.cells[c].neighbours)
        EXPECT_LT(ocean[static_cast<std::size_t>(d)], 0.5f) << "lake " << c << " touches the ocean";
    }
  }
  EXPECT_GT(n_land, 200);
  EXPECT_GT(n_ocean, 200);
  EXPECT_GT(n_lake, 0) << "the test island should have a lake";
}

TEST(Island, ElevationSignsCoastAndFlatLakes) {
  const PolygonMap& m = test_island();
  const auto& e = qattr(m, "elevation");
  const auto& ocean = qattr(m, "ocean");
  const auto& coast = qattr(m, "coast");
  const auto& lake = qattr(m, "lake");
  for (std::size_t q = 0; q < m.corners.size(); ++q) {
    if (coast[q] > 0.5f)
      EXPECT_EQ(e[q], 0.0f);
    else if (ocean[q] > 0.5f)
      EXPECT_LT(e[q], 0.0f);
    else
      EXPECT_GT(e[q], 0.0f);
    EXPECT_LE(e[q], 1000.0f);
    EXPECT_GE(e[q], -200.0f);
  }
  // Lakes are flat: connected lake corners share one elevation.
  for (std::size_t q = 0; q < m.corners.size(); ++q)
    if (lake[q] > 0.5f)
      for (int r : m.corners[q].adjacent)
        if (lake[static_cast<std::size_t>(r)] > 0.5f) {
          EXPECT_EQ(e[q], e[static_cast<std::size_t>(r)]);
        }
}

TEST(Island, ElevationFollowsTheTargetDistribution) {
  for (double k : {1.0, 2.0, 3.0}) {
    IslandParams p = test_params(8);
    p.lowland_bias = k;
    const PolygonMap m = generate_island(p);
    const auto& e = qattr(m, "elevation");
    const auto& ocean = qattr(m, "ocean");
    const auto& coast = qattr(m, "coast");
    // Every inland corner (lakes included, at their flattened level: a few percent of the corners).
    std::vector<double> land;
    for (std::size_t q = 0; q < m.corners.size(); ++q)
      if (ocean[q] < 0.5f && coast[q] < 0.5f) land.push_back(e[q] / p.max_elevation);
    ASSERT_GT(land.size(), 300u);
    std::sort(land.begin(), land.end());
    for (double quantile : {0.1, 0.25, 0.5, 0.75, 0.9}) {
      const double got = land[static_cast<std::size_t>(quantile * static_cast<double>(land.size() - 1))];
      const double want = 1.0 - std::pow(1.0 - quantile, 1.0 / k);
      EXPECT_NEAR(got, want, 0.03) << "k " << k << " quantile " << quantile;
    }
  }
}

TEST(Island, RiversRunDownhillToTheOceanWithGrowingVolume) {
  const PolygonMap& m = test_island();
  const auto& e = qattr(m, "elevation");
  const auto& river = qattr(m, "river");
  const auto& down = qattr(m, "downstream");
  const auto& coast = qattr(m, "coast");
  const auto& ocean = qattr(m, "ocean");
  int river_corners = 0, sources = 0;
  std::vector<int> upstream(m.corners.size(), 0);
  for (std::size_t q = 0; q < m.corners.size(); ++q)
    if (river[q] > 0.0f && down[q] >= 0.0f) ++upstream[static_cast<std::size_t>(down[q])];
  for (std::size_t q = 0; q < m.corners.size(); ++q) {
    if (!(river[q] > 0.0f)) continue;
    ++river_corners;
    sources += upstream[q] == 0;
    // Follow the river to its end.
    std::size_t at = q;
    for (std::size_t steps = 0;; ++steps) {
      ASSERT_LT(steps, m.corners.size()) << "river from " << q << " loops";
      const int d = static_cast<int>(down[at]);
      if (d < 0) break;
      const auto next = static_cast<std::size_t>(d);
      EXPECT_LE(e[next], e[at]) << "river climbs from corner " << at << " to " << next;
      EXPECT_GE(river[next], river[at]) << "volume shrinks from corner " << at << " to " << next;
      // Neighbours along an edge, and the edge carries the river.
      const auto& adj = m.corners[at].adjacent;
      EXPECT_NE(std::find(adj.begin(), adj.end(), d), adj.end());
      at = next;
    }
    EXPECT_EQ(coast[at], 1.0f) << "river from " << q << " ends at a corner that is not on the coast";
    EXPECT_LT(ocean[q], 0.5f);
  }
  EXPECT_GT(sources, 20);
  EXPECT_GT(river_corners, 100);
  // The edge volumes match the corner volumes they leave.
  const auto& eriver = m.edge_attributes.at("river");
  for (std::size_t q = 0; q < m.corners.size(); ++q)
    if (river[q] > 0.0f && down[q] >= 0.0f)
      for (int k : m.corners[q].edges) {
        const auto& edge = m.edges[static_cast<std::size_t>(k)];
        if (edge.corners[0] == static_cast<int>(down[q]) || edge.corners[1] == static_cast<int>(down[q])) {
          EXPECT_EQ(eriver[static_cast<std::size_t>(k)], river[q]);
        }
      }
}

TEST(Island, EveryInlandCornerDrainsToTheCoast) {
  const PolygonMap& m = test_island();
  const auto& e = qattr(m, "elevation");
  const auto& down = qattr(m, "downstream");
  const auto& coast = qattr(m, "coast");
  const auto& ocean = qattr(m, "ocean");
  for (std::size_t q = 0; q < m.corners.size(); ++q) {
    if (ocean[q] > 0.5f || coast[q] > 0.5f) {
      EXPECT_EQ(down[q], -1.0f);
      continue;
    }
    std::size_t at = q, steps = 0;
    while (down[at] >= 0.0f && steps++ < m.corners.size()) {
      EXPECT_LE(e[static_cast<std::size_t>(down[at])], e[at]);
      at = static_cast<std::size_t>(down[at]);
    }
    EXPECT_EQ(coast[at], 1.0f) << "corner " << q;
  }
}

TEST(Island, MoistureDecaysByTheFactorPerStep) {
  for (double decay : {0.8, 0.5}) {
    IslandParams p = test_params(4);
    p.moisture_decay = decay;
    const PolygonMap m = generate_island(p);
    const auto& raw = qattr(m, "moisture_raw");
    const auto& moist = qattr(m, "moisture");
    const auto& river = qattr(m, "river");
    const auto& lake = qattr(m, "lake");
    const auto& ocean = qattr(m, "ocean");
    const auto& coast = qattr(m, "coast");
    int spread = 0;
    for (std::size_t q = 0; q < m.corners.size(); ++q) {
      if (ocean[q] > 0.5f || coast[q] > 0.5f) {
        EXPECT_EQ(moist[q], 1.0f);
        continue;
      }
      double source = river[q] > 0.0f ? std::min(3.0, 0.2 * river[q]) : 0.0;
      if (lake[q] > 0.5f) source = std::max(source, 1.0);
      double best = 0.0;
      for (int r : m.corners[q].adjacent) {
        const auto rr = static_cast<std::size_t>(r);
        if (ocean[rr] > 0.5f || coast[rr] > 0.5f) continue;
        best = std::max(best, static_cast<double>(raw[rr]));
        // Never more than one decay step between land neighbours.
        EXPECT_GE(raw[rr], decay * raw[q] * (1 - 1e-6) - 1e-12);
      }
      const double want = std::max(source, decay * best);
      EXPECT_NEAR(raw[q], want, 1e-6 * std::max(1.0, want)) << "corner " << q;
      spread += raw[q] > source;
      EXPECT_GE(moist[q], 0.0f);
      EXPECT_LE(moist[q], 1.0f);
    }
    EXPECT_GT(spread, 100);
    // The redistributed moisture keeps the order of the raw moisture (never increases away from water).
    std::vector<std::pair<float, float>> pairs;
    for (std::size_t q = 0; q < m.corners.size(); ++q)
      if (ocean[q] < 0.5f && coast[q] < 0.5f) pairs.push_back({raw[q], moist[q]});
    std::sort(pairs.begin(), pairs.end());
    for (std::size_t k = 1; k < pairs.size(); ++k) EXPECT_LE(pairs[k - 1].second, pairs[k].second);
  }
}

TEST(Island, BiomeTable) {
  EXPECT_EQ(whittaker_biome(0.9, 0.9), Biome::Snow);
  EXPECT_EQ(whittaker_biome(0.9, 0.4), Biome::Tundra);
  EXPECT_EQ(whittaker_biome(0.9, 0.2), Biome::Bare);
  EXPECT_EQ(whittaker_biome(0.9, 0.1), Biome::Scorched);
  EXPECT_EQ(whittaker_biome(0.7, 0.7), Biome::Taiga);
  EXPECT_EQ(whittaker_biome(0.7, 0.5), Biome::Shrubland);
  EXPECT_EQ(whittaker_biome(0.7, 0.2), Biome::TemperateDesert);
  EXPECT_EQ(whittaker_biome(0.5, 0.9), Biome::TemperateRainForest);
  EXPECT_EQ(whittaker_biome(0.5, 0.6), Biome::DeciduousForest);
  EXPECT_EQ(whittaker_biome(0.5, 0.3), Biome::Grassland);
  EXPECT_EQ(whittaker_biome(0.5, 0.1), Biome::TemperateDesert);
  EXPECT_EQ(whittaker_biome(0.1, 0.8), Biome::TropicalRainForest);
  EXPECT_EQ(whittaker_biome(0.1, 0.5), Biome::TropicalSeasonalForest);
  EXPECT_EQ(whittaker_biome(0.1, 0.2), Biome::Grassland);
  EXPECT_EQ(whittaker_biome(0.1, 0.0), Biome::SubtropicalDesert);
  // Table I values.
  EXPECT_FLOAT_EQ(biome_info(Biome::Snow).amplitude, 0.5f);
  EXPECT_FLOAT_EQ(biome_info(Biome::Snow).roughness, 0.7f);
  EXPECT_FLOAT_EQ(biome_info(Biome::Scorched).amplitude, 0.7f);
  EXPECT_FLOAT_EQ(biome_info(Biome::TemperateDesert).roughness, 0.1f);
  EXPECT_FLOAT_EQ(biome_info(Biome::SubtropicalDesert).roughness, 0.6f);
  EXPECT_FLOAT_EQ(biome_info(Biome::Ocean).amplitude, 0.2f);
  EXPECT_EQ(biome_info(Biome::TemperateRainForest).name, "temperate_rain_forest");
  // Every cell has exactly one biome, the one the table gives.
  const PolygonMap& m = test_island();
  const auto& biome = cattr(m, "biome");
  const auto& ocean = cattr(m, "ocean");
  const auto& lake = cattr(m, "lake");
  const auto& elev = cattr(m, "elevation");
  const auto& moist = cattr(m, "moisture");
  std::set<int> seen;
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const float b = biome[c];
    ASSERT_EQ(b, std::floor(b));
    ASSERT_GE(b, 0.0f);
    ASSERT_LT(b, static_cast<float>(kBiomeCount));
    seen.insert(static_cast<int>(b));
    bool touches_ocean = false;
    for (int d : m.cells[c].neighbours) touches_ocean = touches_ocean || ocean[static_cast<std::size_t>(d)] > 0.5f;
    Biome want;
    if (ocean[c] > 0.5f)
      want = Biome::Ocean;
    else if (lake[c] > 0.5f)
      want = Biome::Lake;
    else if (touches_ocean)
      want = Biome::Beach;
    else
      want = whittaker_biome(std::clamp(elev[c] / 1000.0, 0.0, 1.0), moist[c]);
    EXPECT_EQ(static_cast<int>(b), static_cast<int>(want)) << "cell " << c;
  }
  EXPECT_GE(seen.size(), 7u);
}

TEST(Island, SameSeedSameMapOtherSeedOtherMap) {
  const PolygonMap a = generate_island(test_params(3));
  const PolygonMap& b = test_island();
  ASSERT_EQ(a.cells.size(), b.cells.size());
  ASSERT_EQ(a.corners.size(), b.corners.size());
  for (std::size_t q = 0; q < a.corners.size(); ++q) ASSERT_EQ(a.corners[q].position, b.corners[q].position);
  EXPECT_EQ(a.cell_attributes, b.cell_attributes);
  EXPECT_EQ(a.corner_attributes, b.corner_attributes);
  EXPECT_EQ(a.edge_attributes, b.edge_attributes);
  const PolygonMap c = generate_island(test_params(4));
  EXPECT_NE(a.cell_attributes.at("biome"), c.cell_attributes.at("biome"));
  bool moved = c.cells.size() != a.cells.size();
  for (std::size_t i = 0; !moved && i < a.cells.size(); ++i) moved = a.cells[i].centre != c.cells[i].centre;
  EXPECT_TRUE(moved);
}

TEST(Island, PoissonSitesKeepTheirDistance) {
  IslandParams p;
  p.cells = 2000;
  p.size = {3000, 2000};
  p.min_corner = {-500, 40};
  const auto sites = island_sites(p);
  EXPECT_NEAR(static_cast<double>(sites.size()), 2000.0, 300.0);
  const double r = std::sqrt(0.7 * p.size.x * p.size.y / p.cells);
  double min_d = 1e300;
  for (std::size_t i = 0; i < sites.size(); ++i) {
    EXPECT_GT(sites[i].x, p.min_corner.x);
    EXPECT_LT(sites[i].x, p.min_corner.x + p.size.x);
    EXPECT_GT(sites[i].y, p.min_corner.y);
    EXPECT_LT(sites[i].y, p.min_corner.y + p.size.y);
    for (std::size_t j = i + 1; j < sites.size(); ++j) min_d = std::min(min_d, glm::length(sites[i] - sites[j]));
  }
  EXPECT_GE(min_d, r * (1 - 1e-9));
}

TEST(Island, MaskShapesTheIsland) {
  // A disk of radius 1200 m in the middle of a 4096 m map.
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {129, 129});
  Heightfield mask(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      mask.at(i, j) = glm::length(d.position(i, j) - glm::dvec2(2048, 2048)) < 1200.0 ? 1.0f : 0.0f;
  IslandParams p;
  p.cells = 1500;
  const PolygonMap m = generate_island(p, &mask);
  const auto& water = cattr(m, "water");
  for (std::size_t c = 0; c < m.cells.size(); ++c) {
    const double r = glm::length(m.cells[c].centre - glm::dvec2(2048, 2048));
    if (r < 1000.0) {
      EXPECT_LT(water[c], 0.5f) << "cell " << c << " at r " << r;
    }
    if (r > 1400.0) {
      EXPECT_GT(water[c], 0.5f) << "cell " << c << " at r " << r;
    }
  }
}

TEST(Island, RiverCurvesFollowTheCorners) {
  const PolygonMap& m = test_island();
  const Curves curves = river_curves(m, 5.0);
  EXPECT_NO_THROW(curves.check_consistent());
  ASSERT_GT(curves.size(), 10u);
  for (const auto& c : curves.curves) {
    ASSERT_GE(c.points.size(), 2u);
    for (std::size_t k = 1; k < c.points.size(); ++k) {
      EXPECT_LE(c.points[k].z, c.points[k - 1].z);
      EXPECT_GE(c.attributes.at("volume")[k], c.attributes.at("volume")[k - 1]);
    }
    EXPECT_NEAR(c.width[0], 5.0 * std::sqrt(c.attributes.at("volume")[0]), 1e-4);
    if (c.parent >= 0) {
      const auto& p = curves.curves[static_cast<std::size_t>(c.parent)];
      EXPECT_EQ(p.points.front(), c.points.back()) << "a curve must end where its parent starts";
    } else {
      EXPECT_EQ(c.points.back().z, 0.0f) << "a root curve ends at the coast";
    }
  }
}

// ---------------------------------------------------------------------------------------------------------
// Rendering

TEST(IslandRaster, BoundsMasksAndExactLookup) {
  const PolygonMap& m = test_island();
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {160, 160});
  for (double perturb : {0.0, 60.0}) {
    RasterParams p;
    p.perturb_distance = perturb;
    const RasterResult r = rasterize_polygon_map(m, d, p);
    const auto& qe = qattr(m, "elevation");
    const float lo = *std::min_element(qe.begin(), qe.end()), hi = *std::max_element(qe.begin(), qe.end());
    int river = 0;
    for (std::size_t k = 0; k < d.sample_count(); ++k) {
      EXPECT_GE(r.elevation->data[k], lo - 1e-3f);
      EXPECT_LE(r.elevation->data[k], hi + 1e-3f);
      for (const auto* f : {r.water.get(), r.ocean.get(), r.lake.get()})
        EXPECT_TRUE(f->data[k] == 0.0f || f->data[k] == 1.0f);
      EXPECT_GE(r.river->data[k], 0.0f);
      EXPECT_LE(r.river->data[k], 1.0f);
      river += r.river->data[k] > 0.5f;
      EXPECT_GE(r.moisture->data[k], 0.0f);
      EXPECT_LE(r.moisture->data[k], 1.0f);
      const float b = r.biome->data[k];
      EXPECT_EQ(b, std::floor(b));
      EXPECT_TRUE(b >= 0.0f && b < kBiomeCount);
      EXPECT_EQ(r.ocean->data[k] > 0.5f, b == static_cast<float>(Biome::Ocean));
      for (int c = 0; c < 4; ++c) {
        EXPECT_GE(r.color->data[k * 4 + static_cast<std::size_t>(c)], 0.0f);
        EXPECT_LE(r.color->data[k * 4 + static_cast<std::size_t>(c)], 1.0f);
      }
      // Land above sea level, sea at or below it.
      if (r.water->data[k] < 0.5f) {
        EXPECT_GE(r.elevation->data[k], 0.0f);
      }
      if (r.ocean->data[k] > 0.5f) {
        EXPECT_LE(r.elevation->data[k], 0.0f);
      }
    }
    EXPECT_GT(river, 10);
    // The border of the map is ocean.
    for (int i = 0; i < d.width(); ++i) {
      EXPECT_EQ(r.ocean->at(i, 0), 1.0f);
      EXPECT_EQ(r.ocean->at(i, d.height() - 1), 1.0f);
    }
  }
  // Without displacement, the value at a site is the cell's value and at a corner the corner's.
  const Domain pts = Domain::from_extent({0, 0}, {4096, 4096}, {2, 2});
  RasterParams exact;
  exact.perturb_distance = 0.0;
  const auto& ce = cattr(m, "elevation");
  for (std::size_t c = 0; c < m.cells.size(); c += 97) {
    const glm::dvec2 s = m.cells[c].centre;
    const Domain one = Domain::from_extent(s, {1e-3, 1e-3}, {2, 2});
    const RasterResult r = rasterize_polygon_map(m, one, exact);
    EXPECT_NEAR(r.elevation->at(0, 0), ce[c], 1e-3f);
  }
  (void)pts;
}

TEST(IslandRaster, ResolutionIndependentAndThreadCountIndependent) {
  // 512^2 and 1024^2 over the same square (the sizes). Their lattices share no samples (spacings
  // 4096/511 and 4096/1023 m), so the fine raster is downsampled to the coarse lattice with a tent filter
  // one coarse spacing wide, in world units.
  const PolygonMap& m = test_island();
  RasterParams p;
  p.perturb_distance = 50.0;
  const Domain coarse = Domain::from_extent({0, 0}, {4096, 4096}, {512, 512});
  const Domain fine = Domain::from_extent({0, 0}, {4096, 4096}, {1024, 1024});
  const RasterResult a = rasterize_polygon_map(m, coarse, p);
  const RasterResult b = rasterize_polygon_map(m, fine, p);
  const double sc = coarse.spacing.x, sf = fine.spacing.x;
  double diff = 0.0;
  std::size_t same_biome = 0;
  for (int j = 0; j < coarse.height(); ++j)
    for (int i = 0; i < coarse.width(); ++i) {
      const glm::dvec2 w = coarse.position(i, j);
      const int ci = static_cast<int>(std::lround(w.x / sf)), cj = static_cast<int>(std::lround(w.y / sf));
      double s = 0.0, sw = 0.0;
      for (int y = std::max(0, cj - 2); y <= std::min(fine.height() - 1, cj + 2); ++y)
        for (int x = std::max(0, ci - 2); x <= std::min(fine.width() - 1, ci + 2); ++x) {
          const double k =
              std::max(0.0, 1.0 - std::abs(fine.x(x) - w.x) / sc) * std::max(0.0, 1.0 - std::abs(fine.y(y) - w.y) / sc);
          s += k * b.elevation->at(x, y);
          sw += k;
        }
      diff += std::abs(s / sw - a.elevation->at(i, j));
      same_biome += a.biome->at(i, j) == b.biome->at(ci, cj);  // nearest fine sample, at most 2 m away
    }
  const double n = static_cast<double>(coarse.sample_count());
  // Measured: 0.14 m and 99.7 % (the filtered and point samples differ only along coasts and rivers).
  EXPECT_LT(diff / n, 1.0);  // metres, of a 1000 m relief
  EXPECT_GT(static_cast<double>(same_biome) / n, 0.99);
  // The lookup depends on the world position only: single samples at coarse and fine sample positions
  // reproduce both rasters exactly.
  for (int k = 0; k < 40; ++k) {
    const int i = (k * 37 + 5) % coarse.width(), j = (k * 91 + 11) % coarse.height();
    const Domain one = Domain::from_extent(coarse.position(i, j), {1.0, 1.0}, {2, 2});
    const RasterResult r = rasterize_polygon_map(m, one, p);
    EXPECT_EQ(r.elevation->at(0, 0), a.elevation->at(i, j)) << i << "," << j;
    EXPECT_EQ(r.biome->at(0, 0), a.biome->at(i, j));
    const int fi = (k * 53 + 3) % fine.width(), fj = (k * 29 + 17) % fine.height();
    const RasterResult rf = rasterize_polygon_map(m, Domain::from_extent(fine.position(fi, fj), {1.0, 1.0}, {2, 2}), p);
    EXPECT_EQ(rf.elevation->at(0, 0), b.elevation->at(fi, fj)) << fi << "," << fj;
  }
  const Domain small = Domain::from_extent({0, 0}, {4096, 4096}, {257, 257});
  const auto one = test::with_threads(1, [&] { return rasterize_polygon_map(m, small, p); });
  const auto many = test::with_threads(test::several_threads(), [&] { return rasterize_polygon_map(m, small, p); });
  EXPECT_EQ(one.elevation->data, many.elevation->data);
  EXPECT_EQ(one.river->data, many.river->data);
  EXPECT_EQ(one.color->data, many.color->data);
}

TEST(IslandRaster, RiverWidthGrowsWithVolume) {
  const PolygonMap& m = test_island();
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {513, 513});
  RasterParams p;
  p.perturb_distance = 0.0;
  p.river_width = 6.0;
  const auto thin = rasterize_polygon_map(m, d, p);
  p.river_width = 18.0;
  const auto wide = rasterize_polygon_map(m, d, p);
  const double a = std::accumulate(thin.river->data.begin(), thin.river->data.end(), 0.0);
  const double b = std::accumulate(wide.river->data.begin(), wide.river->data.end(), 0.0);
  EXPECT_GT(b, 2.0 * a);
  p.river_width = 0.0;
  const auto none = rasterize_polygon_map(m, d, p);
  EXPECT_LE(*std::max_element(none.river->data.begin(), none.river->data.end()), 0.5f);
}

// ---------------------------------------------------------------------------------------------------------
// Nodes

TEST(IslandNodes, EveryParameterAndInputChangesTheKey) {
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {33, 33});
  expect_every_param_changes_key("VoronoiIsland", d);
  expect_every_param_changes_key("PolygonMapRaster", d);
  expect_every_param_changes_key("RiverNetwork", d);
  expect_every_param_changes_key("CarveRivers", d);
  expect_every_param_changes_key("SeaLevelNormalize", d);
  expect_every_input_changes_key("VoronoiIsland", d);
  expect_every_input_changes_key("RiverNetwork", d);
}

TEST(IslandNodes, RunThroughTheRegistry) {
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {65, 65});
  const auto island = run_node("VoronoiIsland", d, {{"cells", std::int64_t{500}}, {"shape_scale", 1.0}});
  const auto map = island.get<PolygonMap>(0);
  ASSERT_TRUE(map);
  EXPECT_EQ(map->cells.size() > 300, true);
  const auto rivers = island.get<Curves>(1);
  ASSERT_TRUE(rivers);
  const auto raster = run_node("PolygonMapRaster", d, {}, {{"in", PortValue(map)}});
  const auto h = raster.get<Heightfield>(0);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->domain, d);
}

// ---------------------------------------------------------------------------------------------------------
// River network (SeamScape)

RiverNetworkParams network_params(std::uint64_t seed = 5) {
  RiverNetworkParams p;
  p.size = {3000, 2500};
  p.min_corner = {-1000, 500};
  p.outlets = 4;
  p.density = 30;
  p.max_length = 400;
  p.seed = seed;
  return p;
}

const Curves& test_network() {
  static const Curves c = river_network(network_params());
  return c;
}

bool proper_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  auto orient = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r) {
    const double v = (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    return (v > 0) - (v < 0);
  };
  if (a == c || a == d || b == c || b == d) return false;
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  return o1 * o2 <= 0 && o3 * o4 <= 0 && !(o1 == 0 && o2 == 0);
}

TEST(RiverNetwork, NoTwoCurvesCross) {
  const Curves& net = test_network();
  EXPECT_NO_THROW(net.check_consistent());
  ASSERT_GT(net.size(), 100u);
  struct S {
    glm::dvec2 a, b;
    std::size_t curve;
  };
  std::vector<S> segs;
  for (std::size_t k = 0; k < net.size(); ++k) {
    const auto& pts = net.curves[k].points;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i)
      segs.push_back({{pts[i].x, pts[i].y}, {pts[i + 1].x, pts[i + 1].y}, k});
  }
  int crossings = 0;
  for (std::size_t i = 0; i < segs.size(); ++i)
    for (std::size_t j = i + 1; j < segs.size(); ++j)
      if (segs[i].curve != segs[j].curve && proper_cross(segs[i].a, segs[i].b, segs[j].a, segs[j].b)) ++crossings;
  EXPECT_EQ(crossings, 0);
  // Every point inside the rectangle.
  for (const auto& s : segs) {
    EXPECT_GE(s.a.x, -1000.0 - 1e-3);
    EXPECT_LE(s.a.x, 2000.0 + 1e-3);
    EXPECT_GE(s.a.y, 500.0 - 1e-3);
    EXPECT_LE(s.a.y, 3000.0 + 1e-3);
  }
}

TEST(RiverNetwork, TreesSizesAndHeights) {
  const RiverNetworkParams p = network_params();
  const Curves& net = test_network();
  std::set<std::pair<float, float>> sources;
  std::vector<double> child_sum(net.size(), 0.0);
  std::map<std::pair<float, float>, double> outlet_size;
  for (std::size_t k = 0; k < net.size(); ++k) {
    const Curve& c = net.curves[k];
    // Each inner point starts exactly one curve.
    EXPECT_TRUE(sources.insert({c.points.front().x, c.points.front().y}).second) << "point joined twice";
    // The parent chain reaches an outlet without loops; a curve ends where its parent starts.
    int at = static_cast<int>(k);
    for (std::size_t steps = 0; at >= 0; ++steps) {
      ASSERT_LT(steps, net.size());
      at = net.curves[static_cast<std::size_t>(at)].parent;
    }
    if (c.parent >= 0) {
      const Curve& q = net.curves[static_cast<std::size_t>(c.parent)];
      EXPECT_EQ(c.points.back(), q.points.front());
      child_sum[static_cast<std::size_t>(c.parent)] += c.attributes.at("size").front();
    } else {
      EXPECT_EQ(c.points.back().z, 0.0f) << "outlets are at height 0";
      outlet_size[{c.points.back().x, c.points.back().y}] += c.attributes.at("size").front();
    }
    // Heights never decrease upstream (points run upstream -> downstream).
    for (std::size_t i = 1; i < c.points.size(); ++i) EXPECT_LE(c.points[i].z, c.points[i - 1].z);
  }
  EXPECT_LE(outlet_size.size(), static_cast<std::size_t>(p.outlets));
  EXPECT_GE(outlet_size.size(), 1u);
  for (std::size_t k = 0; k < net.size(); ++k) {
    const Curve& c = net.curves[k];
    const double size = c.attributes.at("size").front();
    EXPECT_EQ(size, child_sum[k] > 0.0 ? child_sum[k] : 1.0)
        << "size of curve " << k << " is not the sum of its children";
    // Slope formula of SeamScape and h_c = h_p + |c - p| d_c.
    const double parent_size = c.parent >= 0
                                   ? net.curves[static_cast<std::size_t>(c.parent)].attributes.at("size").front()
                                   : outlet_size.at({c.points.back().x, c.points.back().y});
    const double parent_slope =
        c.parent >= 0 ? net.curves[static_cast<std::size_t>(c.parent)].attributes.at("slope").front() : p.base_slope;
    const double r = size / parent_size;
    const double slope = parent_slope - 4.0 * r * (r - 1.0) * p.slope_weight;
    EXPECT_NEAR(c.attributes.at("slope").front(), slope, 1e-6);
    const double chord = std::hypot(c.points.front().x - c.points.back().x, c.points.front().y - c.points.back().y);
    EXPECT_NEAR(c.points.front().z - c.points.back().z, chord * slope, 1e-3 * (1.0 + c.points.front().z));
    EXPECT_NEAR(c.width.front(), p.river_width * std::pow(size, p.width_exponent), 1e-3);
  }
}

TEST(RiverNetwork, TangentsAreContinuousAtJoins) {
  RiverNetworkParams p = network_params();
  p.samples = 64;
  const Curves net = river_network(p);
  int smooth = 0;
  for (const Curve& c : net.curves) {
    if (c.parent < 0 || c.attributes.at("smooth_join").back() < 0.5f) continue;
    ++smooth;
    const Curve& q = net.curves[static_cast<std::size_t>(c.parent)];
    const std::size_t n = c.points.size();
    const glm::dvec2 in =
        glm::normalize(glm::dvec2(c.points[n - 1].x - c.points[n - 2].x, c.points[n - 1].y - c.points[n - 2].y));
    const glm::dvec2 out = glm::normalize(glm::dvec2(q.points[1].x - q.points[0].x, q.points[1].y - q.points[0].y));
    EXPECT_GT(glm::dot(in, out), 0.995) << "kink at a smooth join";
  }
  EXPECT_GT(smooth, static_cast<int>(net.size()) / 4);
}

TEST(RiverNetwork, DeterministicBySeed) {
  const Curves a = river_network(network_params(5));
  const Curves& b = test_network();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a.curves[k].points, b.curves[k].points);
    EXPECT_EQ(a.curves[k].parent, b.curves[k].parent);
  }
  const Curves c = river_network(network_params(6));
  EXPECT_TRUE(c.size() != a.size() || c.curves[0].points != a.curves[0].points);
}

TEST(RiverNetwork, MaskKeepsRiversOnLand) {
  const Domain d = Domain::from_extent({0, 0}, {3000, 3000}, {151, 151});
  Heightfield mask(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      mask.at(i, j) = glm::length(d.position(i, j) - glm::dvec2(1500, 1500)) < 1100.0 ? 1.0f : 0.0f;
  RiverNetworkParams p;
  p.size = {3000, 3000};
  p.outlets = 6;
  p.density = 30;
  p.max_length = 350;
  const Curves net = river_network(p, &mask);
  ASSERT_GT(net.size(), 50u);
  for (const Curve& c : net.curves)
    for (const auto& q : c.points) EXPECT_GE(mask.sample_world(q.x, q.y), 0.5f) << q.x << "," << q.y;
}

TEST(CarveRivers, BedFollowsTheCurveHeights) {
  const Curves& net = test_network();
  const Domain d = Domain::from_extent({-1000, 500}, {3000, 2500}, {301, 251});  // 10 m spacing
  Heightfield flat(d, 400.0f);
  CarveParams p;
  p.radius = 300.0;
  p.depth_ratio = 0.0;
  const CarveResult r = carve_rivers(flat, net, p);
  // On the curve itself (a 2 x 2 domain whose first sample is the curve point) the bed is the curve's height.
  int checked = 0;
  for (std::size_t k = 0; k < net.size(); k += 3) {
    const Curve& c = net.curves[k];
    for (std::size_t i = 0; i < c.points.size(); i += 2) {
      const auto q = c.points[i];
      const Domain one = Domain::from_extent({q.x, q.y}, {1e-3, 1e-3}, {2, 2});
      const CarveResult at = carve_rivers(Heightfield(one, 400.0f), net, p);
      EXPECT_NEAR(at.terrain->at(0, 0), q.z, 1e-3 * (1.0 + q.z)) << "curve bed at " << q.x << "," << q.y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
  // On the 10 m raster, within the river's rise over a sample or two.
  for (const Curve& c : net.curves) {
    const auto q = c.points[c.points.size() / 2];
    EXPECT_NEAR(r.terrain->sample_world(q.x, q.y), q.z, 2.0 + 20.0 * c.attributes.at("slope").front());
  }
  // Beyond the radius the terrain is untouched; carving never raises the terrain above the max of both.
  for (std::size_t k = 0; k < d.sample_count(); ++k) {
    EXPECT_GE(r.mask->data[k], 0.0f);
    EXPECT_LE(r.mask->data[k], 1.0f);
  }
  // The channel: depth_ratio * width below the blended bed on the curve.
  p.depth_ratio = 0.5;
  for (std::size_t k = 0; k < net.size(); k += 7) {
    const Curve& c = net.curves[k];
    const auto q = c.points[c.points.size() / 2];
    const Domain one = Domain::from_extent({q.x, q.y}, {1e-3, 1e-3}, {2, 2});
    const CarveResult at = carve_rivers(Heightfield(one, 400.0f), net, p);
    // The widest channel through the point sets the depth (rivers meet at joins).
    EXPECT_LE(at.terrain->at(0, 0), q.z - 0.5 * c.width[c.points.size() / 2] + 1e-3);
    EXPECT_GT(at.terrain->at(0, 0), q.z - 0.5 * 1000.0);
    EXPECT_EQ(at.mask->at(0, 0), 1.0f);
  }
  // Bit-identical for any thread count.
  const auto one = test::with_threads(1, [&] { return carve_rivers(flat, net, p); });
  const auto many = test::with_threads(test::several_threads(), [&] { return carve_rivers(flat, net, p); });
  EXPECT_EQ(one.terrain->data, many.terrain->data);
  EXPECT_EQ(one.mask->data, many.mask->data);
  // No curves: identity.
  const CarveResult none = carve_rivers(flat, Curves{}, p);
  EXPECT_EQ(none.terrain->data, flat.data);
}

TEST(CarveRivers, FarFromRiversTheTerrainIsUnchanged) {
  Curves one;
  Curve c;
  c.points = {{0.0f, 500.0f, 10.0f}, {1000.0f, 500.0f, 0.0f}};
  c.width = {8.0f, 8.0f};
  one.curves.push_back(c);
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {101, 101});
  Heightfield h(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h.at(i, j) = static_cast<float>(100.0 + 0.05 * d.x(i));
  CarveParams p;
  p.radius = 200.0;
  p.depth_ratio = 0.25;
  const CarveResult r = carve_rivers(h, one, p);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const double dist = std::abs(d.y(j) - 500.0);
      if (dist >= 200.0) {
        EXPECT_EQ(r.terrain->at(i, j), h.at(i, j));
      }
      if (dist == 0.0) {  // bed - 0.25 * 8
        EXPECT_NEAR(r.terrain->at(i, j), 10.0 * (1.0 - d.x(i) / 1000.0) - 2.0, 1e-3);
      }
      if (dist > 4.0 + 10.0) {
        EXPECT_EQ(r.mask->at(i, j), 0.0f);
      }
      // Monotone blend: never outside the range of terrain and river.
      const double river = 10.0 * (1.0 - d.x(i) / 1000.0);
      EXPECT_GE(r.terrain->at(i, j), std::min<double>(h.at(i, j), river) - 2.0 - 1e-3);
      EXPECT_LE(r.terrain->at(i, j), std::max<double>(h.at(i, j), river) + 1e-3);
    }
}

TEST(CarveRivers, TakesTheRiversOfRiverExtract) {
  const Domain d = Domain::from_extent({0, 0}, {2000, 2000}, {101, 101});
  auto terrain = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      terrain->at(i, j) =
          static_cast<float>(0.05 * d.x(i) + 30.0 * std::sin(d.y(j) / 180.0) * std::cos(d.x(i) / 240.0) + 40.0);
  const auto extracted =
      run_node("RiverExtract", d, {{"threshold", 4e4}}, {{"in", PortValue(HeightfieldPtr(terrain))}});
  const auto rivers = extracted.get<Curves>(0);
  ASSERT_TRUE(rivers);
  ASSERT_GT(rivers->size(), 3u);
  const auto carved = run_node("CarveRivers", d, {{"radius", 60.0}, {"depth_ratio", 0.2}},
                               {{"in", PortValue(HeightfieldPtr(terrain))}, {"rivers", PortValue(rivers)}});
  const auto out = carved.get<Heightfield>(0);
  const auto mask = carved.get<Heightfield>(1);
  int on_river = 0;
  for (const Curve& c : rivers->curves)
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      // Curve vertices of RiverExtract sit on samples (no smoothing at the ends): the bed there is the river
      // height minus the channel depth of the widest river through it.
      if (k != 0 && k + 1 != c.points.size()) continue;
      const glm::dvec2 s = d.to_sample({c.points[k].x, c.points[k].y});
      const int i = static_cast<int>(std::lround(s.x)), j = static_cast<int>(std::lround(s.y));
      if (std::abs(s.x - i) > 1e-3 || std::abs(s.y - j) > 1e-3) continue;
      EXPECT_LE(out->at(i, j), c.points[k].z - 0.2 * c.width[k] + 1e-2);
      EXPECT_GT(mask->at(i, j), 0.0f);
      ++on_river;
    }
  EXPECT_GT(on_river, 3);
}
}  // namespace
}  // namespace orogen
