#pragma once
// KMeansClusters across the tiles of a tiled or distributed build (graph/tile_graph.h, docs/distributed.md): every
// tile assigns its own cells, the tallies of all tiles (counts and exact feature sums, nodes/climate/kmeans_steps.h)
// add up to the whole domain's in any order, and every tile takes the same new centres. Exact: the labels, colors
// and report equal the whole-domain node's bit for bit on any tiling. With init diagonal only (k-means++ picks its
// centres by a running sum over the whole domain in row order, so that node stays on the whole domain).
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/climate/kmeans.h"

namespace orogen::climate {

// The algorithm for parameters `p` (init diagonal; p.weights is ignored: the tiles take the channel weights from
// their image's channel names and `group`, the node's five weights in group_weights order) on the whole domain.
struct KMeansGroupWeights {
  double slope = 1, temperature = 1, illumination = 1, humidity = 0.1, other = 1;
};
std::unique_ptr<TileGraphAlgorithm> kmeans_across_tiles(const KMeansParams& p, const KMeansGroupWeights& group,
                                                        const Domain& whole);

}  // namespace orogen::climate
