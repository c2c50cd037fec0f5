#pragma once
// The share of its flow each cell hands to each of its receivers, for the accumulations whose sums are floating
// point (D-infinity, MFD, and D8 with a weight per cell), and the pull that adds a cell's shares up.
//
// A cell's accumulation is defined as a function of its upstream neighbours' accumulations alone, whatever order a
// traversal of the flow graph takes (accumulate() on the whole domain, nodes/hydrology/tile_shares.h across tiles):
//
//     acc(c) = w(c) + sum over k = 0, 1, ..., 7 (in that order) of acc(m_k) * fraction(m_k, opposite(k))
//
// over the neighbours m_k of c that send it flow, in double. The fraction is a function of the donor's nine heights
// (flow_proportions), so a tile that sees one sample beyond its border computes every fraction of its own cells as
// the whole domain does, and the sum above is the same sequence of roundings wherever it is computed.
// (Implemented in flow_routing.cpp, next to the routing it shares.)
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

class FlowShares {
 public:
  // Receivers of every cell of `g` with the heights `z` and `opt`'s method and outlets. O(n) memory: a byte a cell;
  // for MFD also its normaliser and a pointer to its weights (16 bytes) and a float per receiver (each weight
  // computed once: its exp and log are most of MFD's cost); for D-infinity 4 bytes (its split).
  FlowShares(const FlowGrid& g, std::span<const float> z, const RoutingOptions& opt, const ExecContext* ctx = nullptr);

  // Bit k set: cell c sends part of its flow to its neighbour k.
  std::uint8_t receivers(std::int32_t c) const { return receivers_[static_cast<std::size_t>(c)]; }
  // The fraction of c's flow that its receiver k gets: exactly the proportion flow_proportions gives (for D-infinity
  // its split in single precision, as accumulate always stored it; 1 for D8).
  double fraction(std::int32_t c, int k) const {
    const auto u = static_cast<std::size_t>(c);
    if (method_ == FlowMethod::MFD) {
      // Receiver k's weight (its place among the cell's receivers, in neighbour order) times 1 / their sum: the
      // product route_cell makes.
      const int at = std::popcount(static_cast<unsigned>(receivers_[u]) & ((1u << k) - 1u));
      return static_cast<double>(weights_of_[u][at]) * inverse_sum_[u];
    }
    if (method_ == FlowMethod::D8) return 1.0;
    // D-infinity, two receivers: the cardinal one (even k) gets the split, the diagonal one the rest; one gets all.
    if (std::popcount(static_cast<unsigned>(receivers_[u])) < 2) return 1.0;
    return (k & 1) ? 1.0 - static_cast<double>(split_[u]) : static_cast<double>(split_[u]);
  }
  // Whether neighbour k of c (inside the grid) sends c flow.
  bool donor(std::int32_t c, int k) const { return (receivers(c + off_[k]) >> opposite(k)) & 1u; }
  std::int32_t offset(int k) const { return off_[k]; }

 private:
  FlowMethod method_;
  std::int32_t off_[8];
  std::vector<std::uint8_t> receivers_;
  std::vector<double> inverse_sum_;              // MFD: 1 / the sum of the cell's weights
  std::vector<std::vector<float>> row_weights_;  // MFD: each row's weights, cell after cell, receiver after receiver
  std::vector<const float*> weights_of_;         // MFD: the cell's first weight in its row's
  std::vector<float> split_;                     // D-infinity: the share of the cardinal receiver when there are two
};

}  // namespace orogen::hydrology
