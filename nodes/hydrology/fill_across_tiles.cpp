// FillDepressions (fill mode, flat surfaces) and Lakes across the tiles of a tiled or distributed build, exact
// (graph/tile_graph.h): round 0 floods each tile and solves the spill graphs of all tiles (nodes/hydrology/tile_fill.h,
// Barnes 2016); round 1 joins and numbers the lakes across tiles (nodes/hydrology/tile_lakes.h). The outputs equal
// the whole-domain node's bit for bit: levels are minimax heights over paths (no arithmetic), depths are the same
// subtraction per cell, and lakes are kept and numbered by the same rule over whole lakes.
//
// FillDepressions' epsilon flats and carve mode are not here: their heights follow the order in which one flood
// reaches each cell across the whole domain, so they are computed on the whole domain (docs/distributed.md).
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/flow_routing.h"
#include "graph/tile_bytes.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_lakes.h"

namespace orogen::hydrology {
namespace {

class FlatFillTile : public TileGraphTile {
 public:
  FlatFillTile(HeightfieldPtr ground, glm::ivec2 whole, bool ground_outside_lakes)
      : ground_(std::move(ground)), whole_(whole), ground_outside_lakes_(ground_outside_lakes) {
    rect_ = {ground_->domain.first, ground_->domain.resolution};
    flood_ = flood_tile(ground_->data, rect_);
  }

  std::string message(int round) override {
    if (round == 0) return encode(flood_.graph);
    return encode(lakes_.lakes);
  }

  void answer(int round, std::string_view bytes) override {
    if (round == 0) {
      const auto levels = bytes::take_vector<float>(bytes, "spill levels");
      water_ = apply_spill_levels(flood_, levels);
      flood_ = {};  // the labels and levels of the flood are done with
      lakes_ = label_tile_lakes(water_, ground_->data, rect_, whole_);
    } else {
      lake_number_ = bytes::take_vector<std::int32_t>(bytes, "lake numbers");
      if (lake_number_.size() != lakes_.lakes.first_cell.size())
        throw std::invalid_argument("lake numbers: one per lake of the tile expected");
    }
  }

  std::vector<PortValue> outputs() override {
    const Domain& d = ground_->domain;
    auto out = std::make_shared<Heightfield>(d), depth = std::make_shared<Heightfield>(d),
         id = std::make_shared<Heightfield>(d);
    for (std::size_t c = 0; c < water_.size(); ++c) {
      const std::int32_t k = lakes_.label[c];
      const std::int32_t number = k ? lake_number_[static_cast<std::size_t>(k - 1)] : 0;
      out->data[c] = ground_outside_lakes_ && !number ? ground_->data[c] : water_[c];
      depth->data[c] = number ? water_[c] - ground_->data[c] : 0.0f;
      id->data[c] = static_cast<float>(number);
    }
    return {HeightfieldPtr(out), HeightfieldPtr(depth), HeightfieldPtr(id)};
  }

 private:
  HeightfieldPtr ground_;
  glm::ivec2 whole_;
  bool ground_outside_lakes_;
  TileRect rect_;
  TileFlood flood_;
  std::vector<float> water_;
  TileLakeLabels lakes_;
  std::vector<std::int32_t> lake_number_;
};

// Depressions filled flat, then the lakes `keep` keeps. `ground_outside_lakes`: `out` is the ground where no lake
// is kept (Lakes), else the filled surface everywhere (FillDepressions, which keeps every lake).
class FlatFillAcrossTiles : public TileGraphAlgorithm {
 public:
  FlatFillAcrossTiles(glm::ivec2 whole, KeepLake keep, bool ground_outside_lakes)
      : whole_(whole), keep_(std::move(keep)), ground_outside_lakes_(ground_outside_lakes) {}

  int rounds() const override { return 2; }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("filling across tiles needs a heightfield input");
    return std::make_unique<FlatFillTile>(*ground, whole_, ground_outside_lakes_);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    std::vector<std::string> answers(messages.size());
    if (round == 0) {
      std::vector<TileSpillGraph> graphs;
      graphs.reserve(messages.size());
      for (const auto& m : messages) graphs.push_back(decode_spill_graph(m));
      const auto levels = solve_spill_graphs(graphs, whole_);
      for (std::size_t t = 0; t < levels.size(); ++t) bytes::put_vector(answers[t], levels[t]);
    } else {
      std::vector<TileLakes> lakes;
      lakes.reserve(messages.size());
      for (const auto& m : messages) lakes.push_back(decode_tile_lakes(m));
      const auto numbers = solve_tile_lakes(lakes, whole_, keep_);
      for (std::size_t t = 0; t < numbers.size(); ++t) bytes::put_vector(answers[t], numbers[t]);
    }
    return answers;
  }

 private:
  glm::ivec2 whole_;
  KeepLake keep_;
  bool ground_outside_lakes_;
};

// FillDepressions keeps every lake; Lakes those deep and large enough, as the whole-domain node decides
// (nodes/hydrology/depressions.cpp).
const bool kFillRegistered = register_tile_graph(
    "FillDepressions",
    [](const ParamView& p, const Domain& whole) {
      std::unique_ptr<TileGraphAlgorithm> algorithm;
      if (p.get<std::string>("mode") == "fill" && p.get<std::string>("flats") == "flat")
        algorithm = std::make_unique<FlatFillAcrossTiles>(
            whole.resolution, [](float, std::int64_t) { return true; }, false);
      return algorithm;
    },
    "with mode 'fill' and flats 'flat'");

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
