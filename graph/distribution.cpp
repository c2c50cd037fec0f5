#include "graph/distribution.h"

namespace orogen {

const char* to_string(Distribution kind) {
  switch (kind) {
    case Distribution::PerTile:
      return "per-tile";
    case Distribution::Reduction:
      return "reduction";
    case Distribution::Replicated:
      return "replicated";
    case Distribution::TileGraph:
      return "tile-graph";
    case Distribution::HaloExchange:
      return "halo-exchange";
    case Distribution::Gathered:
      return "gathered";
    case Distribution::Undeclared:
      break;
  }
  return "undeclared";
}

bool runs_across_ranks(Distribution kind) { return kind == Distribution::PerTile || kind == Distribution::Replicated; }

const char* describe(Distribution kind) {
  switch (kind) {
    case Distribution::PerTile:
      return "each rank computes its own tiles with the halo of the reach; no communication";
    case Distribution::Reduction:
      return "per-tile partial results combined in tile order, the same for any rank count; one small "
             "all-gather";
    case Distribution::Replicated:
      return "a small result computed by every rank that needs it; no communication";
    case Distribution::TileGraph:
      return "exact across tiles through a graph of tile perimeters solved once (Barnes 2016, 2017); "
             "perimeters travel, not tiles";
    case Distribution::HaloExchange:
      return "an explicit simulation run per tile, halos exchanged between ranks every iteration (or every k "
             "iterations with a k times wider halo)";
    case Distribution::Gathered:
      return "the whole domain on one rank, within --max-memory";
    case Distribution::Undeclared:
      break;
  }
  return "undeclared: cannot run distributed";
}

}  // namespace orogen
