#pragma once
// Helpers shared by the landform primitives (nodes/landform): the seeded noise some of them perturb their
// shape with, and the checks of their parameters. Every landform is a function of the world position only,
// so a tile evaluated alone equals the same samples of a larger domain bit for bit.
#include <cstdint>
#include <string>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen::landform {

// Seeded fractal Perlin noise on `domain`, unit amplitude: fBm (about [-1, 1]) or Musgrave's ridged
// multifractal ([0, 1]) with `octaves` octaves, lacunarity 2 and gain 0.5 (nodes/noise/fbm.h).
Heightfield unit_noise(const Domain& domain, double feature_size, int octaves, bool ridged, std::uint64_t seed,
                       const ExecContext* ctx);
// The same noise at one world position (the scalar reference of unit_noise).
double unit_noise_at(double x, double y, double feature_size, int octaves, bool ridged, std::uint64_t seed);

// Throws NodeError "<node>: <param> (<value> m) must be <relation>" unless `ok`.
void require(bool ok, const std::string& node, const std::string& message);

// A number as the messages show it (%g).
std::string num(double v);

}  // namespace orogen::landform
