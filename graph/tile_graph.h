#pragma once
// How a tile-graph node (graph/distribution.h) runs across the tiles of a tiled or distributed build, exact: the
// shape of R. Barnes's parallel hydrology (2016, 2017), common to every such algorithm (docs/distributed.md).
//
// A run goes in rounds (a fixed number, or until a round changes nothing). In each round every tile sends a message
// (small: perimeters, spill graphs, per-lake figures; never the tile), the messages of all tiles are solved once,
// identically on every rank, into one answer per tile, and each tile takes in its answer. After the last round each
// tile has the node's outputs on its own samples. The driver (cli/tile_graph_stages.h) moves the messages between ranks
// (graph/rank_group.h) and knows nothing of the algorithm; the algorithm knows nothing of ranks, so tests run it on any
// tiling in one process.
//
// Tiles share their border samples with their neighbours (cli/tiling.h), so every pair of 8-neighbours lies in
// one tile, and what crosses a border is a shared sample, seen by both tiles with the same value.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "graph/domain.h"
#include "graph/port_value.h"

namespace orogen {

class ParamView;

// One tile's state in a run.
class TileGraphTile {
 public:
  virtual ~TileGraphTile() = default;
  // The tile's message in round `round` (0, 1, ... while the algorithm's another_round() says so).
  virtual std::string message(int round) = 0;
  // The solve's answer for this tile in round `round`.
  virtual void answer(int round, std::string_view bytes) = 0;
  // The node's outputs on the tile's samples (in output order), after the last round's answer; a Report output is
  // the whole domain's, the same on every tile. An output the build does not use (output_needed) may be left unset.
  virtual std::vector<PortValue> outputs() = 0;

  // Which outputs the build uses, by output index (the driver says so right after start(); empty: all).
  void set_needed_outputs(std::vector<bool> needed) { needed_ = std::move(needed); }
  bool output_needed(std::size_t output) const {
    return needed_.empty() || output >= needed_.size() || needed_[output];
  }

 private:
  std::vector<bool> needed_;
};

class TileGraphAlgorithm {
 public:
  virtual ~TileGraphAlgorithm() = default;
  // The number of rounds, or for an algorithm that iterates to a fixed point the rounds it always runs.
  virtual int rounds() const = 0;
  // Whether another round follows round `round`, from that round's messages of every tile (so every rank
  // decides the same). Runs to a fixed point end when a round changes nothing.
  virtual bool another_round(int round, const std::vector<std::string>& messages) const {
    (void)messages;
    return round + 1 < rounds();
  }
  // A tile's state from the node's inputs (in input order) on exactly the tile's samples; their domains say where
  // the tile lies (Domain::first is its first sample in the whole domain).
  virtual std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const = 0;
  // Every tile's message of round `round`, indexed by tile (row-major over the tiling), into every tile's answer.
  // Throws std::invalid_argument on messages that do not fit together.
  virtual std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const = 0;
};

// Input k of a tile (TileGraphAlgorithm::start) as a heightfield, or nullptr when the port is unlinked (or holds no
// heightfield).
inline HeightfieldPtr tile_heightfield(const std::vector<PortValue>& inputs, std::size_t k) {
  const auto* h = k < inputs.size() ? std::get_if<HeightfieldPtr>(&inputs[k]) : nullptr;
  return h ? *h : nullptr;
}

// The algorithm of a node type for its parameter values on the build's whole domain, or nullptr when these values
// do not run across tiles (the node is then computed on the whole domain).
using TileGraphFactory =
    std::function<std::unique_ptr<TileGraphAlgorithm>(const ParamView& params, const Domain& whole)>;

// Registers the algorithm of node type `type` (at static initialisation, next to the node's declaration);
// `conditions` says for which parameter values the factory gives one ("" for all), for the node reference.
// `unlinked_inputs` names the input ports the algorithm cannot take (FlowAccumulation's rainfall weight): a node
// with one of them linked is computed on the whole domain (cli/tiling.h across_tile_nodes).
bool register_tile_graph(const std::string& type, TileGraphFactory factory, std::string conditions = {},
                         std::vector<std::string> unlinked_inputs = {});
// The registered factory of node type `type`, or nullptr.
const TileGraphFactory* find_tile_graph(const std::string& type);
// The algorithm of node type `type` for `params` on the build's whole domain `whole`, or nullptr: when the type
// registered none, when these values do not run across tiles, or when the factory refuses the run with a NodeError
// (too much work), which the node computed on the whole domain then reports itself.
std::unique_ptr<TileGraphAlgorithm> tile_graph_for(const std::string& type, const ParamView& params,
                                                   const Domain& whole);
// The conditions registered with it ("" if none or no factory).
std::string tile_graph_conditions(const std::string& type);
// The input ports that must be unlinked for the algorithm to run (empty if none or no factory).
std::vector<std::string> tile_graph_unlinked_inputs(const std::string& type);

}  // namespace orogen
