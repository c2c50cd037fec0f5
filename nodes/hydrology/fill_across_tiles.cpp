// FillDepressions (fill mode, flat surfaces) and Lakes across the tiles of a tiled or distributed build, exact
// (graph/tile_graph.h): round 0 floods each tile and solves the spill graphs of all tiles (nodes/hydrology/tile_fill.h,
// Barnes 2016); round 1 joins and numbers the lakes across tiles (nodes/hydrology/tile_lakes.h). The outputs equal
// the whole-domain node's bit for bit: levels are minimax heights over paths (no arithmetic), depths are the same
// subtraction per cell, and lakes are kept and numbered by the same rule over whole lakes.
//
// With epsilon flats, rounds 2, 3, ... relax the epsilon surface of the flat levels across tiles until no perimeter
// value falls (nodes/hydrology/tile_fill.h, TileEpsilon): the least fixed point of its definition, the whole-domain
// fill's surface bit for bit. Carve mode has rounds of its own (nodes/hydrology/carve_across_tiles.h).
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/carve_across_tiles.h"
#include "nodes/hydrology/flow_routing.h"
#include "graph/tile_bytes.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_lakes.h"

namespace orogen::hydrology {
namespace {

// Rounds 0 and 1 fill flat and number the lakes; with epsilon, rounds 2, 3, ... relax the epsilon surface of the
// flat levels until no perimeter value falls (TileEpsilon).
class FlatFillTile : public TileGraphTile {
 public:
  FlatFillTile(HeightfieldPtr ground, glm::ivec2 whole, bool ground_outside_lakes, bool epsilon)
      : ground_(std::move(ground)), whole_(whole), ground_outside_lakes_(ground_outside_lakes), epsilon_(epsilon) {
    rect_ = {ground_->domain.first, ground_->domain.resolution};
    flood_ = flood_tile(ground_->data, rect_);
  }

  std::string message(int round) override {
    if (round == 0) return encode(flood_.graph);
    if (round == 1) return encode(lakes_.lakes);
    return eps_->message();
  }

  void answer(int round, std::string_view bytes) override {
    if (round == 0) {
      const auto levels = bytes::take_vector<float>(bytes, "spill levels");
      water_ = apply_spill_levels(flood_, levels);
      flood_ = {};  // the labels and levels of the flood are done with
      lakes_ = label_tile_lakes(water_, ground_->data, rect_, whole_);
    } else if (round == 1) {
      lake_number_ = bytes::take_vector<std::int32_t>(bytes, "lake numbers");
      if (lake_number_.size() != lakes_.lakes.first_cell.size())
        throw std::invalid_argument("lake numbers: one per lake of the tile expected");
      if (epsilon_) eps_ = std::make_unique<TileEpsilon>(water_, rect_, whole_);
    } else {
      eps_->answer(bytes);
    }
  }

  std::vector<PortValue> outputs() override {
    const Domain& d = ground_->domain;
    auto out = std::make_shared<Heightfield>(d), depth = std::make_shared<Heightfield>(d),
         id = std::make_shared<Heightfield>(d);
    for (std::size_t c = 0; c < water_.size(); ++c) {
      const std::int32_t k = lakes_.label[c];
      const std::int32_t number = k ? lake_number_[static_cast<std::size_t>(k - 1)] : 0;
      out->data[c] = eps_ ? eps_->surface()[c] : ground_outside_lakes_ && !number ? ground_->data[c] : water_[c];
      depth->data[c] = number ? water_[c] - ground_->data[c] : 0.0f;
      id->data[c] = static_cast<float>(number);
    }
    return {HeightfieldPtr(out), HeightfieldPtr(depth), HeightfieldPtr(id)};
  }

 private:
  HeightfieldPtr ground_;
  glm::ivec2 whole_;
  bool ground_outside_lakes_;
  bool epsilon_;
  TileRect rect_;
  TileFlood flood_;
  std::vector<float> water_;
  TileLakeLabels lakes_;
  std::vector<std::int32_t> lake_number_;
  std::unique_ptr<TileEpsilon> eps_;
};

// Depressions filled flat, then the lakes `keep` keeps. `ground_outside_lakes`: `out` is the ground where no lake
// is kept (Lakes), else the filled surface everywhere (FillDepressions, which keeps every lake). `epsilon`: `out` is
// the epsilon surface instead (FillDepressions' default flats); depth and lakes still come from the flat levels, as
// on the whole domain.
class FlatFillAcrossTiles : public TileGraphAlgorithm {
 public:
  FlatFillAcrossTiles(glm::ivec2 whole, KeepLake keep, bool ground_outside_lakes, bool epsilon = false)
      : whole_(whole), keep_(std::move(keep)), ground_outside_lakes_(ground_outside_lakes), epsilon_(epsilon) {}

  int rounds() const override { return epsilon_ ? 3 : 2; }

  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round + 1 < rounds()) return true;
    return epsilon_ && perimeter_minima_fell(message_views(messages));
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("filling across tiles needs a heightfield input");
    return std::make_unique<FlatFillTile>(*ground, whole_, ground_outside_lakes_, epsilon_);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    if (round >= 2) return solve_perimeter_minima(message_views(messages), whole_);
    if (round == 0) return solve_spill_messages(message_views(messages), whole_);
    return solve_lake_messages(message_views(messages), whole_, keep_);
  }

 private:
  glm::ivec2 whole_;
  KeepLake keep_;
  bool ground_outside_lakes_;
  bool epsilon_;
};

// FillDepressions keeps every lake (or, carving, those no deeper than max_depth); Lakes those deep and large enough,
// as the whole-domain node decides (nodes/hydrology/depressions.cpp).
const bool kFillRegistered = register_tile_graph("FillDepressions", [](const ParamView& p, const Domain& whole) {
  const bool epsilon = p.get<std::string>("flats") == "epsilon";
  if (p.get<std::string>("mode") == "carve") return carve_across_tiles(whole, p.get<double>("max_depth"), epsilon);
  std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<FlatFillAcrossTiles>(
      whole.resolution, [](float, std::int64_t) { return true; }, false, epsilon);
  return algorithm;
});

const bool kLakesRegistered = register_tile_graph("Lakes", [](const ParamView& p, const Domain& whole) {
  const double min_depth = p.get<double>("min_depth"), min_area = p.get<double>("min_area");
  const double cell_area = FlowGrid::of(whole).cell_area();
  std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<FlatFillAcrossTiles>(
      whole.resolution,
      [=](float deepest, std::int64_t cells) {
        return deepest >= min_depth && static_cast<double>(cells) * cell_area >= min_area;
      },
      true);
  return algorithm;
});

}  // namespace
}  // namespace orogen::hydrology
