#pragma once
// Flow accumulation across tiles for the sums in floating point (D-infinity, MFD, and D8 with a rainfall weight),
// bit for bit the whole domain's: the building block of FlowAccumulation's tile-graph run for those
// (nodes/hydrology/flow_across_tiles.cpp, docs/distributed.md).
//
// The whole-domain accumulation pulls, for every cell, its own weight plus its donors' shares in neighbour order
// (nodes/hydrology/flow_shares.h), once its donors are done: a cell's value is a function of its donors' values and
// its neighbourhood's heights alone, not of the order of the traversal. Across tiles the same pull runs as a
// dataflow over the tiles' shared borders (tiles share their border samples, cli/tiling.h, so every flow edge, a
// donor and its receiver, lies in one tile):
//
//  1. Edges: each tile, with its heights grown by the one-sample ring (nodes/hydrology/tile_ring.h), knows the
//     receivers and fractions of its own cells. It declares the edges it takes (those not lying wholly on its first
//     column or row when another tile lies before it: one taker per edge) into its perimeter cells. The solve tells
//     every tile which perimeter cells get flow from outside it, along which neighbour (the edges whose donor it does
//     not hold), and every taker which of its edges another tile waits for.
//  2. Shares, in rounds: each tile pulls every cell whose donors are all done (its own cells, or the shares that
//     arrived); it sends the share (the donor's accumulation times its fraction, in double) of every awaited edge
//     whose donor became done; the solve hands each to the tiles that wait for it. The rounds end when every tile is
//     done, so all tiles stop together. Flow paths descend, so the edges form a DAG and every round completes at
//     least one more of them: the rounds are at most one more than the tile crossings of the flow path that crosses
//     tile borders most often (a path that follows a tile border may cross it at every step).
//
// Every pull adds the same values in the same order as on the whole domain, so each cell's accumulation is the whole
// domain's, bit for bit, for any tiling. A message carries, per awaited edge, 16 bytes, once: O(perimeter) in all.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

class FlowShares;

class TileShares {
 public:
  // `ringed_z`: the routed heights on ringed_rect(rect, domain_size) (the tile and its ring), row-major. `weight`:
  // each tile cell's own amount (rect.size, row-major), or empty for the cell area dx * dy. `routing`: the method and
  // exponent (the domain's border drains; no outlet mask).
  TileShares(std::vector<float> ringed_z, const TileRect& rect, glm::ivec2 domain_size, double dx, double dy,
             const RoutingOptions& routing, std::vector<float> weight);
  ~TileShares();

  // Round 1: the rectangle and the edges the tile takes into its perimeter cells.
  std::string edges_message() const;
  // Its answer: the edges from outside and the awaited edges; pulls every cell it can.
  void take_edges(std::string_view answer);
  // Rounds 2, ...: whether the tile is done, its rectangle, and the shares of the awaited edges whose donors became
  // done since the last message.
  std::string shares_message();
  // Its answer: the shares from outside; pulls every cell they complete.
  void take_shares(std::string_view answer);

  bool done() const { return pending_ == 0; }
  // The accumulation of every tile cell (rect.size, row-major), once done; the tile lets go of its state (it can
  // take no more answers).
  std::vector<double> take_accumulation();

 private:
  struct OutEdge {
    std::int32_t donor;    // ringed cell
    std::uint8_t k;        // the receiver is the donor's neighbour k
    std::int64_t key;      // receiver's domain sample * 8 + the neighbour of the receiver that is the donor
    bool awaited = false;  // another tile waits for it
  };
  std::int32_t ringed_cell(int i, int j) const { return (at_.y + j) * gw_ + at_.x + i; }
  bool in_tile(std::int32_t r) const;
  // The perimeter index of tile cell `cell` (row-major in the tile), or -1.
  std::int32_t perimeter_of(std::int64_t cell) const {
    return perimeter_position(rect_.size, static_cast<int>(cell % rect_.size.x), static_cast<int>(cell / rect_.size.x));
  }
  void finish(std::int32_t r, std::vector<std::int32_t>& ready);  // pulls r, then counts down its receivers
  void run(std::vector<std::int32_t>& ready);

  TileRect rect_;
  glm::ivec2 domain_, at_;
  int gw_ = 0;  // the ringed tile's width
  std::unique_ptr<FlowShares> shares_;
  std::vector<float> weight_;
  double area_ = 0.0;
  std::vector<double> acc_;              // per ringed cell
  std::vector<std::uint8_t> remaining_;  // donors not done, per ringed cell of the tile
  std::vector<std::uint8_t> outside_;    // per perimeter cell: bit k when neighbour k sends from outside the tile
  std::vector<double> inflow_;           // per perimeter cell, 8 slots: those shares
  std::vector<OutEdge> out_;             // sorted by donor
  std::vector<std::uint8_t> exports_;    // per ringed cell: donor of an awaited edge
  std::vector<std::int64_t> send_keys_;
  std::vector<double> send_values_;
  std::int64_t pending_ = 0;  // tile cells not done
};

// Round 1's solve: every tile's edges message (indexed by tile) into its answer. Throws std::invalid_argument on
// malformed messages.
std::vector<std::string> solve_share_edges(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// A shares round's solve. Throws std::invalid_argument on malformed messages, and when no tile is done yet no share
// moved (a cycle: heights that are not finite).
std::vector<std::string> solve_shares(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// Whether every tile was done when it sent its shares message: the last round.
bool shares_done(std::span<const std::string_view> messages);

}  // namespace orogen::hydrology
