// RiverExtract (no rainfall weight) across the tiles of a tiled or distributed build, exact (graph/tile_graph.h,
// docs/distributed.md). The rounds go in phases, each message and answer tagged with its phase:
//
//  - fill: the spill graphs of all tiles (Barnes 2016), then rounds of the epsilon surface until no perimeter value
//    falls (nodes/hydrology/tile_fill.h): the whole-domain Priority-Flood+epsilon bit for bit, and its flat levels,
//    which say which cells are lakes;
//  - ring: the one-sample ring of the filled surface from the tiles around (nodes/hydrology/tile_ring.h), so the D8
//    direction of every cell is the whole domain's;
//  - accumulation: D8 cell counts through perimeter links (Barnes 2017, nodes/hydrology/tile_accumulation.h); the
//    area is the count times the cell area, as the whole-domain node computes it, so the channel cells are the same;
//  - Strahler: the orders of the channel cells, rounds of donor summaries at the perimeters until none changes
//    (nodes/hydrology/tile_strahler.h);
//  - network: each tile sends its own channel cells (a shared sample by the one tile that owns it): position, D8
//    direction, filled height, count, lake and order. The solve puts the channel network together, orders it as the
//    whole-domain stack order restricted to the channel (outlets in row-major order, each tree depth first with the
//    donors in neighbor order: non-channel cells have no channel cell upstream, so leaving them out keeps the
//    order), cuts it into reaches and builds the curves with the whole-domain node's own code (reach_curves).
//
// Every tile gets the whole joined network, in the untiled node's order (so the tiles' curve files are alike and
// `--merge` writes the untiled file), and draws its part of the river mask from it. What travels in the network
// phase is O(channel cells), the size of the curves themselves, not O(tile).
#include <algorithm>
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/channel_network.h"
#include "nodes/hydrology/channels.h"
#include "nodes/hydrology/rivers.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_ring.h"
#include "nodes/hydrology/tile_strahler.h"

namespace orogen::hydrology {
namespace {

enum class Phase : std::uint8_t { Spill, Epsilon, Ring, Accumulate, Strahler, Network, Done };

constexpr const char* kWhat = "rivers across tiles";

Phase take_phase(std::string_view& bytes) { return hydrology::take_phase<Phase>(bytes, kWhat, kWhat); }

// A channel cell as a tile sends it.
struct ChannelCell {
  std::int64_t sample;  // row-major index in the whole domain
  std::int64_t count;   // cells draining through it
  float z;              // filled height
  std::int32_t order;   // Strahler
  std::uint8_t direction;
  std::uint8_t lake;
  // Zeroed and explicit, not packed: the cells travel as bytes, and packed members would be misaligned in memory.
  std::uint8_t padding[6]{};
};
static_assert(sizeof(ChannelCell) == 32, "no padding beyond the explicit bytes");

void put_curves(std::string& out, const Curves& curves) {
  bytes::put(out, static_cast<std::uint64_t>(curves.curves.size()));
  for (const Curve& c : curves.curves) {
    bytes::put(out, static_cast<std::int32_t>(c.parent));
    bytes::put_vector(out, c.points);
    bytes::put_vector(out, c.width);
    bytes::put(out, static_cast<std::uint64_t>(c.attributes.size()));
    for (const auto& [name, values] : c.attributes) {
      bytes::put_vector(out, std::vector<char>(name.begin(), name.end()));
      bytes::put_vector(out, values);
    }
  }
}

std::shared_ptr<Curves> take_curves(std::string_view& in) {
  auto curves = std::make_shared<Curves>();
  const auto n = bytes::take<std::uint64_t>(in, kWhat);
  if (n > in.size()) throw std::invalid_argument("rivers across tiles: truncated curves");
  curves->curves.resize(static_cast<std::size_t>(n));
  for (Curve& c : curves->curves) {
    c.parent = bytes::take<std::int32_t>(in, kWhat);
    c.points = bytes::take_vector<glm::vec3>(in, kWhat);
    c.width = bytes::take_vector<float>(in, kWhat);
    const auto attributes = bytes::take<std::uint64_t>(in, kWhat);
    if (attributes > in.size()) throw std::invalid_argument("rivers across tiles: truncated curves");
    for (std::uint64_t a = 0; a < attributes; ++a) {
      const auto name = bytes::take_vector<char>(in, kWhat);
      c.attributes[std::string(name.begin(), name.end())] = bytes::take_vector<float>(in, kWhat);
    }
  }
  try {
    curves->check_consistent();
  } catch (const std::logic_error& e) {
    throw std::invalid_argument(std::string("rivers across tiles: ") + e.what());
  }
  return curves;
}

class RiverTile : public TileGraphTile {
 public:
  RiverTile(const Heightfield& ground, const Domain& whole, const RiverParams& p)
      : domain_(ground.domain), whole_(whole), size_(whole.resolution), grid_(FlowGrid::of(whole)), params_(p) {
    rect_ = {domain_.first, domain_.resolution};
    ground_ = ground.data;
    flood_ = flood_tile(ground_, rect_);
  }

  std::string message(int) override {
    switch (phase_) {
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
      case Phase::Strahler:
        return tagged(phase_, strahler_->message());
      case Phase::Network:
        return tagged(phase_, network_message());
      case Phase::Done:
        break;
    }
    throw std::logic_error("rivers across tiles: a message after the last round");
  }

  void answer(int, std::string_view bytes) override {
    const Phase next = take_phase(bytes);
    switch (phase_) {
      case Phase::Spill: {
        const auto levels = bytes::take_vector<float>(bytes, kWhat);
        std::vector<float> flat = apply_spill_levels(flood_, levels);
        flood_ = {};
        lake_.resize(flat.size());
        for (std::size_t c = 0; c < flat.size(); ++c) lake_[c] = flat[c] > ground_[c];  // as extract_rivers
        ground_ = {};
        epsilon_ = std::make_unique<TileEpsilon>(std::move(flat), rect_, size_);
        break;
      }
      case Phase::Epsilon:
        epsilon_->answer(bytes);
        if (next != Phase::Epsilon) {
          surface_ = epsilon_->surface();
          epsilon_.reset();
        }
        break;
      case Phase::Ring:
        take_ring(bytes);
        break;
      case Phase::Accumulate: {
        const std::vector<std::int64_t> counts = finish_tile_accumulation(accumulation_, bytes);
        strahler_ = std::make_unique<TileStrahler>(
            accumulation_.receiver, channel_cells(counts, grid_.cell_area(), params_.threshold), rect_, size_);
        // The orders' rounds and the network need the channel cells alone: what the network message takes of each
        // is kept, the tile's maps go.
        for (const std::int32_t c : strahler_->cells()) {
          const auto u = static_cast<std::size_t>(c);
          const int i = c % rect_.size.x, j = c / rect_.size.x;
          channel_.push_back({static_cast<std::int64_t>(rect_.first.y + j) * size_.x + rect_.first.x + i, counts[u],
                              surface_[u], 0, direction_[u], lake_[u]});
          channel_owned_.push_back(accumulation_.owned[u]);
        }
        accumulation_ = {};
        surface_ = {};
        direction_ = {};
        lake_ = {};
        break;
      }
      case Phase::Strahler:
        strahler_->answer(bytes);
        break;
      case Phase::Network: {
        curves_ = take_curves(bytes);
        expect_end(bytes, kWhat);
        mask_ = std::make_shared<Heightfield>(domain_);
        draw_curves(*curves_, *mask_, &whole_);
        break;
      }
      case Phase::Done:
        throw std::logic_error("rivers across tiles: an answer after the last round");
    }
    phase_ = next;
  }

  std::vector<PortValue> outputs() override {
    if (phase_ != Phase::Done) throw std::logic_error("rivers across tiles: outputs before the last round");
    return {CurvesPtr(curves_), HeightfieldPtr(mask_)};
  }

 private:
  // The D8 directions of the tile's cells on the filled surface grown by its ring, as on the whole domain.
  void take_ring(std::string_view bytes) {
    const TileRect ringed = ringed_rect(rect_, size_);
    const std::vector<float> z = with_ring(surface_, rect_, size_, bytes);
    const FlowGrid g(ringed.size.x, ringed.size.y, grid_.dx, grid_.dy);
    direction_ = without_ring<std::uint8_t>(d8_flow(g, z).direction, rect_, size_);
    accumulation_ = start_tile_accumulation(direction_, rect_, size_);
  }

  // The channel cells this tile owns, with their orders.
  std::string network_message() const {
    std::vector<ChannelCell> cells;
    const auto& order = strahler_->orders();
    for (std::size_t k = 0; k < channel_.size(); ++k) {
      if (!channel_owned_[k]) continue;
      cells.push_back(channel_[k]);
      cells.back().order = order[k];
    }
    std::string out;
    bytes::put_vector(out, cells);
    return out;
  }

  Domain domain_;  // the tile's samples
  Domain whole_;
  glm::ivec2 size_;
  FlowGrid grid_;
  RiverParams params_;
  TileRect rect_;
  Phase phase_ = Phase::Spill;
  std::vector<float> ground_;
  TileFlood flood_;
  std::vector<std::uint8_t> lake_;
  std::unique_ptr<TileEpsilon> epsilon_;
  std::vector<float> surface_;  // the epsilon-filled heights on the tile
  std::vector<std::uint8_t> direction_;
  TileAccumulation accumulation_;
  std::unique_ptr<TileStrahler> strahler_;
  std::vector<ChannelCell> channel_;         // per channel cell (TileStrahler::cells), all but its order
  std::vector<std::uint8_t> channel_owned_;  // per channel cell: this tile sends it
  std::shared_ptr<Curves> curves_;
  std::shared_ptr<Heightfield> mask_;
};

class RiversAcrossTiles : public TileGraphAlgorithm {
 public:
  RiversAcrossTiles(const RiverParams& p, const Domain& whole) : params_(p), whole_(whole) {}

  int rounds() const override { return 1; }

  // Every tile is in the same phase: the first message's tag says which, and what follows it.
  bool another_round(int, const std::vector<std::string>& messages) const override {
    if (messages.empty()) return false;
    std::string_view first(messages.front());
    return take_phase(first) != Phase::Network;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("rivers across tiles need a heightfield input");
    if (inputs.size() > 1 && has_value(inputs[1]))
      throw std::invalid_argument("rivers across tiles take no rainfall weight");
    return std::make_unique<RiverTile>(**ground, whole_, params_);
  }

  std::vector<std::string> solve(int, const std::vector<std::string>& tagged_messages) const override {
    const auto [phase, messages] = untag_messages<Phase>(tagged_messages, kWhat, kWhat);
    const glm::ivec2 size = whole_.resolution;
    std::vector<std::string> answers(messages.size());
    Phase next = Phase::Done;
    switch (phase) {
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
        next = Phase::Accumulate;
        break;
      case Phase::Accumulate:
        answers = solve_tile_accumulation(messages, size);
        next = Phase::Strahler;
        break;
      case Phase::Strahler:
        answers = solve_strahler_perimeters(messages, size);
        next = strahler_changed(messages) ? Phase::Strahler : Phase::Network;
        break;
      case Phase::Network: {
        std::string curves;
        put_curves(curves, *network_curves(messages));
        std::fill(answers.begin(), answers.end(), curves);
        break;
      }
      case Phase::Done:
        throw std::invalid_argument("rivers across tiles: a message after the last round");
    }
    for (auto& a : answers) a = tagged(next, std::move(a));
    return answers;
  }

 private:
  // The channel network of every tile's channel cells, cut into reaches as extract_reaches cuts the whole domain's.
  std::shared_ptr<Curves> network_curves(std::span<const std::string_view> messages) const {
    std::vector<ChannelCell> cells;
    for (std::string_view in : messages) {
      const auto part = bytes::take_vector<ChannelCell>(in, kWhat);
      expect_end(in, kWhat);
      cells.insert(cells.end(), part.begin(), part.end());
    }
    const glm::ivec2 size = whole_.resolution;
    const ChannelNetwork net = sorted_channel_network(cells, size, "rivers across tiles");
    std::vector<std::uint8_t> donors(cells.size());
    std::vector<std::int32_t> strahler(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      donors[c] = static_cast<std::uint8_t>(net.donors[c].size());
      strahler[c] = cells[c].order;
    }
    const std::vector<Reach> reaches =
        channel_reaches(net.order, std::vector<std::uint8_t>(cells.size(), 1), net.receiver, donors, strahler);
    const double cell_area = FlowGrid::of(whole_).cell_area();
    return reach_curves(
        reaches,
        [&](std::int32_t c) {
          const ChannelCell& cell = cells[static_cast<std::size_t>(c)];
          const int i = static_cast<int>(cell.sample % size.x), j = static_cast<int>(cell.sample / size.x);
          return RiverCell{whole_.x(i), whole_.y(j), cell.z, static_cast<double>(cell.count) * cell_area,
                           cell.lake != 0};
        },
        params_);
  }

  RiverParams params_;
  Domain whole_;
};

const bool kRiversRegistered = register_tile_graph(
    "RiverExtract",
    [](const ParamView& p, const Domain& whole) {
      const RiverParams params{p.get<double>("threshold"),
                               p.get<double>("runoff"),
                               p.get<double>("width_coefficient"),
                               p.get<double>("width_exponent"),
                               static_cast<int>(p.get<std::int64_t>("smoothing")),
                               p.get<bool>("split_at_lakes")};
      std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<RiversAcrossTiles>(params, whole);
      return algorithm;
    },
    "with no rainfall_weight linked (the weighted area is a floating-point sum, whose rounding depends on the order "
    "of addition)",
    {"rainfall_weight"});

}  // namespace
}  // namespace orogen::hydrology
