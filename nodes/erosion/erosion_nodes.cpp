// The erosion family's nodes: thin declarations over thermal.h, particles.h, pipe.h and stream_power.h.
// Every node takes `in` (height, m) and an optional `mask` (0..1) scaling its effect, and outputs `out`
// (eroded height), `erosion` (m removed), `deposition` (m laid down) and `flow` (0..1 where water ran).
// All are global: a simulation's output at a point depends on the whole domain.
#include <string>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/report_builder.h"
#include "nodes/erosion/particles.h"
#include "nodes/erosion/pipe.h"
#include "nodes/erosion/stream_power.h"
#include "nodes/erosion/thermal.h"

namespace orogen {
namespace {

using erosion::ErosionMaps;

void declare_common_ports(NodeBuilder& b, const char* mask_text) {
  b.input("in", PortType::Heightfield).description("Height to erode, metres");
  b.input("mask", PortType::Heightfield).optional().description(mask_text);
  b.output("out", PortType::Heightfield).description("Eroded height, metres");
  b.output("erosion", PortType::Heightfield)
      .description("Material removed, metres (>= 0); the 'wear' map")
      .kind(OutputKind::Scalar);
  b.output("deposition", PortType::Heightfield)
      .description("Material laid down, metres (>= 0); the 'deposits' map")
      .kind(OutputKind::Scalar);
  b.output("flow", PortType::Heightfield).description("Where water (or material) ran, 0..1").kind(OutputKind::Mask);
}

// The maps a node computed: those it skipped (nothing linked to them) stay unset.
void set_common_outputs(ExecContext& ctx, ErosionMaps& m) {
  ctx.set_output("out", m.out);
  if (m.erosion) ctx.set_output("erosion", m.erosion);
  if (m.deposition) ctx.set_output("deposition", m.deposition);
  if (m.flow) ctx.set_output("flow", m.flow);
}

}  // namespace

OROGEN_NODE(ThermalErosion) {
  b.distribution(Distribution::HaloExchange);
  b.reach_global();  // a simulation: every output sample depends on the whole input
  b.category("erosion").description(
      "Thermal erosion (talus slumping): material steeper than the talus angle slides to its lower "
      "neighbors until no slope exceeds the angle (Musgrave, Kolb and Mace 1989, 'The synthesis and "
      "rendering of eroded fractal terrains'; Olsen 2004, 'Realtime procedural terrain generation'). Slopes "
      "are measured over the true distance to all 8 neighbors, so an angle gives the same slopes at any "
      "resolution. Volume is conserved; bit-identical for any thread count, and in a tiled or distributed build, "
      "where tiles exchange halos every few iterations, for any tiling and rank count.");
  declare_common_ports(b, "Scales how fast material leaves each cell, 0..1 (1 if unconnected)");
  b.input("hardness", PortType::Heightfield)
      .optional()
      .description("Rock hardness 0..1: raises a cell's talus angle toward 89 degrees (1: cliffs that never slump)");
  b.param_float("talus_angle", 35.0)
      .range(1.0, 89.0)
      .unit(Unit::Degree)
      .description("Angle of repose: steeper slopes slump");
  b.param_float("strength", 0.5)
      .unit(Unit::Unitless)
      .range(0.01, 1.0)
      .description("Share of the excess over the talus moved per iteration (unitless); lower is smoother but slower");
  b.param_float("travel_distance", 500.0)
      .range(1.0, 1e5)
      .soft_range(10.0, 5000.0)
      .unit(Unit::Metre)
      .description(
          "How far material may travel: the iteration count is 2 x distance / spacing (stops early once settled)");
  b.param_float("tolerance", 1e-4)
      .range(0.0, 10.0)
      .unit(Unit::Metre)
      .description("Stop when no cell moves more than this in an iteration");
  // Working memory beyond the outputs, 20 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 20); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto mask = secondary_input<Heightfield>(ctx, "mask", in->domain);
    const auto hard = secondary_input<Heightfield>(ctx, "hardness", in->domain);
    erosion::ThermalParams p;
    p.talus_angle = ctx.param<double>("talus_angle");
    p.strength = ctx.param<double>("strength");
    p.travel_distance = ctx.param<double>("travel_distance");
    p.tolerance = ctx.param<double>("tolerance");
    auto m = erosion::thermal_erosion(*in, p, mask.get(), hard.get(), &ctx);
    set_common_outputs(ctx, m);
  });
}

OROGEN_NODE(HydraulicErosion) {
  // Across tiles: the droplet schedule's phases, the changed samples exchanged between them
  // (particles_across_tiles.cpp).
  b.distribution(Distribution::HaloExchange);
  b.reach_global();  // a simulation: every output sample depends on the whole input
  // Version 2: the report output (the volume balance). Version 3: deposits with the erosion's brush, and a
  // droplet in a hollow fills it up to its spill height (issue 29: fewer closed pits on fine grids).
  b.category("erosion").version(3).description(
      "Particle hydraulic erosion after Beyer 2015, 'Implementation of a method for hydraulic erosion' (TU "
      "Munich): droplets start at random places, run downhill with inertia, erode with a brush where they "
      "can carry more and deposit with the same brush where they carry too much; a droplet that runs into a "
      "hollow fills it up to where it spills rather than leaving a closed pit. Droplets per km^2, brush "
      "radius, step length and lifetime are in metres and sediment is a volume, so results agree across "
      "resolutions. Droplets run in a fixed schedule of blocks of the domain, each block's droplets in index "
      "order: bit-identical for any thread count, and for any tiling and rank count, where tiles run the "
      "blocks and exchange the samples each phase changed. The report balances the volumes: eroded = "
      "deposited + carried off the border.");
  declare_common_ports(b, "Scales erosion and deposition per cell, 0..1 (1 if unconnected)");
  b.output("report", PortType::Report)
      .description(
          "Volume balance (m^3): eroded, deposited, carried_off (sediment that left the domain with its droplet); "
          "droplets, steps");
  b.param_float("droplets_per_km2", 20000.0)
      .range(0.0, 1e8)
      .soft_range(1000.0, 200000.0)
      .unit(Unit::PerSquareKilometre)
      .description("Droplets per square kilometre of the domain");
  b.param_float("step_length", 10.0)
      .range(0.01, 1e4)
      .soft_range(1.0, 50.0)
      .unit(Unit::Metre)
      .description("Distance a droplet moves per step (about one sample spacing)");
  b.param_float("lifetime", 300.0)
      .range(0.01, 1e5)
      .soft_range(10.0, 3000.0)
      .unit(Unit::Metre)
      .description("Distance a droplet travels before it evaporates");
  b.param_float("radius", 30.0)
      .range(0.0, 1e4)
      .soft_range(0.0, 200.0)
      .unit(Unit::Metre)
      .description("Erosion brush radius");
  b.param_float("inertia", 0.05)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Share of the previous direction a droplet keeps (unitless)");
  b.param_float("capacity", 4.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 50.0)
      .unit(Unit::CubicMetre)
      .description("Sediment a droplet carries per unit slope x speed x water");
  b.param_float("min_gradient", 0.01)
      .range(0.0, 10.0)
      .unit(Unit::MetrePerMetre)
      .description("Slope floor of the capacity, so droplets on flats still carry");
  b.param_float("deposition", 0.3)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Share of the surplus sediment deposited per step (unitless)");
  b.param_float("erosion", 0.3)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Share of the free capacity eroded per step (unitless)");
  b.param_float("evaporation", 0.01)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Share of the water evaporated per step (unitless)");
  b.param_float("gravity", 4.0)
      .range(0.0, 100.0)
      .unit(Unit::MetrePerSecondSquared)
      .description("Speed gain: speed^2 grows by gravity x drop in metres");
  b.param_seed("seed", 0).description("Droplet origins and directions hash (seed, droplet index)");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto mask = secondary_input<Heightfield>(ctx, "mask", in->domain);
    erosion::ParticleParams p;
    p.droplets_per_km2 = ctx.param<double>("droplets_per_km2");
    p.step_length = ctx.param<double>("step_length");
    p.lifetime = ctx.param<double>("lifetime");
    p.radius = ctx.param<double>("radius");
    p.inertia = ctx.param<double>("inertia");
    p.capacity = ctx.param<double>("capacity");
    p.min_slope = ctx.param<double>("min_gradient");
    p.deposition = ctx.param<double>("deposition");
    p.erosion = ctx.param<double>("erosion");
    p.evaporation = ctx.param<double>("evaporation");
    p.gravity = ctx.param<double>("gravity");
    p.seed = ctx.param<std::uint64_t>("seed");
    p.change_maps = ctx.output_requested("erosion") || ctx.output_requested("deposition");
    p.flow_map = ctx.output_requested("flow");
    erosion::ParticleStats stats;
    auto m = erosion::particle_erosion(*in, p, mask.get(), &ctx, &stats);
    set_common_outputs(ctx, m);
    ReportJson j;
    j["eroded"] = report_number(stats.eroded);
    j["deposited"] = report_number(stats.deposited);
    j["carried_off"] = report_number(stats.carried_off);
    j["droplets"] = stats.droplets;
    j["steps"] = stats.steps;
    ctx.set_output("report", make_report(j));
  });
}

OROGEN_NODE(PipeErosion) {
  b.distribution(Distribution::HaloExchange);
  b.reach_global();  // a simulation: every output sample depends on the whole input
  b.category("erosion").description(
      "Shallow-water hydraulic erosion on virtual pipes (Mei, Decaudin and Hu 2007, 'Fast hydraulic erosion "
      "simulation and visualization on GPU'): rain, outflow fluxes, water and velocity fields, sediment "
      "capacity from speed and tilt, dissolution, deposition, transport with the water, evaporation. The "
      "time step follows a CFL condition on the cell size, so a finer grid takes more, smaller steps of the "
      "same physical duration. Cells under sea level are sinks; water and sediment leave at the border. "
      "Bit-identical for any thread count, and in a tiled or distributed build, where tiles exchange a 2-sample "
      "halo every time step and all take the step of the deepest water over all tiles, for any tiling and rank "
      "count.");
  declare_common_ports(b, "Scales dissolution and deposition per cell, 0..1 (1 if unconnected)");
  b.input("rainfall_rate", PortType::Heightfield)
      .unit(Unit::MillimetrePerHour)
      .optional()
      .description("Rain rate per cell, mm/h (replaces the rainfall_rate parameter)");
  b.input("moisture", PortType::Heightfield).optional().description("Drops mode: chance factor of rain per cell, 0..1");
  b.input("evaporation_factor", PortType::Heightfield)
      .optional()
      .description("Evaporation factor per cell (1 nominal, >= 0)");
  b.input("hardness", PortType::Heightfield)
      .optional()
      .description("Soil hardness 0..1: slows dissolution by (1 - hardness)");
  b.output("water_depth", PortType::Heightfield)
      .unit(Unit::Metre)
      .description("Water depth at the end, metres")
      .kind(OutputKind::WaterDepth);
  b.output("velocity", PortType::Heightfield).description("Water speed at the end, m/s").kind(OutputKind::Scalar);
  b.param_float("duration", 1800.0)
      .range(0.0, 1e7)
      .soft_range(60.0, 20000.0)
      .unit(Unit::Second)
      .description("Simulated time");
  b.param_float("rainfall_rate", 50.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 500.0)
      .unit(Unit::MillimetrePerHour)
      .description("Rain rate (uniform mode, or where no rainfall field)");
  b.param_enum("rain_mode", {"uniform", "drops"}, "uniform")
      .description(
          "uniform: rain everywhere; drops: random drops with a chance scaled by the moisture field (Mei 2007 / the "
          "Georgia Tech model)");
  b.param_float("drop_chance", 0.1)
      .range(1e-6, 100.0)
      .unit(Unit::PerSecond)
      .description("Drops mode: chance of a drop per cell and second at moisture 1");
  b.param_float("capacity", 1.0)
      .range(0.0, 1e4)
      .unit(Unit::SecondPerMetre)
      .description("Kc: sediment capacity (m) per unit sin(tilt) x speed (m/s) x water depth (m)");
  b.param_float("dissolving", 0.1)
      .range(0.0, 1e3)
      .unit(Unit::PerSecond)
      .description("Ks: rate of dissolution toward capacity");
  b.param_float("depositing", 0.1)
      .range(0.0, 1e3)
      .unit(Unit::PerSecond)
      .description("Kd: rate of deposition of the surplus");
  b.param_float("evaporation", 0.001)
      .range(0.0, 10.0)
      .unit(Unit::PerSecond)
      .description("Ke: share of the water evaporated per second");
  b.param_float("gravity", 9.81)
      .range(0.1, 100.0)
      .unit(Unit::MetrePerSecondSquared)
      .description("Gravitational acceleration of the flow");
  b.param_float("courant", 0.25)
      .unit(Unit::Unitless)
      .range(0.01, 0.5)
      .description("CFL number of the time step (unitless)");
  b.param_float("layer_depth", 0.0)
      .range(0.0, 1e4)
      .unit(Unit::Metre)
      .description("Soil doubles in hardness every layer_depth eroded (0: uniform soil)");
  b.param_float("sea_level", -1e4).range(-1e9, 1e9).unit(Unit::Metre).description("Cells below are sinks");
  b.param_seed("seed", 0).description("Drops mode: where drops fall hashes (seed, step, row)");
  // Working memory beyond the outputs, 64 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 64); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto mask = secondary_input<Heightfield>(ctx, "mask", in->domain);
    const auto rain = secondary_input<Heightfield>(ctx, "rainfall_rate", in->domain);
    const auto moist = secondary_input<Heightfield>(ctx, "moisture", in->domain);
    const auto temp = secondary_input<Heightfield>(ctx, "evaporation_factor", in->domain);
    const auto hard = secondary_input<Heightfield>(ctx, "hardness", in->domain);
    erosion::PipeParams p;
    p.duration = ctx.param<double>("duration");
    p.rain_rate = ctx.param<double>("rainfall_rate");
    p.rain_mode = ctx.enum_index("rain_mode") == 0 ? erosion::RainMode::Uniform : erosion::RainMode::Drops;
    p.drop_chance = ctx.param<double>("drop_chance");
    p.capacity = ctx.param<double>("capacity");
    p.dissolving = ctx.param<double>("dissolving");
    p.depositing = ctx.param<double>("depositing");
    p.evaporation = ctx.param<double>("evaporation");
    p.gravity = ctx.param<double>("gravity");
    p.courant = ctx.param<double>("courant");
    p.layer_depth = ctx.param<double>("layer_depth");
    p.sea_level = ctx.param<double>("sea_level");
    p.seed = ctx.param<std::uint64_t>("seed");
    auto m = erosion::pipe_erosion(*in, p, mask.get(), rain.get(), moist.get(), temp.get(), hard.get(), &ctx);
    set_common_outputs(ctx, m);
    ctx.set_output("water_depth", m.water);
    ctx.set_output("velocity", m.velocity);
  });
}

OROGEN_NODE(StreamPower) {
  // With the Priority-Flood fill every stage of a step runs across tiles, exact (stream_power_across_tiles.cpp); the
  // basin graph's reroutes follow a minimum spanning tree of the whole domain's pits, so it is computed whole.
  b.distribution(
      [](const ParamView& p) {
        return p.get<std::string>("depressions") == "priority_flood" ? Distribution::TileGraph : Distribution::Gathered;
      },
      "tile-graph with depressions 'priority_flood' (each step's fill, routing, areas and incision exact across "
      "tiles), gathered with 'basin_graph'");
  b.reach_global();  // a simulation: every output sample depends on the whole input
  b.category("erosion").description(
      "Landscape evolution by the stream-power law dz/dt = U - K A^m S^n + D laplacian(z) (Howard 1994; "
      "Whipple and Tucker 1999), solved with the implicit O(n) scheme of Braun and Willett 2013, 'A very "
      "efficient O(n), implicit and parallel method to solve the stream power equation' (Newton iteration "
      "for n != 1), over D8 routing with closed depressions crossed through the basin graph of Cordonnier, "
      "Bovy and Braun 2019, 'A versatile, linear complexity algorithm for flow routing in topographies with "
      "depressions' (only the basins of pits are rerouted, over the minimum spanning tree of their passes; "
      "depressions fill with sediment to their spill level), or with depressions 'priority_flood' by the "
      "Priority-Flood+epsilon fill of the pit basins, which tiled and distributed builds run across the tiles "
      "bit for bit. Border cells and cells below sea level are base level. "
      "Produces real drainage networks.");
  declare_common_ports(b, "Scales erodibility K and diffusivity D per cell, 0..1 (1 if unconnected)");
  b.input("uplift", PortType::Heightfield)
      .optional()
      .description("Uplift factor per cell (>= 0), times uplift_rate; 1 if unconnected");
  b.output("accumulation", PortType::Heightfield)
      .description("Drainage area of the final routing, m^2")
      .kind(OutputKind::Scalar);
  b.param_float("k", 2e-5).range(0.0, 1.0).soft_range(1e-7, 1e-3).unit(Unit::Erodibility).description("Erodibility K");
  b.param_float("m", 0.45).unit(Unit::Unitless).range(0.0, 2.0).description("Drainage-area exponent m (unitless)");
  b.param_float("n", 1.0)
      .unit(Unit::Unitless)
      .range(0.2, 4.0)
      .description("Slope exponent n (unitless); 1 solves directly, else by Newton");
  b.param_float("uplift_rate", 1e-3)
      .range(0.0, 1.0)
      .soft_range(0.0, 0.01)
      .unit(Unit::MetrePerYear)
      .description("Rock uplift rate U");
  b.param_float("diffusion", 0.01)
      .range(0.0, 100.0)
      .soft_range(0.0, 1.0)
      .unit(Unit::SquareMetrePerYear)
      .description("Hillslope diffusivity D");
  b.param_float("time_step", 10000.0)
      .range(1.0, 1e8)
      .unit(Unit::Year)
      .description("Years per step (the implicit scheme is stable at any step)");
  b.param_float("duration", 500000.0)
      .range(0.0, 1e10)
      .soft_range(1e4, 1e7)
      .unit(Unit::Year)
      .description("Simulated time");
  b.param_float("sea_level", -1e4).range(-1e9, 1e9).unit(Unit::Metre).description("Cells below are base level (sinks)");
  b.param_float("channel_area", 0.0)
      .range(0.0, 1e12)
      .soft_range(0.0, 1e6)
      .unit(Unit::SquareMetre)
      .description(
          "Channel initiation: fluvial incision only where the drainage area reaches this; smaller areas are "
          "hillslopes shaped by diffusion alone. A threshold above a few cells makes the result converge with "
          "resolution (0: every cell incises, as in Braun and Willett 2013)");
  b.param_enum("depressions", {"basin_graph", "priority_flood"}, "basin_graph")
      .description(
          "How each step crosses closed depressions; both fill them with sediment to their spill level. "
          "'basin_graph' routes the double heights by D8 and reroutes only the basins of pits over their passes "
          "(Cordonnier, Bovy and Braun 2019): no more than D8 when the surface has no pit, the fastest on one "
          "machine. 'priority_flood' routes the heights rounded to float, filled by Priority-Flood+epsilon where they "
          "have a pit (Barnes et al. 2014), which tiled and distributed builds run across the tiles exactly (with "
          "'basin_graph' they compute the node on the whole domain). The two differ by rounding-level routing "
          "choices on flats; docs/distributed.md gives the difference after 100 steps");
  // Working memory beyond the outputs, 144 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 144); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto mask = secondary_input<Heightfield>(ctx, "mask", in->domain);
    const auto up = secondary_input<Heightfield>(ctx, "uplift", in->domain);
    erosion::StreamPowerParams p;
    p.k = ctx.param<double>("k");
    p.m = ctx.param<double>("m");
    p.n = ctx.param<double>("n");
    p.uplift = ctx.param<double>("uplift_rate");
    p.diffusion = ctx.param<double>("diffusion");
    p.dt = ctx.param<double>("time_step");
    p.duration = ctx.param<double>("duration");
    p.sea_level = ctx.param<double>("sea_level");
    p.channel_area = ctx.param<double>("channel_area");
    p.depressions = ctx.enum_index("depressions") == 1 ? erosion::StreamPowerParams::Depressions::PriorityFlood
                                                       : erosion::StreamPowerParams::Depressions::BasinGraph;
    std::shared_ptr<Heightfield> acc;
    auto m = erosion::stream_power(*in, p, up.get(), mask.get(), &ctx, nullptr, nullptr, &acc);
    set_common_outputs(ctx, m);
    ctx.set_output("accumulation", acc);
  });
}

}  // namespace orogen
