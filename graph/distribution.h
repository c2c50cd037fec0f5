#pragma once
// How a node type runs in a distributed build (`mpirun -n R orogen eval --tiles NxM`, docs/distributed.md),
// declared with its reach in the node declaration. Point-wise and local nodes, writers and domain-independent
// nodes need no declaration (per tile with halos, per tile, replicated); every node whose reach can be global
// must declare one, checked at registration (check_declaration), so the planner never meets a node it cannot
// place.
namespace orogen {

enum class Distribution {
  Undeclared,
  // Each rank computes its tiles, each expanded by the halo its reach needs (point-wise and local nodes, writers,
  // and global-reach nodes whose results are tile invariant, such as hashed scatterings).
  PerTile,
  // Per-tile partial results combined in tile order (graph/rank_group.h gather_by_tile), so the result does not
  // depend on the rank count: Normalize, auto ranges, statistics.
  Reduction,
  // Small results (vector networks, plants, rocks) computed by every rank that needs them.
  Replicated,
  // Exact across tiles by a graph of tile perimeters solved once (R. Barnes 2016, 2017): depression filling,
  // flow routing and what derives from them.
  TileGraph,
  // Explicit simulations: per tile, halos exchanged between ranks at every iteration.
  HaloExchange,
  // The whole domain on one rank, within --max-memory (the rest get its result).
  Gathered,
};

// "per-tile", "reduction", "replicated", "tile-graph", "halo-exchange", "gathered", "undeclared".
const char* to_string(Distribution kind);
// Whether the distributed build runs the kind as described yet. The others are, for now, computed on the whole
// domain by every rank that needs them and cut into its tiles: exact, but at the whole domain's memory per rank
// (the tiled build's --global-nodes whole).
bool runs_across_ranks(Distribution kind);
// One sentence for the node reference: how the kind runs and what it costs in communication.
const char* describe(Distribution kind);

}  // namespace orogen
