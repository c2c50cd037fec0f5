// Perlin: the node wrapping perlin() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(Perlin) {
  b.reach_pointwise();
  declare_lattice_generator(
      b,
      "Improved Perlin gradient noise (quintic fade, 16 unit gradients at 22.5-degree steps): smooth "
      "hills, 0 at every lattice point, within [-amplitude, amplitude]. K. Perlin (2002), \"Improving "
      "noise\", SIGGRAPH.",
      "Lattice cell size: the wavelength of the dominant features", &perlin);
}

}  // namespace orogen::noise
