#pragma once
// Ports and parameters every noise generator node shares, declared once so they read the same everywhere.
#include <memory>

#include "graph/exec_context.h"
#include "graph/node_type.h"
#include "nodes/noise/lattice_noise.h"
#include "nodes/noise/noise_field.h"

namespace orogen::noise {

// Optional inputs warp_x and warp_y (metres).
void declare_warp_inputs(NodeBuilder& b);
// feature_size (m) with the given default.
void declare_feature_size(NodeBuilder& b, double default_metres, const char* description);
// amplitude (m) with the given default.
void declare_amplitude(NodeBuilder& b, double default_metres, const char* description);
// seed
void declare_seed(NodeBuilder& b);

// The raster inputs of a generator brought onto its requested domain (the rule of
// nodes/common/match_domain.h), owned here and lent to the noise functions by view().
struct GeneratorInputs {
  HeightfieldPtr warp_x, warp_y, roughness, amplitude;  // null where unconnected
  NoiseInputs view() const { return {warp_x.get(), warp_y.get(), roughness.get(), amplitude.get()}; }
};

// The warp fields connected to the node, on its domain.
GeneratorInputs warp_inputs(const ExecContext& ctx);

// The whole declaration of a lattice generator (Perlin, Simplex, Value, White): warp inputs, the "out"
// field, feature_size, amplitude and seed, executed by `generate`.
using LatticeGenerator = Heightfield (*)(const Domain&, const LatticeNoiseParams&, const NoiseInputs&,
                                         const ExecContext*);
void declare_lattice_generator(NodeBuilder& b, const char* description, const char* feature_size_description,
                               LatticeGenerator generate);

inline void set_field_output(ExecContext& ctx, Heightfield&& field) {
  ctx.set_output("out", std::make_shared<Heightfield>(std::move(field)));
}

}  // namespace orogen::noise
