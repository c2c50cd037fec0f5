#pragma once
// Components of several tiles joined into whole-domain components through the samples the tiles share (tiles share
// their border samples, cli/tiling.h, so every 8-neighbour pair lies in one tile and a component crosses a border
// only through a shared sample): the lakes of FillDepressions and Lakes (nodes/hydrology/tile_lakes.cpp), the
// flood of FloodFill (nodes/hydrology/flood_fill_across_tiles.cpp) and the depressions of DrainageMetrics
// (nodes/hydrology/drainage_across_tiles.cpp) across tiles.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

// Union-find with the lowest index as the root, so roots do not depend on the order of the joins.
struct LowestRootUnionFind {
  std::vector<std::int32_t> parent;

  explicit LowestRootUnionFind(std::size_t n = 0) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::int32_t add() {
    parent.push_back(static_cast<std::int32_t>(parent.size()));
    return parent.back();
  }
  std::int32_t root(std::int32_t a) {
    while (parent[static_cast<std::size_t>(a)] != a) {
      auto& up = parent[static_cast<std::size_t>(a)];
      up = parent[static_cast<std::size_t>(up)];  // path halving
      a = up;
    }
    return a;
  }
  void join(std::int32_t a, std::int32_t b) {
    a = root(a), b = root(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

// Joins the nodes tiles give the samples they share. `node_of(t, p)`: the node of tile t's perimeter cell p
// (perimeter_cells order), or -1 where it has none (e.g. dry ground); called once per cell, tile by tile. Throws
// std::invalid_argument(`disagreement`) when two tiles disagree whether a shared sample has a node.
template <class NodeOf>
void join_perimeter_components(LowestRootUnionFind& joined, std::span<const TileRect> rects, glm::ivec2 whole,
                               NodeOf&& node_of, const char* disagreement) {
  std::unordered_map<std::int64_t, std::int32_t> shared;  // sample -> the first tile's node there, or -1
  for (std::size_t t = 0; t < rects.size(); ++t) {
    const auto cells = perimeter_cells(rects[t].size);
    for (std::size_t p = 0; p < cells.size(); ++p) {
      const std::int32_t node = node_of(t, p);
      const auto [it, fresh] = shared.try_emplace(domain_sample(rects[t], whole, cells[p]), node);
      if (fresh) continue;
      if ((it->second < 0) != (node < 0)) throw std::invalid_argument(disagreement);
      if (node >= 0) joined.join(it->second, node);
    }
  }
}

// The common case: each tile (a `rect` and a `perimeter`) numbers its components 1..count, perimeter[p] is the number
// at its perimeter cell p (0: none), and the joined nodes are offset[t] + number - 1 (offset[t]: the components of the
// tiles before t, offset.back() of them in all). Returns their union-find.
template <class Tile>
LowestRootUnionFind join_numbered_components(const std::vector<Tile>& tiles, glm::ivec2 whole,
                                             std::span<const std::int32_t> offset, const char* disagreement) {
  LowestRootUnionFind joined(static_cast<std::size_t>(offset.back()));
  std::vector<TileRect> rects;
  for (const Tile& t : tiles) rects.push_back(t.rect);
  join_perimeter_components(
      joined, rects, whole,
      [&](std::size_t t, std::size_t p) {
        const std::int32_t k = tiles[t].perimeter[p];
        return k ? offset[t] + k - 1 : -1;
      },
      disagreement);
  return joined;
}

}  // namespace orogen::hydrology
