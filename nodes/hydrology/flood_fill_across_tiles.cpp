// FloodFill across the tiles of a tiled or distributed build, exact (graph/tile_graph.h, docs/distributed.md).
//
// The whole-domain node (flood_fill, nodes/hydrology/depressions.cpp) floods every cell 8-connected to the seed's
// nearest sample whose ground lies below a level: the given one, or the Flat Priority-Flood level at the seed (its
// depression's spill level). Across tiles:
//
//  - spill (level_mode 'spill' only): each tile floods itself with labels and sends its spill graph (Barnes 2016,
//    nodes/hydrology/tile_fill.h), and the tile holding the seed adds its own flood level and label there; the solve
//    gives every tile the level max(local level, the label's spill level), which is the whole-domain Flat fill at the
//    seed bit for bit (both are a minimax height over paths: no arithmetic);
//  - components: each tile labels its own components of ground below the level and sends the component of each
//    perimeter cell (and the tile holding the seed, the seed's); the solve joins components through the samples
//    neighboring tiles share (every 8-neighbor pair lies in one tile, so that is the only way a lake crosses a
//    border) and tells each tile which of its components are the seed's.
//
// Every output is then a per-cell function of the ground, the level and whether the cell is flooded, as on the whole
// domain. Messages are O(perimeter) a tile, two rounds with the spill level, one with a given level.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/depressions.h"
#include "nodes/hydrology/tile_components.h"
#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {
namespace {

constexpr const char* kWhat = "flood fill across tiles";

class FloodFillTile : public TileGraphTile {
 public:
  FloodFillTile(HeightfieldPtr ground, glm::ivec2 seed, bool spill, float level)
      : ground_(std::move(ground)), spill_(spill), level_(level) {
    rect_ = {ground_->domain.first, ground_->domain.resolution};
    const glm::ivec2 at = seed - rect_.first;
    if (at.x >= 0 && at.y >= 0 && at.x < rect_.size.x && at.y < rect_.size.y) seed_cell_ = at.y * rect_.size.x + at.x;
  }

  std::string message(int round) override {
    std::string out;
    if (spill_ && round == 0) {
      // The spill graph, with the tile's own flood level and label at the seed if it holds it.
      const TileFlood flood = flood_tile(ground_->data, rect_);
      const auto c = static_cast<std::size_t>(std::max(seed_cell_, 0));
      bytes::put(out, static_cast<std::uint8_t>(seed_cell_ >= 0));
      bytes::put(out, seed_cell_ >= 0 ? flood.level[c] : 0.0f);
      bytes::put(out, seed_cell_ >= 0 ? flood.label[c] : std::int32_t{0});
      out += encode(flood.graph);
      return out;
    }
    // Components of ground below the level (as the whole-domain flood's test `ground < level`).
    std::vector<std::uint8_t> wet(ground_->data.size());
    for (std::size_t c = 0; c < wet.size(); ++c) wet[c] = ground_->data[c] < level_;
    components_ = label_components(rect_.size.x, rect_.size.y, wet, label_);
    put_tile_rect(out, rect_);
    bytes::put(out, seed_cell_ >= 0 ? label_[static_cast<std::size_t>(seed_cell_)] : std::int32_t{-1});
    std::vector<std::int32_t> perimeter;
    for (const std::int32_t c : perimeter_cells(rect_.size)) perimeter.push_back(label_[static_cast<std::size_t>(c)]);
    bytes::put_vector(out, perimeter);
    return out;
  }

  void answer(int round, std::string_view bytes) override {
    if (spill_ && round == 0) {
      level_ = bytes::take<float>(bytes, kWhat);
    } else {
      const auto flooded = bytes::take_vector<std::int32_t>(bytes, kWhat);
      flooded_.assign(static_cast<std::size_t>(components_) + 1, 0);
      for (const std::int32_t k : flooded) {
        if (k < 1 || static_cast<std::size_t>(k) >= flooded_.size())
          throw std::invalid_argument("flood fill across tiles: an unknown component");
        flooded_[static_cast<std::size_t>(k)] = 1;
      }
    }
    if (!bytes.empty()) throw std::invalid_argument("flood fill across tiles: trailing bytes");
  }

  std::vector<PortValue> outputs() override {
    const Domain& d = ground_->domain;
    auto out = std::make_shared<Heightfield>(*ground_), depth = std::make_shared<Heightfield>(d),
         mask = std::make_shared<Heightfield>(d);
    for (std::size_t c = 0; c < label_.size(); ++c) {
      if (!flooded_[static_cast<std::size_t>(label_[c])]) continue;
      out->data[c] = level_;
      depth->data[c] = level_ - ground_->data[c];
      mask->data[c] = 1.0f;
    }
    return {HeightfieldPtr(out), HeightfieldPtr(depth), HeightfieldPtr(mask)};
  }

 private:
  HeightfieldPtr ground_;
  bool spill_;
  float level_;
  TileRect rect_;
  std::int32_t seed_cell_ = -1;  // the seed's tile cell, or -1 if another tile holds it
  int components_ = 0;
  std::vector<std::int32_t> label_;    // per tile cell: its component below the level, 0 if dry
  std::vector<std::uint8_t> flooded_;  // per component: the seed's
};

class FloodFillAcrossTiles : public TileGraphAlgorithm {
 public:
  FloodFillAcrossTiles(glm::ivec2 whole, glm::ivec2 seed, bool spill, float level)
      : whole_(whole), seed_(seed), spill_(spill), level_(level) {}

  int rounds() const override { return spill_ ? 2 : 1; }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("flood fill across tiles needs a heightfield input");
    return std::make_unique<FloodFillTile>(*ground, seed_, spill_, level_);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    return spill_ && round == 0 ? solve_level(messages) : solve_components(messages);
  }

 private:
  // The Flat fill's level at the seed, for every tile.
  std::vector<std::string> solve_level(const std::vector<std::string>& messages) const {
    std::vector<TileSpillGraph> graphs;
    int seed_tile = -1;
    float local = 0.0f;
    std::int32_t label = 0;
    for (std::size_t t = 0; t < messages.size(); ++t) {
      std::string_view m(messages[t]);
      const bool holds = bytes::take<std::uint8_t>(m, kWhat) != 0;
      const float l = bytes::take<float>(m, kWhat);
      const auto k = bytes::take<std::int32_t>(m, kWhat);
      if (holds && seed_tile < 0) seed_tile = static_cast<int>(t), local = l, label = k;
      graphs.push_back(decode_spill_graph(m));
    }
    if (seed_tile < 0) throw std::invalid_argument("flood fill across tiles: no tile holds the seed");
    const auto levels = solve_spill_graphs(graphs, whole_);
    const auto& spill = levels[static_cast<std::size_t>(seed_tile)];
    if (label < 0 || static_cast<std::size_t>(label) >= spill.size())
      throw std::invalid_argument("flood fill across tiles: the seed's label is not a perimeter cell");
    std::string answer;
    bytes::put(answer, std::max(local, spill[static_cast<std::size_t>(label)]));
    return std::vector<std::string>(messages.size(), answer);
  }

  // Joins the tiles' components through their shared samples; answers each tile with its components that are the
  // seed's.
  std::vector<std::string> solve_components(const std::vector<std::string>& messages) const {
    std::vector<TileRect> rects;
    std::vector<std::vector<std::int32_t>> perimeters;
    std::size_t seed_tile = messages.size();
    std::int32_t seed = -1;
    for (std::size_t t = 0; t < messages.size(); ++t) {
      std::string_view m(messages[t]);
      rects.push_back(take_tile_rect(m, whole_, kWhat));
      const auto s = bytes::take<std::int32_t>(m, kWhat);
      perimeters.push_back(bytes::take_vector<std::int32_t>(m, kWhat));
      if (!m.empty() || perimeters.back().size() != perimeter_cells(rects.back().size).size())
        throw std::invalid_argument("flood fill across tiles: one component per perimeter cell expected");
      for (const std::int32_t k : perimeters.back())
        if (k < 0) throw std::invalid_argument("flood fill across tiles: a negative component");
      if (s >= 0 && seed_tile == messages.size()) seed_tile = t, seed = s;
    }
    if (seed_tile == messages.size()) throw std::invalid_argument("flood fill across tiles: no tile holds the seed");
    LowestRootUnionFind joined;
    std::vector<std::unordered_map<std::int32_t, std::int32_t>> node(messages.size());  // tile component -> node
    auto node_of = [&](std::size_t t, std::int32_t k) {
      const auto [it, fresh] = node[t].try_emplace(k, 0);
      if (fresh) it->second = joined.add();
      return it->second;
    };
    const std::int32_t seed_node = seed > 0 ? node_of(seed_tile, seed) : -1;
    join_perimeter_components(
        joined, rects, whole_,
        [&](std::size_t t, std::size_t p) {
          const std::int32_t k = perimeters[t][p];
          return k ? node_of(t, k) : -1;
        },
        "flood fill across tiles: tiles disagree whether a shared sample is flooded");
    std::vector<std::string> answers(messages.size());
    for (std::size_t t = 0; t < messages.size(); ++t) {
      std::vector<std::int32_t> flooded;
      if (seed_node >= 0)
        for (const auto& [k, n] : node[t])
          if (joined.root(n) == joined.root(seed_node)) flooded.push_back(k);
      std::sort(flooded.begin(), flooded.end());
      bytes::put_vector(answers[t], flooded);
    }
    return answers;
  }

  glm::ivec2 whole_, seed_;
  bool spill_;
  float level_;
};

// Every parameter value: the seed's sample is found on the whole domain as flood_fill finds it.
const bool kFloodFillRegistered = register_tile_graph("FloodFill", [](const ParamView& p, const Domain& whole) {
  const glm::dvec2 s = whole.to_sample(p.get<glm::dvec2>("position"));
  const glm::ivec2 last = glm::max(whole.resolution - 1, glm::ivec2(0));
  const glm::ivec2 seed(std::clamp(static_cast<int>(std::lround(s.x)), 0, last.x),
                        std::clamp(static_cast<int>(std::lround(s.y)), 0, last.y));
  const bool spill = p.get<std::string>("level_mode") == "spill";
  std::unique_ptr<TileGraphAlgorithm> algorithm =
      std::make_unique<FloodFillAcrossTiles>(whole.resolution, seed, spill, static_cast<float>(p.get<double>("level")));
  return algorithm;
});

}  // namespace
}  // namespace orogen::hydrology
