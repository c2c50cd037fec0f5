#pragma once
// Non-finite inputs to simulations. A simulation cannot propagate NaN or infinity the way a pointwise node
// does: one infinite rain rate makes an infinite water depth, the CFL time step 0 and simulated time stand
// still. Simulations therefore refuse a non-finite sample on an input where it has no meaning, naming the
// node, the port and the first such sample (docs/reliability.md, "Values between nodes").
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

// Throws NodeError if `field` (may be null: an unconnected input) holds a NaN or infinite sample.
inline void require_finite(const Heightfield* field, std::string_view node, std::string_view port) {
  if (!field) return;
  const int w = field->width();
  for (std::size_t k = 0; k < field->data.size(); ++k)
    if (!std::isfinite(field->data[k]))
      throw NodeError(std::string(node) + ": input '" + std::string(port) + "' holds a non-finite value (" +
                      (std::isnan(field->data[k]) ? "NaN" : "infinite") + ") at sample (" +
                      std::to_string(static_cast<int>(k % static_cast<std::size_t>(w))) + ", " +
                      std::to_string(static_cast<int>(k / static_cast<std::size_t>(w))) +
                      "); a simulation needs finite values there (clamp or replace them upstream)");
}

// The one check every simulation makes before it runs (HydraulicErosion, StreamPower, ThermalErosion,
// PipeErosion, WaterFlow): each of its heightfield inputs, by port name, terrain heights included (a NaN
// height makes every gradient around it NaN and an infinite one an infinite slope). Null entries are
// unconnected inputs.
inline void require_finite_inputs(std::string_view node,
                                  std::initializer_list<std::pair<std::string_view, const Heightfield*>> inputs) {
  for (const auto& [port, field] : inputs) require_finite(field, node, port);
}

}  // namespace orogen
