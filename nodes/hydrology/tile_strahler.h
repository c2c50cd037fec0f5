#pragma once
// Strahler orders of a D8 channel network across tiles, exact: RiverExtract's and DrainageMetrics' tile-graph
// distribution (nodes/hydrology/rivers_across_tiles.cpp, drainage_across_tiles.cpp, docs/distributed.md).
//
// The whole-domain order (strahler_orders, nodes/hydrology/channels.h) of a channel cell is 1 at a source, else the
// highest order o among its channel donors, plus one when two or more donors have o. It is a function of one
// summary of the donors, (o, how many have it), and summaries combine across any split of the donors (the larger o
// wins, equal o add their counts). Across tiles:
//
//  - each flow edge (a cell and its D8 receiver) is taken by exactly one tile, the lowest-numbered holding it
//    (TileAccumulation::receiver, nodes/hydrology/tile_accumulation.h), so a shared sample's donors are split among
//    the tiles that hold it;
//  - each round, each tile computes the orders of its cells from its own edges and, at its perimeter cells, the
//    summaries of the other tiles' donors it last received, and sends the summary of its own donors at each
//    perimeter cell (TileStrahler::message); the solve answers each tile with the other tiles' summaries at its
//    perimeter cells (solve_strahler_perimeters);
//  - the rounds end when no tile's summaries changed (strahler_changed).
//
// Unknown donors start absent, and the order is monotone in its donors' orders, so every value rises towards the
// whole-domain order and never past it; when a round changes nothing, every cell satisfies the order's equation
// with its whole set of donors, and since the receivers form no cycle that solution is unique: the whole-domain
// orders, for any tiling. The rounds grow with the number of tile borders a channel crosses between two confluences
// that matter (each round carries the orders one tile further downstream); each is O(perimeter) in bytes.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

// The channel donors of a cell as far as they are known: the highest order and how many donors have it.
struct DonorSummary {
  std::int32_t order = 0;  // 0: no channel donor
  std::int32_t count = 0;
};

class TileStrahler {
 public:
  // `receiver`: per tile cell, the tile cell its flow edge goes to if this tile takes the edge, else -1
  // (TileAccumulation::receiver); `channel`: per tile cell, nonzero on the channel network. Both rect.size,
  // row-major. The tile keeps the channel cells alone (a few in a hundred), not a value a cell. Throws
  // std::invalid_argument if the sizes disagree or the channel's receivers form a cycle.
  TileStrahler(const std::vector<std::int32_t>& receiver, const std::vector<std::uint8_t>& channel,
               const TileRect& rect, glm::ivec2 domain_size);
  // The summaries of this tile's own donors at its perimeter cells, and whether any changed since the last message.
  std::string message();
  // The other tiles' summaries at this tile's perimeter cells; the orders are computed again from them.
  void answer(std::string_view bytes);
  // The channel cells (tile cells, ascending) and their Strahler orders, in that order: the whole domain's once no
  // round changes anything.
  const std::vector<std::int32_t>& cells() const { return cells_; }
  const std::vector<std::int32_t>& orders() const { return order_; }

 private:
  void compute();

  TileRect rect_;
  glm::ivec2 domain_;
  std::vector<std::int32_t> cells_;           // the channel cells, ascending
  std::vector<std::int32_t> receiver_;        // per channel cell: its receiver's index in cells_, or -1
  std::vector<std::int32_t> upstream_first_;  // indices in cells_, every one before its receiver
  std::vector<std::int32_t> order_;           // per channel cell
  std::vector<DonorSummary> own_;             // per perimeter cell: this tile's donors
  std::vector<DonorSummary> external_;        // per perimeter cell: the other tiles' donors, as last received
  std::vector<DonorSummary> sent_;
  bool first_ = true;
};

// The channel cells: those whose count of draining cells times `cell_area` reaches `threshold`, as the whole-domain
// nodes pick them.
std::vector<std::uint8_t> channel_cells(const std::vector<std::int64_t>& counts, double cell_area, double threshold);

// Every tile's message of a round (indexed by tile) into every tile's answer. Throws std::invalid_argument on
// malformed messages.
std::vector<std::string> solve_strahler_perimeters(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// Whether any tile's summaries changed in this round's messages (else the orders are final).
bool strahler_changed(std::span<const std::string_view> messages);

}  // namespace orogen::hydrology
