// FillDepressions' carve across tiles, exact. The rounds go in phases, each message and answer tagged with its phase:
//  - spill: the Flat fill's spill graphs (Barnes 2016, nodes/hydrology/tile_fill.h): the water levels;
//  - lakes: the lakes joined and numbered across tiles (nodes/hydrology/tile_lakes.h); those at most max_depth deep
//    are kept, filled to their level, and are the heights the carve works on;
//  - epsilon: rounds of the epsilon surface of the water levels (which is that of the heights with the kept lakes
//    filled, since both have the same Flat fill) until no perimeter value falls;
//  - ring: the one-sample ring of that surface and of the heights from the tiles around (nodes/hydrology/tile_ring.h);
//  - breach: the carve's values carried down the tree across tiles until none falls (nodes/hydrology/tile_breach.h).
// The result is the whole-domain node's (nodes/hydrology/depressions.cpp) bit for bit: the same water levels, lakes,
// surface, tree, pits and minima.
#include "nodes/hydrology/carve_across_tiles.h"

#include <stdexcept>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_breach.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_lakes.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_ring.h"

namespace orogen::hydrology {
namespace {

enum class Phase : std::uint8_t { Spill, Lakes, Epsilon, Ring, Breach, Done };

constexpr const char* kWhat = "carving across tiles";

Phase take_phase(std::string_view& bytes) { return hydrology::take_phase<Phase>(bytes, kWhat, kWhat); }

class CarveTile : public TileGraphTile {
 public:
  CarveTile(const Heightfield& ground, const Domain& whole, bool epsilon)
      : domain_(ground.domain), whole_(whole.resolution), epsilon_(epsilon), ground_(ground.data) {
    rect_ = {domain_.first, domain_.resolution};
    const FlowGrid g = FlowGrid::of(whole);
    dx_ = g.dx, dy_ = g.dy;
    flood_ = flood_tile(ground_, rect_);
  }

  std::string message(int) override {
    switch (phase_) {
      case Phase::Spill:
        return tagged(phase_, encode(flood_.graph));
      case Phase::Lakes:
        return tagged(phase_, encode(lakes_.lakes));
      case Phase::Epsilon:
        return tagged(phase_, epsilon_surface_->message());
      case Phase::Ring:
        return tagged(phase_, ring_pair_message(surface_, carved_ground_, rect_));
      case Phase::Breach:
        return tagged(phase_, breach_->message());
      case Phase::Done:
        break;
    }
    throw std::logic_error("carving across tiles: a message after the last round");
  }

  void answer(int, std::string_view bytes) override {
    const Phase next = take_phase(bytes);
    switch (phase_) {
      case Phase::Spill:
        water_ = apply_spill_levels(flood_, bytes::take_vector<float>(bytes, kWhat));
        flood_ = {};
        lakes_ = label_tile_lakes(water_, ground_, rect_, whole_);
        break;
      case Phase::Lakes: {
        lake_number_ = bytes::take_vector<std::int32_t>(bytes, kWhat);
        if (lake_number_.size() != lakes_.lakes.first_cell.size())
          throw std::invalid_argument("carving across tiles: one lake number per lake of the tile expected");
        // The heights to carve: the kept lakes filled to their level.
        carved_ground_ = ground_;
        for (std::size_t c = 0; c < carved_ground_.size(); ++c)
          if (number(c)) carved_ground_[c] = water_[c];
        epsilon_surface_ = std::make_unique<TileEpsilon>(water_, rect_, whole_);
        break;
      }
      case Phase::Epsilon:
        epsilon_surface_->answer(bytes);
        if (next != Phase::Epsilon) {
          surface_ = epsilon_surface_->surface();
          epsilon_surface_.reset();
        }
        break;
      case Phase::Ring: {
        const auto [surface, ground] = with_ring_pair(surface_, carved_ground_, rect_, whole_, bytes);
        breach_ = std::make_unique<TileBreach>(ground, surface, rect_, whole_, dx_, dy_, epsilon_);
        surface_ = {}, carved_ground_ = {};
        break;
      }
      case Phase::Breach:
        breach_->answer(bytes);
        break;
      case Phase::Done:
        throw std::logic_error("carving across tiles: an answer after the last round");
    }
    phase_ = next;
  }

  std::vector<PortValue> outputs() override {
    if (phase_ != Phase::Done) throw std::logic_error("carving across tiles: outputs before the last round");
    auto out = std::make_shared<Heightfield>(domain_), depth = std::make_shared<Heightfield>(domain_),
         id = std::make_shared<Heightfield>(domain_);
    out->data = breach_->carved();
    for (std::size_t c = 0; c < water_.size(); ++c) {
      const std::int32_t k = number(c);
      depth->data[c] = k ? water_[c] - ground_[c] : 0.0f;
      id->data[c] = static_cast<float>(k);
    }
    return {HeightfieldPtr(out), HeightfieldPtr(depth), HeightfieldPtr(id)};
  }

 private:
  // The whole-domain number of the kept lake cell c lies in, 0 if none.
  std::int32_t number(std::size_t c) const {
    const std::int32_t k = lakes_.label[c];
    return k ? lake_number_[static_cast<std::size_t>(k - 1)] : 0;
  }

  Domain domain_;
  glm::ivec2 whole_;
  bool epsilon_;
  double dx_ = 1.0, dy_ = 1.0;
  TileRect rect_;
  Phase phase_ = Phase::Spill;
  std::vector<float> ground_;
  TileFlood flood_;
  std::vector<float> water_;  // the Flat fill's levels
  TileLakeLabels lakes_;
  std::vector<std::int32_t> lake_number_;
  std::vector<float> carved_ground_;  // the heights to carve, until the ring
  std::unique_ptr<TileEpsilon> epsilon_surface_;
  std::vector<float> surface_;  // their epsilon surface, until the ring
  std::unique_ptr<TileBreach> breach_;
};

class CarveAcrossTiles : public TileGraphAlgorithm {
 public:
  CarveAcrossTiles(const Domain& whole, double max_depth, bool epsilon)
      : whole_(whole), max_depth_(max_depth), epsilon_(epsilon) {}

  int rounds() const override { return 1; }

  bool another_round(int, const std::vector<std::string>& messages) const override {
    if (messages.empty()) return false;
    const auto [phase, views] = untag_messages<Phase>(messages, kWhat, kWhat);
    return phase != Phase::Breach || perimeter_minima_fell(views);
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const HeightfieldPtr ground = tile_heightfield(inputs, 0);
    if (!ground) throw std::invalid_argument("carving across tiles needs a heightfield input");
    return std::make_unique<CarveTile>(*ground, whole_, epsilon_);
  }

  std::vector<std::string> solve(int, const std::vector<std::string>& tagged_messages) const override {
    const auto [phase, messages] = untag_messages<Phase>(tagged_messages, kWhat, kWhat);
    const glm::ivec2 size = whole_.resolution;
    std::vector<std::string> answers(messages.size());
    Phase next = Phase::Done;
    switch (phase) {
      case Phase::Spill:
        answers = solve_spill_messages(messages, size);
        next = Phase::Lakes;
        break;
      case Phase::Lakes: {
        // As the whole-domain node: a lake no deeper than max_depth is kept (none when it is 0: every lake is
        // deeper).
        const double max_depth = max_depth_;
        answers = solve_lake_messages(messages, size,
                                      [max_depth](float deepest, std::int64_t) { return deepest <= max_depth; });
        next = Phase::Epsilon;
        break;
      }
      case Phase::Epsilon:
        answers = solve_perimeter_minima(messages, size);
        next = perimeter_minima_fell(messages) ? Phase::Epsilon : Phase::Ring;
        break;
      case Phase::Ring:
        answers = solve_ring_pairs(messages, size);
        next = Phase::Breach;
        break;
      case Phase::Breach:
        answers = solve_perimeter_minima(messages, size);
        next = perimeter_minima_fell(messages) ? Phase::Breach : Phase::Done;
        break;
      case Phase::Done:
        throw std::invalid_argument("carving across tiles: a message after the last round");
    }
    for (auto& a : answers) a = tagged(next, std::move(a));
    return answers;
  }

 private:
  Domain whole_;
  double max_depth_;
  bool epsilon_;
};

}  // namespace

std::unique_ptr<TileGraphAlgorithm> carve_across_tiles(const Domain& whole, double max_depth, bool epsilon) {
  return std::make_unique<CarveAcrossTiles>(whole, max_depth, epsilon);
}

}  // namespace orogen::hydrology
