// Value: the node wrapping value_noise() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(Value) {
  b.reach_pointwise();
  declare_lattice_generator(
      b,
      "Value noise: random heights in [-1, 1] at lattice points blended with a quintic fade, times "
      "amplitude.",
      "Lattice cell size: the wavelength of the dominant features", &value_noise);
}

}  // namespace orogen::noise
