#pragma once
// What the placement nodes (PoissonDisk, ForestLifeCycle) share around their library call: library errors
// become node errors, and the points take their z from an optional height input.
#include <cmath>
#include <stdexcept>
#include <utility>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/points.h"

namespace orogen::scatter {

// Runs `place` (returning Points) and sets each point's z to the height under it (0 outside the field) when
// `height` is given.
template <class Place>
PointsPtr run_placement(Place&& place, const Heightfield* height) {
  auto out = std::make_shared<Points>();
  try {
    *out = std::forward<Place>(place)();
  } catch (const std::invalid_argument& e) {
    throw NodeError(e.what());
  } catch (const std::runtime_error& e) {
    throw NodeError(e.what());
  }
  if (height)
    for (auto& q : out->position) {
      const float z = height->sample_world(q.x, q.y);
      q.z = std::isfinite(z) ? z : 0.0f;
    }
  return out;
}

}  // namespace orogen::scatter
