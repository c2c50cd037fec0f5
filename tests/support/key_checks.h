#pragma once
// Cache-key checks for node tests (the Gaffer idea: every input must change the hash, nothing else may).
//
//   expect_every_param_changes_key("Perlin", domain);
//   expect_every_input_changes_key("Add", domain);
//
// Failures are reported through GoogleTest with the type, parameter or input and the values tried. The checks
// are the node contracts of testing/contracts.h (shared with `orogen test-node` and node libraries' kit).
#include <string>

#include "graph/domain.h"

namespace orogen::test {

// For each parameter: a changed valid value (every component of vectors and colours, every other enum choice)
// changes the node's key and setting it back restores it. A changed domain changes the key unless the type is
// domain_independent. Renaming the node, moving it in the editor or adding unrelated nodes does not.
void expect_every_param_changes_key(const std::string& type_name, const Domain& d);

// For each input port: connecting a different upstream changes the key, reconnecting the original restores
// it, and disconnecting an optional input changes it.
void expect_every_input_changes_key(const std::string& type_name, const Domain& d);

}  // namespace orogen::test

namespace orogen {
using test::expect_every_input_changes_key;
using test::expect_every_param_changes_key;
}  // namespace orogen
