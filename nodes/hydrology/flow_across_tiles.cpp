// FlowDirection (fill on), FlowAccumulation (every method) and Watersheds across the tiles of a tiled or distributed
// build, exact (graph/tile_graph.h, docs/distributed.md). The rounds go in phases, each message and answer tagged with
// its phase so every rank and tile knows where the run stands:
//
//  - surface (with `fill` on): whether every tile kept the filled surface of the same heights from an earlier flow
//    node (nodes/hydrology/tile_surface_memo.h); if so the fill's rounds are skipped;
//  - fill (with `fill` on): the spill graphs of all tiles (Barnes 2016, nodes/hydrology/tile_fill.h), then rounds of
//    the epsilon surface until no perimeter value falls: the whole-domain Priority-Flood+epsilon bit for bit;
//  - ring: each tile gets the one-sample ring of that surface from the tiles around it (nodes/hydrology/tile_ring.h),
//    so the direction, proportions and slope of its perimeter cells see their neighbours across the border, and
//    every per-cell map is the same function of the same nine heights as on the whole domain;
//  - accumulation (FlowAccumulation): D8 cell counts through perimeter links (Barnes 2017,
//    nodes/hydrology/tile_accumulation.h), whole numbers, so exact; the area is the count times the cell area, as
//    the whole-domain node computes it;
//  - edges and shares (FlowAccumulation with D-infinity, MFD or a rainfall weight): the floating-point sums, each
//    cell's donors pulled in neighbour order as the whole-domain node does, as a dataflow across the tiles' borders
//    in rounds until every tile is done (nodes/hydrology/tile_shares.h);
//  - maximum (the flow map with flow_max_area 0): the largest area of any tile, the flow map's upper end;
//  - links and basins (Watersheds): where each perimeter cell's D8 path ends, joined into every cell's outlet, then
//    the cells per outlet added up and the basins numbered by decreasing area (nodes/hydrology/tile_basins.h).
//
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/match_domain.h"
#include "nodes/hydrology/flow.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_basins.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_ring.h"
#include "nodes/hydrology/tile_shares.h"
#include "nodes/hydrology/tile_surface_memo.h"

namespace orogen::hydrology {
namespace {

enum class Phase : std::uint8_t {
  Spill,
  Epsilon,
  Ring,
  Accumulate,
  Maximum,
  Links,
  Basins,
  Edges,
  Shares,
  Surface,
  Done
};

constexpr const char* kWhat = "flow across tiles";

Phase take_phase(std::string_view& bytes) { return hydrology::take_phase<Phase>(bytes, kWhat, kWhat); }

// What the tiles compute once they have the ring.
struct FlowJob {
  enum class Output { Directions, Accumulation, Basins } output = Output::Directions;
  bool fill = true;
  RoutingOptions routing;                  // FlowDirection's and FlowAccumulation's method and exponent
  AccumulationParams accumulation_params;  // FlowAccumulation's
  double min_area = 0.0;                   // Watersheds'
  // What follows the ring: the accumulation, the basins' links, or nothing (the directions are done).
  Phase after_ring() const {
    return output == Output::Accumulation ? Phase::Accumulate : output == Output::Basins ? Phase::Links : Phase::Done;
  }
  // What follows the accumulation: the largest count, unless flow_max_area fixes the flow map's upper end.
  Phase after_accumulation() const { return accumulation_params.flow_max_area > 0.0 ? Phase::Done : Phase::Maximum; }
};

class FlowTile : public TileGraphTile {
 public:
  // The tile keeps no reference to `ground`: the stage lets it go once every tile has started.
  // `rainfall`: FlowAccumulation's weight on the tile, or null.
  FlowTile(const Heightfield& ground, const Heightfield* rainfall, const FlowJob& job, const Domain& whole)
      : domain_(ground.domain), job_(job), whole_(whole.resolution), grid_(FlowGrid::of(whole)) {
    rect_ = {domain_.first, domain_.resolution};
    // The counts of whole cells serve D8 without a weight; every other accumulation sums floating-point shares.
    by_shares_ =
        job_.output == FlowJob::Output::Accumulation && (job_.routing.method != FlowMethod::D8 || rainfall != nullptr);
    if (rainfall) {
      // As flow_accumulation: the weight times the cell area, in single precision.
      weight_.resize(rainfall->data.size());
      for (std::size_t c = 0; c < weight_.size(); ++c)
        weight_[c] = static_cast<float>(std::max(0.0f, rainfall->data[c]) * grid_.cell_area());
    }
    if (job_.fill) {
      // The heights until the tiles decide whether to fill them or take the surfaces they kept.
      heights_hash_ = hash_heights(ground.data);
      kept_ = find_filled_surface(rect_, whole_, heights_hash_);
      surface_ = ground.data;
      phase_ = Phase::Surface;
    } else {
      surface_ = ground.data;
      phase_ = Phase::Ring;
    }
  }

  std::string message(int) override {
    switch (phase_) {
      case Phase::Surface: {
        std::string out;
        bytes::put(out, static_cast<std::uint8_t>(kept_ != nullptr));
        return tagged(phase_, std::move(out));
      }
      case Phase::Spill:
        return tagged(phase_, encode(flood_.graph));
      case Phase::Epsilon:
        return tagged(phase_, epsilon_->message());
      case Phase::Ring:
        return tagged(phase_, ring_message(surface_, rect_));
      case Phase::Accumulate: {
        std::string out = tagged(phase_, accumulation_message(accumulation_));
        accumulation_.local = {};  // only the message needs the local counts
        return out;
      }
      case Phase::Maximum: {
        std::string out;
        bytes::put(out, largest_area());
        return tagged(phase_, std::move(out));
      }
      case Phase::Edges:
        return tagged(phase_, shares_->edges_message());
      case Phase::Shares:
        return tagged(phase_, shares_->shares_message());
      case Phase::Links:
        return tagged(phase_, basin_links_message(basins_));
      case Phase::Basins:
        return tagged(phase_, basin_count_message(basins_));
      case Phase::Done:
        break;
    }
    throw std::logic_error("flow across tiles: a message after the last round");
  }

  void answer(int, std::string_view bytes) override {
    const Phase next = take_phase(bytes);
    switch (phase_) {
      case Phase::Surface:
        expect_end(bytes, kWhat);
        if (next == Phase::Ring) {
          if (!kept_) throw std::invalid_argument("flow across tiles: no kept surface to take");
          surface_ = *kept_;
        } else {
          flood_ = flood_tile(surface_, rect_);
          surface_ = {};
        }
        kept_.reset();
        break;
      case Phase::Spill: {
        const auto levels = bytes::take_vector<float>(bytes, kWhat);
        epsilon_ = std::make_unique<TileEpsilon>(apply_spill_levels(flood_, levels), rect_, whole_);
        flood_ = {};
        break;
      }
      case Phase::Epsilon:
        epsilon_->answer(bytes);
        if (next != Phase::Epsilon) {
          surface_ = epsilon_->surface();
          epsilon_.reset();
          keep_filled_surface(rect_, whole_, heights_hash_, surface_);
        }
        break;
      case Phase::Ring:
        take_ring(bytes);
        // The solve names the accumulation that follows the ring; the tile knows which of the two it runs.
        if (next == Phase::Accumulate && by_shares_) {
          phase_ = Phase::Edges;
          return;
        }
        break;
      case Phase::Edges:
        shares_->take_edges(bytes);
        break;
      case Phase::Shares:
        shares_->take_shares(bytes);
        if (next != Phase::Shares) {
          areas_ = shares_->take_accumulation();
          shares_.reset();
        }
        break;
      case Phase::Accumulate:
        counts_ = finish_tile_accumulation(accumulation_, bytes);
        accumulation_ = {};
        break;
      case Phase::Maximum:
        largest_ = bytes::take<double>(bytes, kWhat);
        expect_end(bytes, kWhat);
        break;
      case Phase::Links:
        take_basin_outlets(basins_, bytes);
        break;
      case Phase::Basins: {
        id_ = std::make_shared<Heightfield>(domain_);
        area_ = std::make_shared<Heightfield>(domain_);
        basin_maps(basins_, bytes, grid_.cell_area(), id_->data, area_->data);
        basins_ = {};
        break;
      }
      case Phase::Done:
        throw std::logic_error("flow across tiles: an answer after the last round");
    }
    phase_ = next;
  }

  std::vector<PortValue> outputs() override {
    if (phase_ != Phase::Done) throw std::logic_error("flow across tiles: outputs before the last round");
    if (job_.output == FlowJob::Output::Directions)
      return {HeightfieldPtr(maps_.angle), HeightfieldPtr(maps_.dx), HeightfieldPtr(maps_.dy),
              HeightfieldPtr(maps_.slope)};
    if (job_.output == FlowJob::Output::Basins) return {HeightfieldPtr(id_), HeightfieldPtr(area_)};
    // As flow_accumulation on the whole domain: the area is the cell count times the cell area, or the sum of shares.
    const Domain& d = domain_;
    const AccumulationParams& p = job_.accumulation_params;
    // The flow map and the wetness index only where the build uses them (their logarithms cost more than the rest).
    auto out = std::make_shared<Heightfield>(d);
    auto flow = output_needed(1) ? std::make_shared<Heightfield>(d) : nullptr;
    auto wetness = output_needed(2) ? std::make_shared<Heightfield>(d) : nullptr;
    const double area = grid_.cell_area();
    const double lo = p.flow_min_area > 0.0 ? p.flow_min_area : area;
    const double hi = p.flow_max_area > 0.0 ? p.flow_max_area : largest_;
    const double width = std::sqrt(area);
    const std::size_t n = by_shares_ ? areas_.size() : counts_.size();
    for (std::size_t c = 0; c < n; ++c) {
      const double acc = by_shares_ ? areas_[c] : static_cast<double>(counts_[c]) * area;
      out->data[c] = static_cast<float>(acc);
      if (flow) flow->data[c] = flow_map_value(acc, lo, hi);
      if (wetness) wetness->data[c] = wetness_value(acc, width, slope_[c], p.min_slope);
    }
    return {HeightfieldPtr(out), flow ? PortValue(HeightfieldPtr(flow)) : PortValue{},
            wetness ? PortValue(HeightfieldPtr(wetness)) : PortValue{}};
  }

 private:
  // The largest accumulation on the tile, in m^2 (for counts the largest count times the cell area: the same
  // product, since rounding is monotone).
  double largest_area() const {
    if (by_shares_) return *std::max_element(areas_.begin(), areas_.end());
    return static_cast<double>(*std::max_element(counts_.begin(), counts_.end())) * grid_.cell_area();
  }

  // The surface with its ring from the tiles around: the tile's maps, or its D8 directions and slopes.
  void take_ring(std::string_view bytes) {
    const TileRect ringed = ringed_rect(rect_, whole_);
    std::vector<float> z = with_ring(surface_, rect_, whole_, bytes);
    surface_ = {};
    // The ringed tile as a grid of its own: its cells are border cells (outlets) only where the domain's border is,
    // and every neighbour of the tile's cells is in it.
    const FlowGrid g(ringed.size.x, ringed.size.y, grid_.dx, grid_.dy);
    const glm::ivec2 at = rect_.first - ringed.first;
    if (job_.output == FlowJob::Output::Directions) {
      const Domain& d = domain_;
      maps_.angle = std::make_shared<Heightfield>(d);
      maps_.dx = std::make_shared<Heightfield>(d);
      maps_.dy = std::make_shared<Heightfield>(d);
      maps_.slope = std::make_shared<Heightfield>(d);
      direction_maps(g, z, at, job_.routing, maps_);
      return;
    }
    const bool basins = job_.output == FlowJob::Output::Basins;
    // The slope serves the wetness index alone.
    const bool wetness = !basins && output_needed(2);
    if (by_shares_) {
      if (wetness) slope_ = without_ring<float>(steepest_slope(g, z), rect_, whole_);
      shares_ = std::make_unique<TileShares>(std::move(z), rect_, whole_, grid_.dx, grid_.dy, job_.routing,
                                             std::move(weight_));
      weight_ = {};
      return;
    }
    if (wetness) slope_ = without_ring<float>(steepest_slope(g, z), rect_, whole_);
    accumulation_ =
        start_tile_accumulation(without_ring<std::uint8_t>(d8_flow(g, z).direction, rect_, whole_), rect_, whole_);
    if (basins) {
      basins_ = start_tile_basins(accumulation_);
      accumulation_ = {};
    }
  }

  Domain domain_;  // the tile's samples
  FlowJob job_;
  glm::ivec2 whole_;
  FlowGrid grid_;  // the whole domain's spacing
  TileRect rect_;
  Phase phase_ = Phase::Ring;
  HeightsHash heights_hash_;                        // of the input heights (with `fill`)
  std::shared_ptr<const std::vector<float>> kept_;  // their filled surface, from an earlier flow node
  TileFlood flood_;
  std::unique_ptr<TileEpsilon> epsilon_;
  std::vector<float> surface_;  // the routed heights on the tile: filled (epsilon) or the input
  DirectionResult maps_;
  TileAccumulation accumulation_;
  std::vector<float> slope_;
  std::vector<std::int64_t> counts_;
  bool by_shares_ = false;
  std::vector<float> weight_;  // the rainfall weight times the cell area, until the shares start
  std::unique_ptr<TileShares> shares_;
  std::vector<double> areas_;  // the accumulation by shares
  double largest_ = 0.0;
  TileBasins basins_;
  std::shared_ptr<Heightfield> id_, area_;
};

class FlowAcrossTiles : public TileGraphAlgorithm {
 public:
  FlowAcrossTiles(FlowJob job, const Domain& whole) : job_(std::move(job)), whole_(whole) {}

  int rounds() const override { return 1; }

  // Every tile is in the same phase: the first message's tag says which, and what follows it.
  bool another_round(int, const std::vector<std::string>& messages) const override {
    if (messages.empty()) return false;
    std::string_view first(messages.front());
    switch (take_phase(first)) {
      case Phase::Surface:
      case Phase::Spill:
      case Phase::Epsilon:
        return true;  // more epsilon rounds, or the ring
      case Phase::Ring:
        return job_.after_ring() != Phase::Done;
      case Phase::Accumulate:
        return job_.after_accumulation() != Phase::Done;
      case Phase::Edges:
        return true;
      case Phase::Shares:
        return !shares_done(untag_messages<Phase>(messages, kWhat, kWhat).views) ||
               job_.after_accumulation() != Phase::Done;
      case Phase::Links:
        return true;
      default:
        return false;
    }
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("flow routing across tiles needs a heightfield input");
    const auto* rain = inputs.size() > 1 ? std::get_if<HeightfieldPtr>(&inputs[1]) : nullptr;
    HeightfieldPtr rainfall = rain ? *rain : nullptr;
    if (rainfall && rainfall->domain != (*ground)->domain) {
      // On another lattice: resampled onto the tile as the whole-domain node resamples it onto the domain (every
      // sample from its world position, origin + (first + i) * spacing, so the tile's samples are the domain's).
      if (!domains_overlap(rainfall->domain, whole_))
        throw std::invalid_argument("FlowAccumulation: input 'rainfall_weight' (" + rainfall->domain.describe() +
                                    ") does not overlap the domain (" + whole_.describe() + ")");
      rainfall = match_domain(rainfall, (*ground)->domain);
    }
    return std::make_unique<FlowTile>(**ground, rainfall.get(), job_, whole_);
  }

  std::vector<std::string> solve(int, const std::vector<std::string>& tagged_messages) const override {
    const auto [phase, messages] = untag_messages<Phase>(tagged_messages, kWhat, kWhat);
    const glm::ivec2 size = whole_.resolution;
    std::vector<std::string> answers(messages.size());
    Phase next = Phase::Done;
    switch (phase) {
      case Phase::Surface: {
        // The fill's rounds unless every tile kept its surface.
        bool all = true;
        for (std::string_view m : messages) {
          const bool kept = bytes::take<std::uint8_t>(m, kWhat) != 0;
          all = all && kept;
          expect_end(m, kWhat);
        }
        next = all ? Phase::Ring : Phase::Spill;
        break;
      }
      case Phase::Spill: {
        answers = solve_spill_messages(messages, size);
        next = Phase::Epsilon;
        break;
      }
      case Phase::Epsilon:
        answers = solve_perimeter_minima(messages, size);
        next = perimeter_minima_fell(messages) ? Phase::Epsilon : Phase::Ring;
        break;
      case Phase::Ring:
        answers = solve_rings(messages, size);
        next = job_.after_ring();
        break;
      case Phase::Accumulate:
        answers = solve_tile_accumulation(messages, size);
        next = job_.after_accumulation();
        break;
      case Phase::Edges:
        answers = solve_share_edges(messages, size);
        next = Phase::Shares;
        break;
      case Phase::Shares:
        answers = solve_shares(messages, size);
        next = shares_done(messages) ? job_.after_accumulation() : Phase::Shares;
        break;
      case Phase::Links:
        answers = solve_basin_links(messages, size);
        next = Phase::Basins;
        break;
      case Phase::Basins:
        answers = solve_basin_counts(messages, FlowGrid::of(whole_).cell_area(), job_.min_area);
        break;
      case Phase::Maximum: {
        double largest = 0.0;
        for (std::string_view m : messages) {
          largest = std::max(largest, bytes::take<double>(m, kWhat));
          expect_end(m, kWhat);
        }
        for (auto& a : answers) bytes::put(a, largest);
        break;
      }
      case Phase::Done:
        throw std::invalid_argument("flow across tiles: a message after the last round");
    }
    for (auto& a : answers) a = tagged(next, std::move(a));
    return answers;
  }

 private:
  FlowJob job_;
  Domain whole_;
};

FlowMethod method_named(const std::string& name) {
  if (name == "d8") return FlowMethod::D8;
  if (name == "dinf") return FlowMethod::DInfinity;
  if (name == "mfd") return FlowMethod::MFD;
  throw std::invalid_argument("flow across tiles: unknown method '" + name + "'");
}

// FlowDirection with fill on, every method: each map is a function of a cell's nine filled heights. (With fill off
// it is a local node of one sample, per tile with a halo, and needs no rounds.)
const bool kDirectionRegistered = register_tile_graph("FlowDirection", [](const ParamView& p, const Domain& whole) {
  std::unique_ptr<TileGraphAlgorithm> algorithm;
  if (!p.get<bool>("fill")) return algorithm;
  FlowJob job;
  job.routing.method = method_named(p.get<std::string>("method"));
  job.routing.exponent = p.get<double>("exponent");
  algorithm = std::make_unique<FlowAcrossTiles>(std::move(job), whole);
  return algorithm;
});

// FlowAccumulation, every method, fill on or off, the rainfall weight linked or not: D8 without it by whole cell
// counts, the others by shares pulled in a fixed order.
const bool kAccumulationRegistered =
    register_tile_graph("FlowAccumulation", [](const ParamView& p, const Domain& whole) {
      FlowJob job;
      job.output = FlowJob::Output::Accumulation;
      job.routing.method = method_named(p.get<std::string>("method"));
      job.routing.exponent = p.get<double>("exponent");
      job.fill = p.get<bool>("fill");
      job.accumulation_params.fill = job.fill;
      job.accumulation_params.flow_min_area = p.get<double>("flow_min_area");
      job.accumulation_params.flow_max_area = p.get<double>("flow_max_area");
      job.accumulation_params.min_slope = p.get<double>("min_gradient");
      std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<FlowAcrossTiles>(std::move(job), whole);
      return algorithm;
    });

// Watersheds, fill on or off: D8 labels through perimeter links, whole cell counts per basin.
const bool kWatershedsRegistered = register_tile_graph("Watersheds", [](const ParamView& p, const Domain& whole) {
  FlowJob job;
  job.output = FlowJob::Output::Basins;
  job.fill = p.get<bool>("fill");
  job.min_area = p.get<double>("min_area");
  std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<FlowAcrossTiles>(std::move(job), whole);
  return algorithm;
});

}  // namespace
}  // namespace orogen::hydrology
