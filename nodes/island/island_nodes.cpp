// Node declarations of the island family: VoronoiIsland and PolygonMapRaster.
#include <cmath>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/island/island.h"
#include "nodes/island/island_raster.h"
#include "nodes/island/river_curves.h"
#include "nodes/island/river_network.h"

namespace orogen::island {

OROGEN_NODE(VoronoiIsland) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("island").description(
      "A polygon-map island (A. Patel 2010, \"Polygonal Map Generation for Games\"; S. Weiss 2015, \"Procedural "
      "Terrain\", Georgia Tech CS6491): seeded sites (uniform or Poisson-disk, Bridson 2007), Lloyd relaxation to "
      "true area centroids (Lloyd 1982), the Voronoi diagram as the dual of a CGAL Delaunay triangulation clipped to "
      "the map rectangle; water per corner from Perlin noise against a radial threshold (or a mask), ocean "
      "flood-filled "
      "from the border, lakes, coast; elevation from the graph distance to the coast redistributed to the target "
      "distribution F(y) = 1 - (1 - y)^lowland_bias and flat across lakes; rivers from inland corners down the "
      "steepest descent to the ocean with volume growing downstream; moisture spreading from fresh water, x decay per "
      "step; Whittaker biomes (Whittaker 1975, as tabulated by Patel) from elevation (temperature) and moisture. "
      "Attributes: cells water, ocean, lake, coast, elevation (m), moisture, temperature, biome; corners water, "
      "ocean, lake, coast, elevation (m), moisture, moisture_raw, river, downstream, distance; edges river.");
  b.input("mask", PortType::Heightfield)
      .optional()
      .description(
          "Island shape instead of the noise: land where >= 0.5 (unitless, sampled at the corners; NaN is water)");
  b.output("out", PortType::PolygonMap).description("The island: cells, corners and edges with attributes");
  b.output("rivers", PortType::Curves)
      .description(
          "Rivers as polylines from source or confluence to the next confluence or the coast; z = elevation (m), width "
          "(m), attribute volume (number of upstream sources)");
  b.param_vec2("min_corner", {0.0, 0.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the map's lower-left corner");
  b.param_vec2("size", {4096.0, 4096.0})
      .range(1.0, 1e7)
      .soft_range(100.0, 1e5)
      .unit(Unit::Metre)
      .description("Width and height of the map");
  b.param_int("cells", 2000)
      .unit(Unit::Count)
      .range(1, 200000)
      .soft_range(100, 20000)
      .description("Number of Voronoi cells (Poisson: about that many)");
  b.param_enum("distribution", {"uniform", "poisson"}, "poisson")
      .description(
          "Sites: uniform random, or Poisson-disk (Bridson 2007) with the radius that gives about `cells` sites");
  b.param_int("relaxation", 2)
      .unit(Unit::Count)
      .range(0, 10)
      .description("Lloyd relaxation passes (each moves every site to its cell's area centroid)");
  b.param_float("shape_scale", 2.2)
      .unit(Unit::Unitless)
      .range(0.0, 20.0)
      .description(
          "Weight of the squared normalized distance from the map center in the water test (unitless; larger: smaller "
          "island)");
  b.param_float("shape_offset", -0.2)
      .unit(Unit::Unitless)
      .range(-2.0, 2.0)
      .description("Offset of the water threshold (unitless; larger: smaller island)");
  b.param_float("shape_frequency", 6.0)
      .range(0.1, 64.0)
      .unit(Unit::Unitless)
      .description("Frequency of the shape noise's first octave, lattice cells per half map width");
  b.param_int("shape_octaves", 4)
      .unit(Unit::Count)
      .range(1, 8)
      .description("Octaves of the shape noise (frequency x2, amplitude / 2.5 each)");
  b.param_float("water_fraction", 0.3)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Share of a cell's corners that must be water for the cell to be water (unitless)");
  b.param_float("max_elevation", 1000.0)
      .range(1.0, 1e5)
      .soft_range(10.0, 5000.0)
      .unit(Unit::Metre)
      .description("Elevation of the highest corner");
  b.param_float("ocean_depth", 200.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Depth of the ocean corner farthest from the coast");
  b.param_float("lowland_bias", 2.0)
      .unit(Unit::Unitless)
      .range(0.1, 10.0)
      .description(
          "Exponent k of the elevation distribution F(y) = 1 - (1 - y)^k (unitless; 1 uniform, larger: more lowland)");
  b.param_int("rivers", 60)
      .unit(Unit::Count)
      .range(0, 100000)
      .description("River sources drawn at inland corners with normalized elevation in [0.3, 0.9]");
  b.param_float("moisture_decay", 0.8)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Factor applied to moisture per corner step away from fresh water (unitless)");
  b.param_float("river_width", 6.0)
      .range(0.0, 1e4)
      .soft_range(0.0, 100.0)
      .unit(Unit::Metre)
      .description("Width of a river of volume 1 in the rivers output; width = river_width * sqrt(volume)");
  b.param_seed("seed", 0).description("Seed of the sites, the shape noise and the river sources");
  // About 1 KB per cell: sites, the Delaunay triangulation and the polygons (measured:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) {
    return per_item_bytes(static_cast<double>(q.params.get<std::int64_t>("cells")), 1024.0);
  });
  b.execute([](ExecContext& ctx) {
    IslandParams p;
    p.min_corner = ctx.param<glm::dvec2>("min_corner");
    p.size = ctx.param<glm::dvec2>("size");
    p.cells = static_cast<int>(ctx.param<std::int64_t>("cells"));
    p.distribution = ctx.enum_index("distribution") == 0 ? SiteDistribution::Uniform : SiteDistribution::Poisson;
    p.relaxation = static_cast<int>(ctx.param<std::int64_t>("relaxation"));
    p.shape_scale = ctx.param<double>("shape_scale");
    p.shape_offset = ctx.param<double>("shape_offset");
    p.shape_frequency = ctx.param<double>("shape_frequency");
    p.shape_octaves = static_cast<int>(ctx.param<std::int64_t>("shape_octaves"));
    p.water_fraction = ctx.param<double>("water_fraction");
    p.max_elevation = ctx.param<double>("max_elevation");
    p.ocean_depth = ctx.param<double>("ocean_depth");
    p.lowland_bias = ctx.param<double>("lowland_bias");
    p.rivers = static_cast<int>(ctx.param<std::int64_t>("rivers"));
    p.moisture_decay = ctx.param<double>("moisture_decay");
    p.seed = ctx.param<std::uint64_t>("seed");
    const auto mask = ctx.input<Heightfield>("mask");
    auto map = std::make_shared<PolygonMap>(generate_island(p, mask.get(), &ctx));
    ctx.check_cancelled();
    ctx.set_output("rivers", std::make_shared<Curves>(river_curves(*map, ctx.param<double>("river_width"))));
    ctx.set_output("out", std::shared_ptr<const PolygonMap>(std::move(map)));
  });
}

OROGEN_NODE(PolygonMapRaster) {
  b.reach_pointwise();  // each sample looks the map up at its own (displaced) world position
  b.category("island").description(
      "Renders a polygon map on the requested domain (A. Patel 2010, \"Polygonal Map Generation for Games\"): "
      "elevation and moisture interpolated linearly over the triangles (cell site, corner, next corner) of each "
      "cell, looked up at positions displaced by fractal Perlin noise (Perlin 2002) to hide the straight cell edges "
      "(the noisy lookup of Patel's and the Georgia Tech report's renderings); biome id, water, ocean and lake masks "
      "per cell; a river mask of width river_width * sqrt(volume); the biome's multifractal amplitude and roughness "
      "(table I of the report, for the FBM node's multifractal mode, Musgrave 1994); and the biome colors.");
  b.input("in", PortType::PolygonMap).description("Polygon map with the island's attributes (VoronoiIsland)");
  b.output("out", PortType::Heightfield)
      .description("Elevation, metres (0 at the coast, negative at sea)")
      .kind(OutputKind::Height);
  b.output("moisture", PortType::Heightfield).description("Moisture in [0, 1] (unitless)").kind(OutputKind::Mask);
  b.output("biome", PortType::Heightfield)
      .description("Biome id 0..15 (table I order: snow ... ocean)")
      .kind(OutputKind::Scalar);
  b.output("water_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("1 in ocean and lake cells, else 0")
      .kind(OutputKind::Mask);
  b.output("ocean_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("1 in ocean cells, else 0")
      .kind(OutputKind::Mask);
  b.output("lake_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("1 in lake cells, else 0")
      .kind(OutputKind::Mask);
  b.output("river_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("River coverage in [0, 1]")
      .kind(OutputKind::Mask);
  b.output("roughness", PortType::Heightfield)
      .description("Multifractal roughness R of the biome (table I), unitless")
      .kind(OutputKind::Mask);
  b.output("amplitude", PortType::Heightfield)
      .description("Multifractal amplitude A of the biome (table I), unitless")
      .kind(OutputKind::Mask);
  b.output("color", PortType::Image).description("Biome colors with rivers, linear RGBA");
  b.param_float("perturb_distance", 40.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 500.0)
      .unit(Unit::Metre)
      .description("Amplitude of the lookup displacement (0: exact polygon lookup)");
  b.param_float("perturb_feature_size", 400.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 5000.0)
      .unit(Unit::Metre)
      .description("Feature size of the displacement noise's first octave");
  b.param_float("river_width", 6.0)
      .range(0.0, 1e4)
      .soft_range(0.0, 100.0)
      .unit(Unit::Metre)
      .description("Width of a river of volume 1; width = river_width * sqrt(volume)");
  b.param_seed("seed", 0).description("Seed of the displacement noise");
  b.execute([](ExecContext& ctx) {
    const auto map = ctx.require<PolygonMap>("in");
    RasterParams p;
    p.perturb_distance = ctx.param<double>("perturb_distance");
    p.perturb_feature_size = ctx.param<double>("perturb_feature_size");
    p.river_width = ctx.param<double>("river_width");
    p.seed = ctx.param<std::uint64_t>("seed");
    RasterResult r = rasterize_polygon_map(*map, ctx.domain(), p, &ctx);
    ctx.set_output("out", r.elevation);
    ctx.set_output("moisture", r.moisture);
    ctx.set_output("biome", r.biome);
    ctx.set_output("water_mask", r.water);
    ctx.set_output("ocean_mask", r.ocean);
    ctx.set_output("lake_mask", r.lake);
    ctx.set_output("river_mask", r.river);
    ctx.set_output("roughness", r.roughness);
    ctx.set_output("amplitude", r.amplitude);
    ctx.set_output("color", r.color);
  });
}

}  // namespace orogen::island

namespace orogen::island {

OROGEN_NODE(RiverNetwork) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("island").description(
      "A river network grown as a tree before the terrain (S. Ekman et al. 2016, \"SeamScape\", Chalmers bachelor "
      "thesis, "
      "§2.2 and §3.6, after J.-D. Génevaux et al. 2013, \"Terrain generation using procedural models based on "
      "hydrology\"): outlets on the map border or on the coastline of a mask, inner points scattered by Poisson-disk "
      "sampling (Bridson 2007) at a density; from a random pool point, the nearest unused inner point whose curve "
      "crosses no existing curve joins the tree. Sizes are summed from the leaves; slopes d_c = d_p - 4 (s_c/s_p)"
      "(s_c/s_p - 1) w and heights h_c = h_p + |c - p| d_c rise upstream from 0 at the outlets. Each edge is a "
      "quadratic Bézier curve B(t) = (1-t)^2 P0 + 2(1-t)t P1 + t^2 P2; a point's first branch continues the tangent "
      "of the curve arriving there. One curve per edge, upstream to downstream, parent = the curve it flows into.");
  b.input("mask", PortType::Heightfield)
      .optional()
      .description("Land mask (unitless, land >= 0.5): outlets on its coastline, inner points and curves on land");
  b.output("out", PortType::Curves)
      .description(
          "River curves: z = height (m), width (m); attributes size (leaves below), slope (m/m), smooth_join (1 where "
          "the "
          "curve continues its parent's tangent)");
  b.param_vec2("min_corner", {0.0, 0.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the network's lower-left corner");
  b.param_vec2("size", {4096.0, 4096.0})
      .range(1.0, 1e7)
      .soft_range(100.0, 1e5)
      .unit(Unit::Metre)
      .description("Width and height of the network's rectangle");
  b.param_int("outlets", 5)
      .unit(Unit::Count)
      .range(0, 1000)
      .soft_range(1, 50)
      .description("Number of outlets (roots) on the border or the coastline");
  b.param_float("density", 40.0)
      .range(0.0, 10000.0)
      .soft_range(1.0, 500.0)
      .unit(Unit::PerSquareKilometre)
      .description("Inner points per square kilometre");
  b.param_float("max_length", 400.0)
      .range(1.0, 1e6)
      .soft_range(20.0, 5000.0)
      .unit(Unit::Metre)
      .description("Longest river segment (candidate search radius)");
  b.param_float("base_gradient", 0.02)
      .range(0.0, 10.0)
      .soft_range(0.0, 0.5)
      .unit(Unit::MetrePerMetre)
      .description("Slope d at the outlets");
  b.param_float("gradient_weight", 0.02)
      .range(0.0, 10.0)
      .soft_range(0.0, 0.5)
      .unit(Unit::MetrePerMetre)
      .description("w: slope added upstream, most for branches of half their parent's size");
  b.param_float("river_width", 3.0)
      .range(0.0, 1e4)
      .soft_range(0.0, 100.0)
      .unit(Unit::Metre)
      .description("Width of a river of size 1");
  b.param_float("width_exponent", 0.5)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Width = river_width * size^exponent (1: width proportional to size, as in SeamScape)");
  b.param_float("meander", 0.25)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Largest sideways offset of a free control point, as a fraction of the chord");
  b.param_int("samples", 8).unit(Unit::Count).range(1, 64).description("Polyline segments per Bézier curve");
  b.param_seed("seed", 0).description("Seed of the outlets, the inner points and the growth order");
  // About 1.5 KB per point of the network (density x area), with its triangulation (measured:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) {
    const glm::dvec2 size = q.params.get<glm::dvec2>("size");
    return per_item_bytes(q.params.get<double>("density") * size.x * size.y * 1e-6, 1536.0);
  });
  b.execute([](ExecContext& ctx) {
    RiverNetworkParams p;
    p.min_corner = ctx.param<glm::dvec2>("min_corner");
    p.size = ctx.param<glm::dvec2>("size");
    p.outlets = static_cast<int>(ctx.param<std::int64_t>("outlets"));
    p.density = ctx.param<double>("density");
    p.max_length = ctx.param<double>("max_length");
    p.base_slope = ctx.param<double>("base_gradient");
    p.slope_weight = ctx.param<double>("gradient_weight");
    p.river_width = ctx.param<double>("river_width");
    p.width_exponent = ctx.param<double>("width_exponent");
    p.meander = ctx.param<double>("meander");
    p.samples = static_cast<int>(ctx.param<std::int64_t>("samples"));
    p.seed = ctx.param<std::uint64_t>("seed");
    const auto mask = ctx.input<Heightfield>("mask");
    ctx.set_output("out", std::make_shared<Curves>(river_network(p, mask.get(), &ctx)));
  });
}

OROGEN_NODE(CarveRivers) {
  b.reach_pointwise();  // each sample reads the terrain at itself and the curves
  b.category("island").description(
      "Carves river curves into a terrain (S. Ekman et al. 2016, \"SeamScape\", Chalmers bachelor thesis, §2.2.4, "
      "with its weight corrected): within `radius` the terrain blends toward the river height with the smoothstep "
      "weight "
      "s(1 - d/r), s(t) = t^2 (3 - 2t); the river height is the nearest curve's height on it and the mean of the "
      "nearby curves midway between two; inside the channel (d < width/2) a parabolic bed depth_ratio * width deep. "
      "Takes any curves with per-vertex z and width: RiverNetwork, RiverExtract, VoronoiIsland rivers.");
  b.input("in", PortType::Heightfield).description("Terrain heights, metres");
  b.input("rivers", PortType::Curves).description("River curves: z = river height (m), per-vertex width (m)");
  b.output("out", PortType::Heightfield).description("Carved terrain, metres").kind(OutputKind::Height);
  b.output("river_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("Channel coverage in [0, 1]")
      .kind(OutputKind::Mask);
  b.param_float("radius", 150.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Distance over which the terrain blends into the river height");
  b.param_float("depth_ratio", 0.1)
      .range(0.0, 10.0)
      .soft_range(0.0, 1.0)
      .unit(Unit::Factor)
      .description("Channel depth per metre of river width");
  b.param_float("strength", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Scales the blend weight (0: only the channel is cut)");
  // Working memory beyond the outputs, 24 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 24); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto rivers = ctx.require<Curves>("rivers");
    const CarveParams p{ctx.param<double>("radius"), ctx.param<double>("depth_ratio"), ctx.param<double>("strength")};
    CarveResult r = carve_rivers(*in, *rivers, p, &ctx);
    ctx.set_output("out", r.terrain);
    ctx.set_output("river_mask", r.mask);
  });
}

}  // namespace orogen::island
