// ScatterRules and BiomeScatter: the nodes over scatter_ecosystems() and scatter_biomes().
#include <stdexcept>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "graph/table_json.h"
#include "nodes/common/match_domain.h"
#include "nodes/scatter/scatter_rules.h"

namespace orogen {

OROGEN_NODE(ScatterRules) {
  b.distribution(Distribution::PerTile);
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Ecosystem placement after Hammes (2001), \"Modeling of ecosystems as a data source for real-time terrain "
      "rendering\", as used by Ekman et al. (2016), \"SeamScape: a procedural generation system for accelerated "
      "creation of 3D landscapes\": each ecosystem prefers ranges of "
      "elevation, relative elevation, slope (degrees) and skew (1 inside [min, max], a smoothstep to 0 over "
      "(max - min) / sharpness outside); each plant has a density and a scale range. In every world cell, "
      "density * area candidates per plant at hashed positions; a candidate stays if the ecosystem drawn by "
      "roulette over the memberships at its position is its own. Every draw hashes (seed, cell, ecosystem, "
      "plant, counter): tile invariant. Attribute: ecosystem (row of the table).");
  b.input("in", PortType::Heightfield).description("Terrain heights, metres");
  b.input("relative_height", PortType::Heightfield)
      .optional()
      .description("Height above the local mean (m), e.g. height minus a blurred height; 0 if unconnected");
  b.input("slope", PortType::Heightfield)
      .unit(Unit::Degree)
      .optional()
      .description("Slope angle in degrees (e.g. Slope.out); from the height's gradient if unconnected");
  b.output("out", PortType::Points).description("The plants: class ids from the table, scale, yaw, z on the terrain");
  b.param_table("ecosystems", ecosystem_schema(), default_ecosystems())
      .description(
          "One ecosystem per row: its name and preferred ranges of elevation (m), relative height (m), slope "
          "(deg) and skew (dz/dy), each with a sharpness; a range left out is no preference. Default: SeamScape's "
          "Table 1");
  b.param_table("plants", ecosystem_plant_schema(), default_ecosystem_plants())
      .description("One plant per row: its ecosystem (a name in ecosystems), class, density (per m^2) and scale range");
  b.param_float("cell_size", 10.0)
      .range(0.1, 1e4)
      .unit(Unit::Metre)
      .description("Side of the world cells candidates are drawn in, metres in [0.1, 10000]");
  b.param_seed("seed", 0).description("Every draw hashes (seed, cell, ecosystem, plant, counter)");
  // Working memory beyond the outputs, 12 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 12); });
  b.execute([](ExecContext& ctx) {
    const auto height = ctx.require<Heightfield>("in");
    const auto relative = secondary_input<Heightfield>(ctx, "relative_height", height->domain);
    const auto slope = secondary_input<Heightfield>(ctx, "slope", height->domain);
    EcosystemParams p;
    TerrainVariables vars{height.get(), relative.get(), slope.get()};
    p.cell_size = ctx.param<double>("cell_size");
    p.seed = ctx.param<std::uint64_t>("seed");
    try {
      p.ecosystems = ecosystems_from_tables(ctx.param<TableValue>("ecosystems"), ctx.param<TableValue>("plants"));
      ctx.set_output("out", std::make_shared<Points>(scatter_ecosystems(ctx.domain().min_corner(),
                                                                        ctx.domain().max_corner(), vars, p, &ctx)));
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("ScatterRules: ") + e.what());
    } catch (const std::runtime_error& e) {
      throw NodeError(std::string("ScatterRules: ") + e.what());
    }
  });
}

OROGEN_NODE(BiomeScatter) {
  b.distribution(Distribution::PerTile);
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Per-biome tree placement after Weiss (2015), \"Procedural terrain\" (vegetation "
      "chapter): in every world cell a plant appears with probability density(biome) * factor, its species "
      "drawn from the biome's weighted table, at a hashed position in the cell. Every draw hashes (seed, cell): "
      "tile invariant. Attribute: biome.");
  b.input("in", PortType::Heightfield).description("Biome id per sample (integer values, nearest sample is used)");
  b.input("height", PortType::Heightfield).optional().description("Terrain heights (m): sets z");
  b.output("out", PortType::Points).description("The plants: class ids from the table, scale, yaw");
  b.param_table("biomes", biome_density_schema(),
                table_from_json_text(R"([{"biome": 0, "density": 0}, {"biome": 1, "density": 0.2},
                                         {"biome": 2, "density": 0.6}, {"biome": 3, "density": 0.05}])",
                                     biome_density_schema()))
      .description("One biome per row: its id and the probability of a plant per cell (0..1)");
  b.param_table("species", biome_species_schema(),
                table_from_json_text(R"([{"biome": 1, "class": 0, "weight": 1}, {"biome": 1, "class": 1, "weight": 1},
                                         {"biome": 2, "class": 0, "weight": 3}, {"biome": 2, "class": 2, "weight": 1},
                                         {"biome": 3, "class": 3, "weight": 1}])",
                                     biome_species_schema()))
      .description("The species of the biomes, one per row: biome id, class and weight");
  b.param_float("factor", 1.0)
      .range(0.0, 100.0)
      .unit(Unit::Unitless)
      .description("Global density factor multiplying every biome's density, 0..100");
  b.param_float("cell_size", 4.0)
      .range(0.1, 1e4)
      .unit(Unit::Metre)
      .description("Side of the world cells (at most one plant each), metres in [0.1, 10000]");
  b.param_vec2("scale_range", glm::dvec2(0.8, 1.2))
      .range(0.01, 100.0)
      .unit(Unit::Factor)
      .description("Smallest and largest scale factor, 0.01..100 (uniform between them)");
  b.param_seed("seed", 0).description("Every draw hashes (seed, cell)");
  // Working memory beyond the outputs, 8 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 8); });
  b.execute([](ExecContext& ctx) {
    const auto biome = ctx.require<Heightfield>("in");
    const auto height = secondary_input<Heightfield>(ctx, "height", biome->domain);
    BiomeScatterParams p;
    p.factor = ctx.param<double>("factor");
    p.cell_size = ctx.param<double>("cell_size");
    const auto sr = ctx.param<glm::dvec2>("scale_range");
    p.scale_min = std::min(sr.x, sr.y);
    p.scale_max = std::max(sr.x, sr.y);
    p.seed = ctx.param<std::uint64_t>("seed");
    try {
      p.table = biome_entries_from_tables(ctx.param<TableValue>("biomes"), ctx.param<TableValue>("species"));
      ctx.set_output("out", std::make_shared<Points>(scatter_biomes(
                                ctx.domain().min_corner(), ctx.domain().max_corner(), *biome, height.get(), p, &ctx)));
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("BiomeScatter: ") + e.what());
    } catch (const std::runtime_error& e) {
      throw NodeError(std::string("BiomeScatter: ") + e.what());
    }
  });
}

}  // namespace orogen
