// White: the node wrapping white_noise() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(White) {
  b.reach_pointwise();
  declare_lattice_generator(
      b,
      "White (cell) noise: one independent random value in [-1, 1] per square cell of side "
      "feature_size, times amplitude. With feature_size at or below the sample spacing it is per-sample "
      "white noise that stays the same noise at any resolution.",
      "Side of the square cells that each get one random value", &white_noise);
}

}  // namespace orogen::noise
