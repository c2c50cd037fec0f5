// PoissonDisk: the node over poisson_disk().
#include <cmath>
#include <stdexcept>
#include <string>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/scatter/poisson_disk.h"
#include "nodes/scatter/run_placement.h"

namespace orogen {

inline constexpr int kPoissonSlots = 4;

OROGEN_NODE(PoissonDisk) {
  // Without fill_border the points inside any rectangle are the same whichever domain asks (tile invariant); with it
  // the sampling fills up to the edges of the domain asked for, so tiled builds compute it whole and cut it.
  b.distribution(
      [](const ParamView& p) { return p.get<bool>("fill_border") ? Distribution::Gathered : Distribution::PerTile; },
      "gathered with fill_border (it fills up to the edges of the domain it is asked for), else per-tile");
  b.reach_global();  // outputs points, not a field
  b.category("scatter").description(
      "Blue-noise placement: Bridson (2007), \"Fast Poisson disk sampling in arbitrary dimensions\" (k "
      "candidates in the annulus [r, 2r], background grid of cell r/sqrt 2), run over world-space chunks in the "
      "phase order of Wei (2008), \"Parallel Poisson disk sampling\", and completed by the gap filling of Ebeida "
      "et al. (2011), \"Efficient maximal Poisson-disk sampling\", so the sampling is maximal: exactly (up to the "
      "float rounding of positions) for one class without density or mask, up to gaps narrower than about a "
      "thousandth of r otherwise (a 45th along a mask's border). Up to four classes (class ids first_class + "
      "0..3), largest radius first; two classes keep cross_separation * (r_i + r_j) / 2 apart. A density field "
      "makes the radius variable (r / sqrt(density)), so counts follow the density. With fill_border (the "
      "default) the domain is sampled up to its edges, which are filled like its interior. Without it the node "
      "returns the points of the plane's sampling that fall inside the domain: tile invariant (the points inside "
      "any rectangle are the same whichever domain asks, so tiles join seamlessly), but a spot within r of the "
      "domain's edge may be free, its covering point lying beyond. Either way resolution independent and the "
      "same for any thread count (density fields must cover the domain plus the halo of (4 * classes - 1) "
      "chunks of max(2 r_max, 8 r_min)). Output attribute: radius (m).");
  b.input("density", PortType::Heightfield).optional().description("Density for every class, 0..1 (unitless)");
  b.input("mask", PortType::Heightfield).optional().description("Points only where mask >= 0.5 (unitless)");
  for (int k = 0; k < kPoissonSlots; ++k)
    b.input("density_" + std::to_string(k), PortType::Heightfield)
        .optional()
        .description("Density of class " + std::to_string(k) + ", 0..1 (unitless), times the common density");
  b.input("height", PortType::Heightfield).optional().description("Terrain height (m): sets z of the points");
  b.output("out", PortType::Points).description("The points, class id 0..class_count-1, attribute radius (m)");
  b.param_int("class_count", 1).range(1, kPoissonSlots).unit(Unit::Count).description("Number of classes, 1..4");
  const double defaults[kPoissonSlots] = {5.0, 2.0, 1.0, 0.5};
  for (int k = 0; k < kPoissonSlots; ++k)
    b.param_float("radius_" + std::to_string(k), defaults[k])
        .range(0.01, 1e4)
        .soft_range(0.1, 100)
        .unit(Unit::Metre)
        .description("Minimum distance between two points of class " + std::to_string(k) +
                     " at density 1, metres in [0.01, 10000]");
  b.param_float("cross_separation", 1.0)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description(
          "Distance between points of different classes as a fraction of the mean of their radii, 0..1 "
          "(0: classes ignore each other, like rocks placed beside trees)");
  b.param_float("min_density", 0.1)
      .range(0.01, 1.0)
      .unit(Unit::Unitless)
      .description(
          "Density below which no point is placed, 0.01..1; bounds the largest radius at r / sqrt(min_density)");
  b.param_int("attempts", 8)
      .range(1, 100)
      .unit(Unit::Count)
      .description(
          "Bridson's k: candidates tried around an active point before it retires, 1..100 (with fill_gaps the "
          "gap filling makes the sampling maximal whatever k; a larger k only moves work from it to Bridson)");
  b.param_bool("fill_gaps", true)
      .description("Fill the gaps Bridson's sampling leaves (Ebeida et al. 2011) so no further point fits");
  b.param_bool("fill_border", true)
      .description(
          "Sample the domain up to its edges (maximal on the domain); off: crop the plane's sampling to the "
          "domain, so tiles join seamlessly but spots near the edges may stay free");
  b.param_int("first_class", 0)
      .range(0, 1000000)
      .unit(Unit::Id)
      .description("Class id of the first class; class k gets first_class + k, 0..1e6");
  b.param_seed("seed", 0).description("Every draw hashes (seed, class, world chunk, counter)");
  b.extra_bytes([](const CostQuery& q) {
    // About one point per r^2 of the domain for each class at density 1, 52 bytes a point (position,
    // rotation, scale, class, radius).
    const glm::dvec2 size = q.domain.size();
    double points = 0.0;
    for (std::int64_t k = 0; k < q.params.get<std::int64_t>("class_count"); ++k) {
      const double r = q.params.get<double>("radius_" + std::to_string(k));
      points += size.x * size.y / (r * r);
    }
    return per_item_bytes(points, 52.0);
  });
  b.execute([](ExecContext& ctx) {
    PoissonParams p;
    const int count = static_cast<int>(ctx.param<std::int64_t>("class_count"));
    std::vector<HeightfieldPtr> keep;
    for (int k = 0; k < count; ++k) {
      PoissonClass c;
      c.radius = ctx.param<double>("radius_" + std::to_string(k));
      c.class_id = static_cast<std::int32_t>(ctx.param<std::int64_t>("first_class") + k);
      auto d = world_sampled_input(ctx, "density_" + std::to_string(k), ctx.domain());
      c.density = d.get();
      keep.push_back(d);
      p.classes.push_back(c);
    }
    const auto density = world_sampled_input(ctx, "density", ctx.domain());
    const auto mask = world_sampled_input(ctx, "mask", ctx.domain());
    const auto height = world_sampled_input(ctx, "height", ctx.domain());
    p.density = density.get();
    p.mask = mask.get();
    p.cross_separation = ctx.param<double>("cross_separation");
    p.min_density = ctx.param<double>("min_density");
    p.attempts = static_cast<int>(ctx.param<std::int64_t>("attempts"));
    p.fill_gaps = ctx.param<bool>("fill_gaps");
    p.seed = ctx.param<std::uint64_t>("seed");
    p.bounded = ctx.param<bool>("fill_border");
    p.bounds_lo = ctx.domain().min_corner();
    p.bounds_hi = ctx.domain().max_corner();
    ctx.set_output(
        "out",
        scatter::run_placement(
            [&] { return poisson_disk(ctx.domain().min_corner(), ctx.domain().max_corner(), p, &ctx); }, height.get()));
  });
}

}  // namespace orogen
