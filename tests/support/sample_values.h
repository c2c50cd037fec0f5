#pragma once
// A value of every port type a registered node can make from a field, for registry-wide tests (extremes,
// cancellation, writers): generic, so whatever node types produce images, meshes, points ... today or later
// are used.
#include <map>

#include "graph/exec_context.h"
#include "graph/port_value.h"

namespace orogen::test {

// Starts from `field` (the heightfield value) and runs every non-writing node type with default parameters on
// the values made so far, keeping the first value of each port type; three passes reach chains (points ->
// scene). Nodes that fail are skipped.
std::map<PortType, PortValue> sample_values(const HeightfieldPtr& field, const OutputPolicy& policy);

}  // namespace orogen::test
