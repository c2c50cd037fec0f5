#pragma once
// Flow routing across closed depressions without filling them first: the basin graph of Cordonnier, Bovy &
// Braun 2019 ("A versatile, linear complexity algorithm for flow routing in topographies with depressions",
// Earth Surface Dynamics 7). Next to the Priority-Flood routing of flow_routing.h, for callers that route
// the same grid again and again (landscape evolution) and mostly find few or no pits.
//
// One call:
//   1. local D8 receivers over the unmodified heights (steepest drop / distance, ties to the lowest k, the
//      neighbour numbering and outlet rules of flow_routing.h), donors;
//   2. the pits (cells other than outlets with no lower neighbour). None: go to 6. This is the common case in
//      a landscape-evolution run after the first steps, and then nothing else is done: the cost is one
//      D8 pass and the stack, no priority queue, no fill;
//   3. the basin of every pit (its upstream cells: a connected component of the receiver forest), labelled
//      by a walk over the donors of the pit only; all outlet basins form one node, the root;
//   4. the basin graph: for every pair of 8-adjacent cells in different basins the pass height
//      max(z_a, z_b), only on the boundaries of pit basins (cost proportional to the pit basins, not the grid);
//      its minimum spanning tree (Kruskal; ties by cell index, so deterministic) rooted at the outlets;
//   5. every pit rerouted to its pass ("carve" variant): the receivers on the path from the pass cell down
//      to the pit are reversed and the pass cell drains into the cell across the pass, so every receiver is
//      still an 8-neighbour and water crosses each depression to its outlet along the lowest spill path
//      (the minimum spanning tree gives the minimax path to the outlets, the Priority-Flood spill level);
//   6. the stack order (Braun & Willett 2013) per outlet tree, built in parallel and concatenated in outlet
//      order, so identical for any thread count.
// After route_basin_graph, cells on the reversed paths and in the lakes may sit below their receivers:
// callers that need a surface that drains (a lake filled with sediment) call route_basin_graph_fill.
#include <cstdint>
#include <span>
#include <vector>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

struct BasinRouting {
  D8Flow flow;                      // receivers after rerouting (neighbours; == self only at outlets)
  std::vector<std::int32_t> stack;  // every cell after its receiver
  std::vector<std::int32_t>
      tree_begin;  // outlet tree t is stack[tree_begin[t], tree_begin[t + 1]); its first cell is its outlet
  // Figures of the last call.
  int pits = 0;         // local minima rerouted
  int pit_cells = 0;    // cells in their basins
  int graph_edges = 0;  // candidate basin-graph edges (cell pairs across pit-basin boundaries)
  int tree_edges = 0;   // edges of the minimum spanning tree (== pits when an outlet exists)

  // Scratch kept between calls (routing the same grid again allocates nothing).
  std::vector<std::int32_t> label_;  // pit basin of a cell, 0 elsewhere; reset after use
  std::vector<std::int32_t> row_pits_;
  std::vector<std::uint8_t> carved_;
  std::vector<std::vector<std::int32_t>> pieces_, piece_roots_;
};

// Routes over z (size g.size(), finite) into r, reusing r's buffers. Outlets as in flow_routing.h; when no
// outlet exists the basin of the lowest pit is the root and keeps its pit.
void route_basin_graph(const FlowGrid& g, std::span<const double> z, const Outlets& outlets, BasinRouting& r,
                       const ExecContext* ctx = nullptr);
void route_basin_graph(const FlowGrid& g, std::span<const float> z, const Outlets& outlets, BasinRouting& r,
                       const ExecContext* ctx = nullptr);

// "Fill" variant: as route_basin_graph, and the lakes are filled in z: after rerouting, every cell of a
// pit basin is raised to just above its carved receiver where it is not higher (the lake reaches its spill
// level with a gradient of max(1e-9 m, |z| 1e-12) per cell towards the pass for double, one float step for
// float: the Priority-Flood+epsilon surface), then those cells are routed by D8 over the filled surface.
// No cell is then a pit, so the next call on a slightly changed surface usually finds none. `raised`
// (optional, size g.size()) accumulates the raise per cell.
void route_basin_graph_fill(const FlowGrid& g, std::span<double> z, const Outlets& outlets, BasinRouting& r,
                            std::span<double> raised = {}, const ExecContext* ctx = nullptr);
void route_basin_graph_fill(const FlowGrid& g, std::span<float> z, const Outlets& outlets, BasinRouting& r,
                            std::span<double> raised = {}, const ExecContext* ctx = nullptr);

// Upslope area (m^2, the cell itself included) or weight, from the stack: acc[c] = w[c] + sum over donors,
// one outlet tree per task (deterministic).
void accumulate_stack(const FlowGrid& g, const BasinRouting& r, std::span<double> acc,
                      std::span<const float> weight = {});

// Calls fn(first, last) for the stack range of every outlet tree, trees in parallel.
template <class Fn>
void for_each_tree(const BasinRouting& r, Fn&& fn);

}  // namespace orogen::hydrology

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace orogen::hydrology {
template <class Fn>
void for_each_tree(const BasinRouting& r, Fn&& fn) {
  const int trees = static_cast<int>(r.tree_begin.size()) - 1;
  if (trees <= 0) return;
  tbb::parallel_for(tbb::blocked_range<int>(0, trees, 4), [&](const tbb::blocked_range<int>& b) {
    for (int t = b.begin(); t != b.end(); ++t) fn(r.tree_begin[t], r.tree_begin[t + 1]);
  });
}
}  // namespace orogen::hydrology
