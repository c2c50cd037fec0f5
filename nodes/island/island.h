#pragma once
// The Voronoi island (Patel 2010, "Polygonal Map Generation for Games", as extended by the Georgia Tech
// terrain report): a polygon map whose cells, corners and edges carry water, ocean, coast, elevation,
// rivers, moisture and a Whittaker biome.
//
// Pipeline (generate_island):
//  1. sites: `cells` points, uniform or Poisson-disk (Bridson 2007), from counter-based hashes of the seed,
//     numbered along a Hilbert curve (so the map's cells and corners near in space are near in memory);
//  2. `relaxation` passes of Lloyd's algorithm (true area centroids, Lloyd 1982), then the clipped Voronoi
//     diagram (voronoi.h, CGAL Delaunay dual);
//  3. water per corner: in normalised coordinates (x, y) in [-1, 1]^2 over the map, water iff
//     noise(x, y) < shape_offset + shape_scale (x^2 + y^2), noise = sum_{i<octaves} perlin(x f 2^i, y f 2^i)
//     0.5 gain^i (Weiss 2015 Eq 1-2 with f = 6, gain = 1/2.5, scale 2.2, offset -0.2); or mask < 0.5 when a mask
//     field is given. Corners on the map border are water;
//  4. a cell is water if at least `water_fraction` of its corners are (and every border cell is); ocean =
//     water cells flood-filled from the border; lakes = the other water cells; corners: ocean if all their
//     cells are, coast if they touch ocean and land, lake if they touch a lake and no ocean;
//  5. elevation: shortest-path distance from the coast over the corner graph on land (a step costs 1.01
//     between two dry corners, 0.01 when either touches a lake, Patel's 1 + 0.01; lakes are then flattened),
//     breadth-first steps over the ocean; land redistributed so the fraction of land corners below normalised height y
//     is F(y) = 1 - (1 - y)^lowland_bias (Patel's 1 - (1 - y)^2 by default), times max_elevation; the ocean falls
//     linearly to -ocean_depth at the farthest ocean corner; every lake is flattened to its lowest corner;
//  6. rivers: `rivers` sources at hashed inland corners with normalised height in [0.3, 0.9] follow the
//     downstream corner (the neighbour closest to the coast; across a lake, to its outlet) to a coast corner;
//     every corner and edge on the way gains one unit of volume, so volume never decreases downstream;
//  7. moisture: fresh water (river corners min(3, 0.2 volume), lake corners 1) spreads over land by
//     breadth-first search, decaying by `moisture_decay` (0.8) per step: raw(q) = max(source(q), decay *
//     max over neighbours raw); then redistributed to its rank in [0, 1] over land; ocean and coast are 1;
//  8. cells average their corners' elevation and moisture; biome from the table below.
//
// Attributes written: cells: water, ocean, lake, coast, elevation (m), moisture, temperature, biome;
// corners: water, ocean, lake, coast, elevation (m), moisture, moisture_raw, river (volume), downstream
// (corner index, -1 at the end of a path), distance (coast distance before redistribution); edges: river.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/heightfield.h"
#include "graph/polygon_map.h"

namespace orogen {
class ExecContext;
}

namespace orogen::island {

// Biomes, in the order of table I of the Georgia Tech report (Whittaker-style names from Patel 2010).
enum class Biome : int {
  Snow,
  Tundra,
  Bare,
  Scorched,
  Taiga,
  Shrubland,
  TemperateDesert,
  TemperateRainForest,
  DeciduousForest,
  Grassland,
  TropicalRainForest,
  TropicalSeasonalForest,
  SubtropicalDesert,
  Beach,
  Lake,
  Ocean
};
inline constexpr int kBiomeCount = 16;

struct BiomeInfo {
  std::string_view name;      // snake_case, as written in graph files and reports
  float amplitude;            // A of the multifractal by biome (table I)
  float roughness;            // R of the multifractal by biome (table I)
  std::array<float, 3> srgb;  // display colour (Patel's palette), sRGB in [0, 1]
};
const BiomeInfo& biome_info(Biome b);

// The Whittaker-style table (Patel 2010), on land away from the beach. e = normalised elevation in [0, 1]
// (temperature = 1 - e), m = moisture in [0, 1]:
//
//   elevation band        | m < 1/6            | < 1/3              | < 1/2              | < 2/3             | < 5/6 |
//   >= 5/6 e > 0.8 (cold)        | scorched           | bare               | tundra             | snow              |
//   snow                | snow 0.6 < e <= 0.8        | temperate desert   | temperate desert   | shrubland          |
//   shrubland         | taiga               | taiga 0.3 < e <= 0.6        | temperate desert   | grassland          |
//   grassland          | deciduous forest  | deciduous forest    | temperate rain forest e <= 0.3 (warm)       |
//   subtropical desert | grassland          | tropical seasonal  | tropical seasonal | tropical rain forest| tropical
//   rain forest
Biome whittaker_biome(double elevation, double moisture);

enum class SiteDistribution { Uniform, Poisson };

struct IslandParams {
  glm::dvec2 min_corner{0.0, 0.0};  // m
  glm::dvec2 size{4096.0, 4096.0};  // m
  int cells = 2000;                 // number of sites (Poisson: about that many)
  SiteDistribution distribution = SiteDistribution::Poisson;
  int relaxation = 2;  // Lloyd passes
  // Island shape (Weiss 2015 Eq 1-2), in normalised map coordinates.
  double shape_scale = 2.2;
  double shape_offset = -0.2;
  double shape_frequency = 6.0;  // lattice cells per unit of normalised coordinate (Weiss 2015's o_b)
  int shape_octaves = 4;
  double shape_gain = 0.4;      // amplitude ratio per octave (1 / 2.5)
  double water_fraction = 0.3;  // share of water corners making a cell water
  // Elevation.
  double max_elevation = 1000.0;  // m
  double ocean_depth = 200.0;     // m
  double lowland_bias = 2.0;      // exponent of the target distribution (1 = uniform)
  // Rivers and moisture.
  int rivers = 60;
  double moisture_decay = 0.8;
  std::uint64_t seed = 0;
};

// Bridson's Poisson-disk sampling (Bridson 2007, "Fast Poisson disk sampling in arbitrary dimensions") of
// about n points in the open rectangle [lo, lo + size], radius sqrt(0.7 size.x size.y / n); every draw is a
// counter-based hash of (seed, draw number).
std::vector<glm::dvec2> poisson_sites(glm::dvec2 lo, glm::dvec2 size, int n, std::uint64_t seed,
                                      const ExecContext* ctx = nullptr);

// The sites of step 1 (before relaxation), inside the map rectangle.
std::vector<glm::dvec2> island_sites(const IslandParams& p, const ExecContext* ctx = nullptr);

// Steps 1-8. `mask` (optional): land where >= 0.5, sampled at the corners (NaN is water). `lloyd_energy`
// (optional) receives the centroidal energy before each relaxation pass and after the last.
PolygonMap generate_island(const IslandParams& p, const Heightfield* mask = nullptr, const ExecContext* ctx = nullptr,
                           std::vector<double>* lloyd_energy = nullptr);

// Steps 3-8 on a given diagram (tests and custom pipelines).
void classify_island(PolygonMap& map, const IslandParams& p, const Heightfield* mask = nullptr,
                     const ExecContext* ctx = nullptr);

// The Weiss 2015 Eq 1 shape noise at normalised coordinates.
double island_shape_noise(const IslandParams& p, double x, double y);

}  // namespace orogen::island
