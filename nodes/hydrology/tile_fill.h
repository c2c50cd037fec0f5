#pragma once
// Depression filling across tiles, exact (R. Barnes 2016, "Parallel priority-flood depression filling for
// trillion cell digital elevation models", Computers & Geosciences 96): the building block of FillDepressions'
// tile-graph distribution (graph/distribution.h, docs/distributed.md).
//
//  1. Each tile floods itself from its own perimeter (flood_tile): every perimeter cell seeds a watershed label,
//     every cell gets the level it fills to if the tile's perimeter were the outlet, and where two watersheds
//     meet the spill edge between their labels records the level water crosses at (the lower of the two cells'
//     levels raised to the higher). What leaves the tile is its TileSpillGraph: the perimeter heights and the
//     spill edges, O(perimeter) in size, never the tile.
//  2. The spill graphs of all tiles are solved once (solve_spill_graphs): a tile's perimeter cells that are the
//     domain's border drain at their own height; a sample shared by neighbouring tiles (tiles share their border
//     samples, cli/tiling.h) joins their labels at its height; the spill level of every label is the lowest level
//     over all paths to the border of the highest edge on the path (a minimax Dijkstra from the border).
//  3. Each tile raises every cell to max(its own level, its label's spill level) (apply_spill_levels).
//
// In Flat mode the result is the whole-domain Priority-Flood's bit for bit (both are the minimax level over
// paths to the border; no arithmetic happens on the heights), for any tiling. Every 8-neighbour pair of cells
// lies inside one tile because tiles share their borders, so no link crosses between tiles but shared samples.
// Heights must be finite.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::hydrology {

// A tile of a domain: its first sample and sample counts in the domain.
struct TileRect {
  glm::ivec2 first{0, 0};
  glm::ivec2 size{1, 1};
};

struct SpillEdge {
  std::int32_t a = 0, b = 0;  // labels: indices of perimeter cells of the tile (perimeter order), or the
                              // perimeter's size for the tile's drained cells (flood_tile)
  float level = 0.0f;
};

// What a tile sends to the solve.
struct TileSpillGraph {
  TileRect rect;
  std::vector<float> perimeter;  // heights of the tile's perimeter cells, in perimeter order
  std::vector<SpillEdge> edges;  // between labels, at most one per pair (the lowest)
};

// The tile's perimeter cells (i == 0, j == 0, i == w-1 or j == h-1), as tile cell indices in row-major order:
// the perimeter order that labels refer to.
std::vector<std::int32_t> perimeter_cells(glm::ivec2 size);
// Per tile cell: its index in perimeter order, or -1.
std::vector<std::int32_t> perimeter_index(glm::ivec2 size);
// The index in perimeter order of cell (i, j) of a tile of `size` samples, or -1: perimeter_index without the array.
inline std::int32_t perimeter_position(glm::ivec2 size, int i, int j) {
  const int side = size.x > 1 ? 2 : 1;  // perimeter cells in a row between the first and the last
  if (j == 0) return i;
  if (j == size.y - 1) return size.x + (size.y - 2) * side + i;
  if (i == 0) return size.x + (j - 1) * side;
  if (i == size.x - 1) return size.x + (j - 1) * side + 1;
  return -1;
}
// The index in the domain (row-major, `domain_size` samples) of tile cell `c` (row-major in the tile).
std::int64_t domain_sample(const TileRect& rect, glm::ivec2 domain_size, std::int32_t c);

// A tile's rectangle at the front of a message, and back (every tile-graph message of the hydrology tiles starts
// with it). take_tile_rect throws std::invalid_argument, naming `what`, on truncated bytes or a rectangle outside a
// domain of `domain_size` samples.
void put_tile_rect(std::string& out, const TileRect& rect);
TileRect take_tile_rect(std::string_view& in, glm::ivec2 domain_size, const char* what);

struct TileFlood {
  std::vector<float> level;         // per tile cell: filled with the tile's perimeter as the outlet
  std::vector<std::int32_t> label;  // per tile cell: the perimeter cell it floods from
  TileSpillGraph graph;
};

// Phase 1: `z` holds the tile's heights (rect.size, row-major). `drained` (optional, one byte per cell) marks cells
// known to keep their height in the fill (a strictly descending path leads them to the domain's border, as every cell
// outside a pit basin): the flood starts from those next to the others, at their own height, as one more label whose
// spill level is -inf (edges to it name label perimeter.size()), never crosses them, and leaves them as they are. The
// flood's work is then that of the other cells. Without `drained` every cell is flooded.
TileFlood flood_tile(std::span<const float> z, const TileRect& rect, std::span<const std::uint8_t> drained = {});

// Phase 2: the spill level of every perimeter cell of every tile (indexed like `tiles`, then perimeter order), for
// a domain of `domain_size` samples that the tiles cover. Throws std::invalid_argument if a tile lies outside the
// domain or the tiles' shared samples disagree in height.
std::vector<std::vector<float>> solve_spill_graphs(const std::vector<TileSpillGraph>& tiles, glm::ivec2 domain_size);

// Phase 3: the filled heights of the tile, row-major.
std::vector<float> apply_spill_levels(const TileFlood& flood, std::span<const float> spill_levels);

// ---- Values that only fall, across tiles ------------------------------------------------------------------
// What the epsilon surface below and the breach of carved depressions (nodes/hydrology/tile_breach.h) exchange in
// rounds: per-cell values that only ever fall, of which a sample shared by several tiles must end with the lowest
// any tile found. Each message carries the tile's perimeter values that fell since its last message (the first:
// every finite one); the solve (solve_perimeter_minima) gives every tile, for each of its perimeter samples some
// tile reported, the lowest value reported; the rounds end when no message carries a value (perimeter_minima_fell).
class PerimeterMinima {
 public:
  explicit PerimeterMinima(const TileRect& rect);
  // The message for `values` (the tile's cells, rect.size row-major).
  std::string message(std::span<const float> values);
  // Takes an answer into `values`: returns the perimeter cells (tile cell indices) whose value fell.
  std::vector<std::int32_t> answer(std::string_view bytes, std::span<float> values);
  // The tile's perimeter cells (perimeter_cells).
  const std::vector<std::int32_t>& perimeter() const { return perimeter_; }

 private:
  TileRect rect_;
  std::vector<std::int32_t> perimeter_;
  std::vector<float> sent_;  // per perimeter cell: the lowest value sent or received
};

// Every tile's message of a round (indexed by tile) into every tile's answer. Throws std::invalid_argument on
// malformed messages.
std::vector<std::string> solve_perimeter_minima(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// Whether any of a round's messages lowered a value (else the values are final and the rounds end).
bool perimeter_minima_fell(std::span<const std::string_view> messages);

// ---- Epsilon surface across tiles -------------------------------------------------------------------------
// FlatMode::Epsilon's surface (nodes/hydrology/flow_routing.h) is the least fixed point of e(n) = max(level(n),
// min over 8-neighbours m of next_up(e(m))) with e = level on the domain's border, and it is the same for the
// heights and for their Flat fill. So after the spill graphs (the Flat levels, exact on every tile) each tile
// relaxes the epsilon surface of its levels from what it knows (relax_epsilon): the domain's border cells it
// holds, then the perimeter values other tiles found. Rounds exchange the perimeter values that fell: a sample
// shared by several tiles takes the lowest of their values, and a tile relaxes again from the perimeter cells
// whose value fell. Every value is a path's cost, so none falls below the fixed point, and when a round lowers
// nothing anywhere the values satisfy the equation on every cell (every 8-neighbour pair lies in one tile), so
// they are the fixed point: the single-process fill's surface bit for bit, for any tiling. Values only fall,
// so the rounds end; their number grows with how many tiles the longest filled flat crosses.
class TileEpsilon {
 public:
  // `level`: the tile's Flat-filled heights (rect.size, row-major). `drained` (optional): as flood_tile's, cells
  // final at their level, relaxed from where they meet the others.
  TileEpsilon(std::vector<float> level, const TileRect& rect, glm::ivec2 domain_size,
              std::span<const std::uint8_t> drained = {});
  // The perimeter values that fell since the last message (PerimeterMinima).
  std::string message() { return minima_.message(e_); }
  // The lowest values of this tile's shared samples (solve_perimeter_minima); relaxes from those that fell.
  void answer(std::string_view bytes);
  // The epsilon surface on the tile once no round lowers anything (+inf where nothing reached yet).
  const std::vector<float>& surface() const { return e_; }

 private:
  TileRect rect_;
  std::vector<float> level_, e_;
  PerimeterMinima minima_;
};

// The spill round's solve on the tiles' encoded spill graphs (decode_spill_graph): each tile's levels as its answer.
std::vector<std::string> solve_spill_messages(std::span<const std::string_view> messages, glm::ivec2 domain_size);

// A spill graph as bytes and back (what ranks exchange; graph/rank_group.h). decode throws std::invalid_argument
// on malformed bytes.
std::string encode(const TileSpillGraph& graph);
TileSpillGraph decode_spill_graph(std::string_view bytes);

}  // namespace orogen::hydrology
