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
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

class FlowShares {
 public:
  // Receivers of every cell of `g` with the heights `z` and `opt`'s method and outlets. O(n) memory: a byte a cell;
  // for MFD also a float per receiver (each weight computed once: its exp and log are most of MFD's cost) and where
  // they are (1.5 bytes); for D-infinity 4 bytes (its split).
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
      // The sum is added again here, in the same order, rather than kept (the weights are floats, exact in double):
      // 8 bytes a cell less for a few additions and a division a flow edge.
      const unsigned bits = receivers_[u];
      const float* w = weights_.data() + block_first_[u / kBlock] + before_in_block_[u];
      double sum = 0.0;
      for (int m = 0, n = bit_count(bits); m < n; ++m) sum += static_cast<double>(w[m]);
      return static_cast<double>(w[bit_count(bits & ((1u << k) - 1u))]) * (1.0 / sum);
    }
    if (method_ == FlowMethod::D8) return 1.0;
    // D-infinity, two receivers: the cardinal one (even k) gets the split, the diagonal one the rest; one gets all.
    if (bit_count(receivers_[u]) < 2) return 1.0;
    return (k & 1) ? 1.0 - static_cast<double>(split_[u]) : static_cast<double>(split_[u]);
  }
  // Whether neighbour k of c (inside the grid) sends c flow.
  bool donor(std::int32_t c, int k) const { return (receivers(c + off_[k]) >> opposite(k)) & 1u; }
  std::int32_t offset(int k) const { return off_[k]; }

 private:
  // The cells of a block, whose weights' place is one 64-bit index: with a byte a cell for the place within the
  // block (at most 15 x 8), 1.5 bytes a cell where a pointer took 8.
  static constexpr std::size_t kBlock = 16;
  // The set bits of a byte (std::popcount is a library call on the x86-64 baseline).
  static int bit_count(unsigned byte) {
    static constexpr auto kCounts = [] {
      std::array<std::uint8_t, 256> counts{};
      for (unsigned b = 0; b < 256; ++b) counts[b] = static_cast<std::uint8_t>(std::popcount(b));
      return counts;
    }();
    return kCounts[byte & 0xFFu];
  }

  FlowMethod method_;
  std::int32_t off_[8];
  std::vector<std::uint8_t> receivers_;
  std::vector<float> weights_;                 // MFD: cell after cell, receiver after receiver
  std::vector<std::uint64_t> block_first_;     // MFD: each block's first weight in weights_
  std::vector<std::uint8_t> before_in_block_;  // MFD: the weights of the cells before this one in its block
  std::vector<float> split_;                   // D-infinity: the share of the cardinal receiver when there are two
};

}  // namespace orogen::hydrology
