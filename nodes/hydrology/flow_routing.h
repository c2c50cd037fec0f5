#pragma once
// Flow-routing core shared by the hydrology and erosion node families: depression filling and breaching,
// D8 receivers and donors, the topological "stack" order, basin labels and flow accumulation (D8,
// D-infinity, multiple flow direction). Plain functions on row-major float grids; no node machinery.
//
// Conventions
// - A grid is nx * ny cells, row-major (cell c = j * nx + i), spacing dx, dy in metres (FlowGrid::of(domain)).
// - Neighbour k in 0..7 is (i + kDi[k], j + kDj[k]): 0 E, 1 NE, 2 N, 3 NW, 4 W, 5 SW, 6 S, 7 SE ("N" = +j).
//   opposite(k) = (k + 4) & 7. Slopes are in world units: drop / distance(k) with distance(k) = dx, dy or
//   hypot(dx, dy).
// - Outlets (base level) are the border cells (Outlets::border, default) plus any cell flagged in
//   Outlets::mask (sea, sinks). An outlet never routes flow onward; every other cell without a strictly lower
//   neighbour is a pit (also receiver[c] == c). After fill_depressions(Epsilon) no pit remains.
// - Heights must be finite.
// - Every function takes an optional ExecContext for cancellation (throws Cancelled) and progress.
// - Results are identical for any thread count (parallel passes are per-row gathers; accumulation pulls its
//   donors in a fixed neighbour order).
//
// Typical use (stream-power erosion after Braun & Willett 2013):
//   FlowGrid g = FlowGrid::of(height.domain);
//   std::vector<float> z = height.data;
//   fill_depressions(g, z, FlatMode::Epsilon);          // optional: route across lakes
//   D8Flow f = d8_flow(g, z);                           // receiver, direction, donor bit masks
//   std::vector<std::int32_t> order = stack_order(g, f);  // every cell after its receiver
//   std::vector<double> area = accumulate_d8(g, f);     // upslope area in m^2 (cell itself included)
//   for (std::int32_t c : order) {                      // outlets first, upstream after: implicit solve
//     std::int32_t r = f.receiver[c]; if (r == c) continue;
//     double L = g.distance(f.direction[c]);  ... z[c] = ... z[r] ...
//   }
// References: Barnes, Lehman & Mulla 2014 "Priority-Flood: an optimal depression-filling and watershed-
// labeling algorithm"; Zhou, Sun & Fu 2016 "An efficient variant of the Priority-Flood algorithm for filling
// depressions in raster digital elevation models"; Lindsay 2016 "Efficient hybrid breaching-filling sink
// removal methods for flow path enforcement in digital elevation models"; Braun & Willett 2013 "A very
// efficient O(n), implicit and parallel method to solve the stream power equation"; O'Callaghan & Mark 1984
// (D8); Tarboton 1997 "A new method for the determination of flow directions and upslope areas in grid
// digital elevation models"; Freeman 1991 "Calculating catchment area with divergent flow based on a regular
// grid"; Holmgren 1994 "Multiple flow direction algorithms for runoff modelling in grid based elevation
// models"; Barnes 2017 "Parallel non-divergent flow accumulation for trillion cell digital elevation models".
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "graph/domain.h"

namespace orogen {
class ExecContext;
}

namespace orogen::hydrology {

inline constexpr int kDi[8] = {1, 1, 0, -1, -1, -1, 0, 1};
inline constexpr int kDj[8] = {0, 1, 1, 1, 0, -1, -1, -1};
inline constexpr std::uint8_t kNoDirection = 255;
constexpr int opposite(int k) { return (k + 4) & 7; }

struct FlowGrid {
  int nx = 0, ny = 0;
  double dx = 1.0, dy = 1.0;  // metres

  FlowGrid() = default;
  FlowGrid(int w, int h, double sx = 1.0, double sy = 1.0) : nx(w), ny(h), dx(sx), dy(sy) {}
  static FlowGrid of(const Domain& d) { return {d.width(), d.height(), std::abs(d.spacing.x), std::abs(d.spacing.y)}; }

  std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  std::int32_t index(int i, int j) const { return j * nx + i; }
  int column(std::int32_t c) const { return c % nx; }
  int row(std::int32_t c) const { return c / nx; }
  std::int32_t offset(int k) const { return kDj[k] * nx + kDi[k]; }
  double distance(int k) const { return (k & 1) ? std::hypot(dx, dy) : ((k & 2) ? dy : dx); }
  double cell_area() const { return dx * dy; }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < nx && j < ny; }
  bool on_border(int i, int j) const { return i == 0 || j == 0 || i == nx - 1 || j == ny - 1; }
};

struct Outlets {
  bool border = true;                  // border cells are outlets
  std::span<const std::uint8_t> mask;  // optional, size nx*ny: nonzero cells are outlets too
  bool is_outlet(const FlowGrid& g, int i, int j) const {
    return (border && g.on_border(i, j)) || (!mask.empty() && mask[static_cast<std::size_t>(g.index(i, j))] != 0);
  }
};

// ---- Depressions ---------------------------------------------------------------------------------------

enum class FlatMode {
  Flat,     // filled areas are exactly flat at their spill level (Priority-Flood+Flat)
  Epsilon,  // filled areas rise by float ulps away from the spill, so every cell but an outlet has a strictly
            // lower neighbour (Priority-Flood+epsilon): the least surface e with e = z at the outlets and
            // e(n) = max(z(n), min over the 8 neighbours m of nextafter(e(m), +inf)) elsewhere. That fixed point
            // is unique, so it does not depend on the order in which a flood visits ties (tiles reproduce it
            // exactly, nodes/hydrology/tile_fill.h); it equals the epsilon surface of the Flat-filled heights F
            // (z <= F <= e: where e is raised the max in its equation ignores F as it ignored z, and where it
            // is not, F = z).
};

// Raises every cell that has no descending path to an outlet to its spill level, in place. Priority-Flood
// (Barnes et al. 2014) with the depression and slope queues of Zhou et al. 2016: only cells that can be
// spill points enter the priority queue. O(n) plus O(m log m) for the m queued cells.
// `spill_level` (optional, size nx*ny) receives the flat water level of every cell: max(input, the spill
// level of its depression), the input where nothing was raised, so `spill_level > input` marks the lakes. With
// Flat it equals the result; with Epsilon it is exactly the Flat fill, from a pass of its own.
void fill_depressions(const FlowGrid& g, std::span<float> z, FlatMode mode, const Outlets& outlets = {},
                      const ExecContext* ctx = nullptr, std::span<float> spill_level = {});

// The incremental form of the epsilon surface, for pieces of a domain (the fill across tiles,
// nodes/hydrology/tile_fill.h): `e` holds upper bounds of the epsilon surface of `level` on an nx * ny grid
// (+inf where nothing is known yet; `level` at the outlets), and `seeds` the cells whose bound was just set or
// lowered. Lowers every cell to the least value its neighbours allow, e(n) = min(e(n), max(level(n),
// next_up(e(m)))), in Dijkstra order from the seeds, so each cell is final when its value is. Called with
// e = level at the outlets, +inf elsewhere, and the outlets as seeds, it gives fill_depressions(Epsilon).
void relax_epsilon(int nx, int ny, std::span<const float> level, std::span<float> e,
                   std::span<const std::int32_t> seeds);

// Carves instead of filling, in place: from every pit a channel is cut down the D8 paths of the epsilon surface
// (to the spill point and beyond) until the path is no higher than the pit (complete breaching, Lindsay 2016, on a
// tree the heights alone define: nodes/hydrology/breach_rule.h). Epsilon: the carved channel descends by one ulp
// per cell, so every cell but an outlet has a strictly lower neighbour (the epsilon fill of the result is the
// result); Flat: it is level, and every cell has a path to an outlet that never rises.
void breach_depressions(const FlowGrid& g, std::span<float> z, FlatMode mode, const Outlets& outlets = {},
                        const ExecContext* ctx = nullptr);
// Per cell: 1 for a pit of breach_depressions (no outlet, no strictly lower neighbour in `z`), else 0.
std::vector<std::uint8_t> breach_pits(const FlowGrid& g, std::span<const float> z, const Outlets& outlets = {});

// ---- D8 ------------------------------------------------------------------------------------------------

struct D8Flow {
  std::vector<std::int32_t> receiver;   // steepest-descent neighbour; receiver[c] == c for outlets and pits
  std::vector<std::uint8_t> direction;  // k of the receiver, kNoDirection for outlets and pits
  std::vector<std::uint8_t> donors;     // bit k set: neighbour k drains into this cell
};

// D8 (O'Callaghan & Mark 1984): each non-outlet cell drains to the neighbour of largest drop / distance > 0;
// ties go to the lowest k.
D8Flow d8_flow(const FlowGrid& g, std::span<const float> z, const Outlets& outlets = {},
               const ExecContext* ctx = nullptr);

// Braun & Willett 2013 stack: outlets/pits in increasing index, each followed depth-first by its upstream
// cells. Every cell appears after its receiver; iterate backwards to go downstream.
std::vector<std::int32_t> stack_order(const FlowGrid& g, const D8Flow& f);

// Basin label of every cell: outlets (receiver == self) numbered 0, 1, ... in increasing cell index; each cell
// gets its outlet's number. `order` is stack_order(g, f).
std::vector<std::int32_t> basin_labels(const D8Flow& f, std::span<const std::int32_t> order,
                                       int* basin_count = nullptr);

// Upslope amount: acc[c] = w[c] + sum of acc over its donors. `weight` per cell (e.g. runoff depth x cell
// area, m^3/s); empty means the cell area, so the result is the contributing area in m^2. Parallel
// (Barnes 2017 dependency counting), deterministic.
std::vector<double> accumulate_d8(const FlowGrid& g, const D8Flow& f, std::span<const float> weight = {},
                                  const ExecContext* ctx = nullptr);
// The number of cells draining through every cell, itself included: accumulate_d8 of unit weights, whole numbers
// (exact in double up to 2^53 cells). Times the cell area it is the contributing area as one product per cell, the
// same on any tiling (nodes/hydrology/tile_accumulation.h), where summing the areas rounds by the order of the sum.
std::vector<double> count_d8(const FlowGrid& g, const D8Flow& f, const ExecContext* ctx = nullptr);
// The contributing area in m^2 as count_d8 times the cell area, one product per cell: FlowAccumulation's D8 area,
// which the tiles reproduce exactly.
std::vector<double> d8_area(const FlowGrid& g, const D8Flow& f, const ExecContext* ctx = nullptr);

// ---- Dispersive routing --------------------------------------------------------------------------------

enum class FlowMethod { D8, DInfinity, MFD };

struct RoutingOptions {
  FlowMethod method = FlowMethod::D8;
  double exponent = 1.1;  // MFD: proportions ~ (tan beta)^exponent (Freeman 1991: 1.1; Holmgren 1994: 1..10)
  Outlets outlets;
};

// The receivers of cell (i, j) and the fraction of its flow each gets (>= 0, sum 1), written to nbr (neighbour
// k) and frac; returns their count (0 for outlets and pits). D8: the steepest neighbour; D-infinity: one or two
// neighbours of the steepest triangular facet, split by angle (Tarboton 1997); MFD: every lower neighbour.
int flow_proportions(const FlowGrid& g, std::span<const float> z, int i, int j, const RoutingOptions& opt, int nbr[8],
                     double frac[8]);

// Accumulation with any method (D8 delegates to accumulate_d8). Dependency counting, in parallel over a
// fixed set of row bands merged up a fixed tree (Barnes 2017); every cell pulls its donors' shares in neighbour
// order once they are done (nodes/hydrology/flow_shares.h), so its sum does not depend on the traversal: the same
// for any thread count, and on tiles (nodes/hydrology/tile_shares.h). Pits keep what reaches them.
std::vector<double> accumulate(const FlowGrid& g, std::span<const float> z, const RoutingOptions& opt,
                               std::span<const float> weight = {}, const ExecContext* ctx = nullptr);

// Local slope tan(beta) of the steepest descent to any neighbour, in world units (0 where no neighbour is
// lower), for wetness and stream-power terms.
std::vector<float> steepest_slope(const FlowGrid& g, std::span<const float> z, const ExecContext* ctx = nullptr);

}  // namespace orogen::hydrology
