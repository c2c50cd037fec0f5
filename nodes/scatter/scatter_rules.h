#pragma once
// Rule-based placement: ecosystems chosen from terrain variables (Hammes 2001, "Modeling of ecosystems as a
// data source for real-time terrain rendering"), and per-biome densities (the biome tree tables of
// procedural island generators).
#include <cstdint>
#include <string>
#include <vector>

#include "graph/heightfield.h"
#include "graph/points.h"
#include "graph/table_value.h"

namespace orogen {

class ExecContext;

// One variable's preference: 1 inside [min, max], falling with a smoothstep to 0 over (max - min) / sharpness
// outside it (a hard edge when sharpness is very large or min == max).
struct RuleRange {
  bool used = false;
  double min = 0.0, max = 0.0, sharpness = 1.0;
  double membership(double v) const;
};

struct RulePlant {
  std::int32_t class_id = 0;
  double density = 0.0;  // plants per m^2 where the ecosystem holds
  double scale_min = 1.0, scale_max = 1.0;
};

struct Ecosystem {
  std::string name;
  RuleRange elevation;  // m
  RuleRange relative;   // m above the local mean height
  RuleRange slope;      // degrees (0 flat, 90 vertical)
  RuleRange skew;       // slope direction: dz/dy, rise over run toward north (> 0 on south-facing slopes)
  std::vector<RulePlant> plants;
  // Product of the used variables' memberships (1 if none is used).
  double membership(double elevation, double relative, double slope, double skew) const;
};

// ScatterRules' two tables. `ecosystems`: one row per ecosystem, its name and optional preferences, each a
// range and its sharpness (default 1): elevation (m), relative (m), slope (deg), skew (dz/dy). `plants`:
// one row per plant, its ecosystem (a name in `ecosystems`), class, density (per m^2) and scale range.
TableSchema ecosystem_schema();
TableSchema ecosystem_plant_schema();
// The ecosystem table of Ekman et al. (2016), "SeamScape", Table 1 (after Hammes): densities as plants per
// m^2 (their per-area counts per 1000 m^2), scales in tenths, slopes in degrees.
TableValue default_ecosystems();
TableValue default_ecosystem_plants();
// The ecosystems in table order, each with its plants in table order. Throws std::invalid_argument naming
// the row and column of a plant whose ecosystem is unknown or a sharpness without its range.
std::vector<Ecosystem> ecosystems_from_tables(const TableValue& ecosystems, const TableValue& plants);

struct EcosystemParams {
  std::vector<Ecosystem> ecosystems;
  double cell_size = 10.0;  // m: side of the world cells the candidates are drawn in
  std::uint64_t seed = 0;
};

// The terrain variables at a world position.
struct TerrainVariables {
  const Heightfield* height = nullptr;    // required
  const Heightfield* relative = nullptr;  // optional: else 0
  const Heightfield* slope = nullptr;     // optional (degrees): else from the height's gradient
  double elevation(double x, double y) const;
  double relative_at(double x, double y) const;
  double slope_at(double x, double y) const;  // degrees
  double skew_at(double x, double y) const;
};

// For every world cell of cell_size overlapping [lo, hi] and every plant of every ecosystem, density * area
// candidates (dithered) at hashed positions; a candidate is kept if the ecosystem drawn at its position by
// roulette over the memberships (none with probability 1 - sum when the sum is below 1) is its own. Points
// inside [lo, hi] only; z = height; yaw and scale (uniform in the plant's range) hashed; attribute
// "ecosystem" (index in the table).
Points scatter_ecosystems(glm::dvec2 lo, glm::dvec2 hi, const TerrainVariables& vars, const EcosystemParams& p,
                          const ExecContext* ctx = nullptr);

// Per-biome densities: for each biome id, a probability per cell and species weights.
struct BiomeEntry {
  int biome = 0;
  double density = 0.0;                                  // probability of a plant per cell before the global factor
  std::vector<std::pair<std::int32_t, double>> species;  // (class id, weight)
};

// BiomeScatter's two tables: `biomes` (biome id, density) and `species` (biome id, class, weight).
TableSchema biome_density_schema();
TableSchema biome_species_schema();
// The biomes in table order, each with the species rows of its id in table order. Throws
// std::invalid_argument naming the row of a species whose biome is not in `biomes`.
std::vector<BiomeEntry> biome_entries_from_tables(const TableValue& biomes, const TableValue& species);

struct BiomeScatterParams {
  std::vector<BiomeEntry> table;
  double factor = 1.0;     // global density factor
  double cell_size = 4.0;  // m
  double scale_min = 0.8, scale_max = 1.2;
  std::uint64_t seed = 0;
};

// For every world cell: the biome at its centre (nearest sample of `biome`), a plant with probability
// density * factor (clamped to 1), its species drawn by weight, at a hashed position in the cell.
Points scatter_biomes(glm::dvec2 lo, glm::dvec2 hi, const Heightfield& biome, const Heightfield* height,
                      const BiomeScatterParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen
