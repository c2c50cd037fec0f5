// ShadePlacement and ForestLifeCycle: the nodes over forest.h.
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/scatter/run_placement.h"
#include "nodes/scatter/forest.h"
#include "nodes/climate/sun.h"

namespace orogen {

OROGEN_NODE(ShadePlacement) {
  // A shadow is cast from crowns anywhere in the domain, unless max_shadow_distance bounds it: then a tile needs
  // the casters within that distance of it, its halo, and the tiles are computed apart.
  b.reach(
      [](const ParamView& p) {
        const double d = p.get<double>("max_shadow_distance");
        return d > 0.0 ? Reach::local(d, 1) : Reach::global();
      },
      "global; local: max_shadow_distance + 1 sample when it is set");
  b.distribution(
      [](const ParamView& p) {
        return p.get<double>("max_shadow_distance") > 0.0 ? Distribution::PerTile : Distribution::Gathered;
      },
      "gathered; per-tile with max_shadow_distance (each tile with the casters within it)");
  b.category("scatter").description(
      "Context-sensitive placement by light, after Potter (2017), \"Generating a virtual forest environment using "
      "procedural content generation\" (shadow-map placement): "
      "the crowns of the caster points (spheres of crown_radius * scale at crown_height * scale above them) cast "
      "shadows along the sun direction; a candidate point is shaded if the ray from it toward the sun meets a "
      "crown (exact ray-sphere tests, no raster). preference shade keeps the shaded candidates (undergrowth "
      "under trees), sun keeps the lit ones, any keeps all. Attribute shade (1 shaded, 0 lit); output shade is "
      "the shadow map on the domain. The sun is given by its azimuth and elevation, or (sun = time) placed for a "
      "latitude, day of the year and solar hour: declination by P. I. Cooper (1969), The absorption of radiation "
      "in solar stills, hour angle 15 deg/h from solar noon, elevation and azimuth by the spherical astronomy of "
      "J. A. Duffie, W. A. Beckman (2013), Solar Engineering of Thermal Processes, ch. 1; with the sun under the "
      "horizon (night) there is no direct light and every candidate is shaded.");
  b.input("in", PortType::Points).description("Candidate points (e.g. undergrowth from PoissonDisk)");
  b.input("casters", PortType::Points).description("Points whose crowns cast shade (e.g. trees)");
  b.input("height", PortType::Heightfield).optional().description("Terrain heights (m) for the shadow map; else z = 0");
  b.output("out", PortType::Points).description("The kept candidates, attribute shade");
  b.output("shade", PortType::Heightfield)
      .description("Shadow map, 1 shaded / 0 lit (unitless)")
      .kind(OutputKind::Mask);
  b.param_enum("preference", {"shade", "sun", "any"}, "shade")
      .description("shade: keep shaded candidates; sun: keep lit ones; any: keep all (annotate only)");
  b.param_enum("sun", {"angles", "time"}, "angles")
      .description(
          "angles: the sun at sun_azimuth and sun_elevation; time: the sun's position at latitude, day_of_year and "
          "hour");
  b.param_float("sun_azimuth", 180.0)
      .range(0.0, 360.0)
      .unit(Unit::Degree)
      .description("Direction of the sun, degrees clockwise from north (180: the sun in the south), 0..360");
  b.param_float("sun_elevation", 45.0)
      .range(1.0, 90.0)
      .unit(Unit::Degree)
      .description("Height of the sun above the horizon, degrees in [1, 90]");
  b.param_float("latitude", 45.0)
      .range(-90.0, 90.0)
      .unit(Unit::Degree)
      .description("sun = time: latitude, degrees in [-90, 90], north positive");
  b.param_int("day_of_year", 172)
      .unit(Unit::DayOfYear)
      .range(1, 366)
      .description("sun = time: day of the year, 1 (January 1st) .. 366; 172 is June 21st");
  b.param_float("hour", 15.0)
      .range(0.0, 24.0)
      .unit(Unit::Hour)
      .description("sun = time: local solar time, decimal hours in [0, 24] (h + min/60 + s/3600; 12 = solar noon)");
  b.param_float("crown_radius", 3.0)
      .range(0.01, 1000.0)
      .unit(Unit::Metre)
      .description("Radius of a caster's crown at scale 1, metres in [0.01, 1000] (times the point's x scale)");
  b.param_float("crown_height", 8.0)
      .range(0.0, 1000.0)
      .unit(Unit::Metre)
      .description(
          "Height of the crown's center above the caster point at scale 1, metres in [0, 1000] (times its z scale)");
  b.param_float("max_shadow_distance", 0.0)
      .range(0.0, 1e6)
      .unit(Unit::Metre)
      .description(
          "A crown whose center lies farther than this from a point, measured horizontally, does not shade it; "
          "metres in [0, 1e6], 0 for any distance. Set it (longer than the longest shadow that matters, about "
          "crown height / tan(sun elevation)) to let tiled and distributed builds compute each tile with its "
          "neighborhood only, instead of the whole domain on one rank");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Points>("in");
    const auto casters = ctx.require<Points>("casters");
    const auto height = world_sampled_input(ctx, "height", ctx.domain());
    ShadePlacementParams p;
    p.canopy.crown_radius = ctx.param<double>("crown_radius");
    p.canopy.crown_height = ctx.param<double>("crown_height");
    p.canopy.max_shadow_distance = ctx.param<double>("max_shadow_distance");
    if (ctx.param<std::string>("sun") == "time")
      p.canopy.sun = climate::sun_direction(
          ctx.param<double>("latitude"),
          climate::declination_for_day(static_cast<double>(ctx.param<std::int64_t>("day_of_year"))),
          ctx.param<double>("hour"));
    else
      p.canopy.sun = sun_direction(ctx.param<double>("sun_azimuth"), ctx.param<double>("sun_elevation"));
    static constexpr ShadePreference kPreferences[] = {ShadePreference::Shade, ShadePreference::Sun,
                                                       ShadePreference::Any};
    p.preference = kPreferences[ctx.enum_index("preference")];
    ShadePlacementResult r = shade_placement(*in, *casters, ctx.domain(), height.get(), p, &ctx);
    ctx.set_output("out", std::make_shared<Points>(std::move(r.points)));
    ctx.set_output("shade", std::make_shared<Heightfield>(std::move(r.shade)));
  });
}

OROGEN_NODE(ForestLifeCycle) {
  b.distribution(Distribution::Gathered);
  b.reach_global();  // a simulation
  b.category("scatter").description(
      "Forest life cycle after Potter (2017), \"Generating a virtual forest environment using procedural content "
      "generation\" (stepped aging): each year every tree ages, "
      "its scale grows linearly from min_scale to max_scale over maturity_age, trees older than max_age die and "
      "drop one or two seeds within dispersal_distance, mature trees drop a seed with dispersal_probability; trees "
      "closer "
      "than competition * (s_i + s_j) / 2 compete and the smaller dies (self-thinning); seeds germinate inside "
      "the domain where suitability >= 0.5 and there is room. Deterministic per seed (fixed order, hashed "
      "draws). Output: the survivors with attribute age (years) and their scale.");
  b.input("in", PortType::Points).description("Initial trees (attribute age in years if present, else hashed)");
  b.input("suitability", PortType::Heightfield)
      .optional()
      .description(
          "Where seeds may germinate: >= 0.5 (unitless), e.g. a ScatterRules-like mask; everywhere if unconnected");
  b.input("height", PortType::Heightfield).optional().description("Terrain heights (m): sets z of the survivors");
  b.output("out", PortType::Points).description("Surviving trees: class id of their lineage, scale, attribute age");
  b.param_int("years", 50).range(0, 1000).unit(Unit::Year).description("Years simulated, 0..1000");
  b.param_float("max_age", 80.0).range(1.0, 5000.0).unit(Unit::Year).description("Age at which a tree dies, years");
  b.param_float("maturity_age", 20.0)
      .range(0.0, 5000.0)
      .unit(Unit::Year)
      .description("Years to grow from min_scale to max_scale; from then on a tree drops seeds");
  b.param_float("min_scale", 0.2).range(0.01, 100.0).unit(Unit::Factor).description("Scale of a seedling, 0.01..100");
  b.param_float("max_scale", 1.0)
      .range(0.01, 100.0)
      .unit(Unit::Factor)
      .description("Scale of a mature tree, 0.01..100 (at least min_scale)");
  b.param_float("dispersal_distance", 12.0)
      .range(0.0, 1e4)
      .unit(Unit::Metre)
      .description("Seeds land uniformly within this distance of their parent, metres");
  b.param_float("dispersal_probability", 0.1)
      .range(0.0, 1.0)
      .unit(Unit::PerYear)
      .description("Probability per year that a mature tree drops a seed, 0..1");
  b.param_float("competition", 6.0)
      .range(0.0, 1e4)
      .unit(Unit::Metre)
      .description("Spacing two trees of scale 1 need, metres; two trees keep competition * (s_i + s_j) / 2 apart");
  b.param_seed("seed", 0).description("Draws hash (seed, tree id, year)");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Points>("in");
    const auto suit = world_sampled_input(ctx, "suitability", ctx.domain());
    const auto height = world_sampled_input(ctx, "height", ctx.domain());
    LifeCycleParams p;
    p.years = static_cast<int>(ctx.param<std::int64_t>("years"));
    p.max_age = ctx.param<double>("max_age");
    p.maturity_age = ctx.param<double>("maturity_age");
    p.min_scale = ctx.param<double>("min_scale");
    p.max_scale = ctx.param<double>("max_scale");
    if (p.max_scale < p.min_scale) throw NodeError("ForestLifeCycle: max_scale is below min_scale");
    p.seed_distance = ctx.param<double>("dispersal_distance");
    p.seed_probability = ctx.param<double>("dispersal_probability");
    p.competition = ctx.param<double>("competition");
    p.suitability = suit.get();
    p.lo = ctx.domain().min_corner();
    p.hi = ctx.domain().max_corner();
    p.seed = ctx.param<std::uint64_t>("seed");
    if (in->size() > 5'000'000) throw NodeError("ForestLifeCycle: more than 5 million initial trees");
    ctx.set_output("out", scatter::run_placement([&] { return forest_life_cycle(*in, p, &ctx); }, height.get()));
  });
}

}  // namespace orogen
