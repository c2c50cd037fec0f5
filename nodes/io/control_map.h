#pragma once
// Splat weights as the control map of Terrain3D, the main terrain system of Godot 4 (Tokisan Games, format of
// its 0.9 and later releases, documented in its "Control Map Format"): one 32-bit unsigned integer per sample,
// stored in a 32-bit float image with its bits unchanged, holding a base texture id (bits 31..27), an overlay
// texture id (26..22), the overlay's blend 0..255 over the base (21..14), and flags: hole (bit 2), navigation
// (bit 1), autoshader (bit 0).
#include <cstdint>

#include "graph/image.h"

namespace orogen {

inline constexpr int kControlMapMaxLayers = 32;  // texture ids are 5 bits

struct ControlMapFlags {
  bool navigation = false;
  bool autoshader = false;
};

// One control word from its fields (ids 0..31 and blend 0..255, masked to their widths).
constexpr std::uint32_t encode_control(unsigned base, unsigned overlay, unsigned blend, bool hole, bool navigation,
                                       bool autoshader) {
  return (base & 0x1Fu) << 27 | (overlay & 0x1Fu) << 22 | (blend & 0xFFu) << 14 | (hole ? 1u : 0u) << 2 |
         (navigation ? 1u : 0u) << 1 | (autoshader ? 1u : 0u);
}

// The control word of each sample of `weights` (one channel per layer, layer c is texture id c): the base is
// the layer of largest weight, the overlay the second largest (ties to the lower layer; the base itself when
// no other layer has weight), and the blend the overlay's share of the two, round(255 * w_overlay / (w_base +
// w_overlay)), so 0..128. A sample with no weight is base 0, overlay 0, blend 0. Throws std::invalid_argument
// for more than 32 layers or a negative or non-finite weight (naming the layer and sample).
std::vector<std::uint32_t> control_words(const Image& weights, const ControlMapFlags& flags);

// The words as a one-channel float image ("R") whose floats carry the words' bits, as Terrain3D reads it.
Image control_map_image(const Domain& domain, const std::vector<std::uint32_t>& words);

}  // namespace orogen
