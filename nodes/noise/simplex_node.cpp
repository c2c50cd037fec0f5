// Simplex: the node wrapping simplex() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(Simplex) {
  b.reach_pointwise();
  declare_lattice_generator(
      b,
      "2D simplex noise (skew F2 = (sqrt3-1)/2, unskew G2 = (3-sqrt3)/6, corner radius sqrt(1/2)): "
      "smooth noise with fewer axis-aligned artifacts than Perlin, within [-amplitude, amplitude]. K. Perlin "
      "(2001), \"Noise hardware\", SIGGRAPH course notes; S. Gustavson (2005), \"Simplex noise demystified\".",
      "Lattice cell size: the wavelength of the dominant features", &simplex);
}

}  // namespace orogen::noise
