#pragma once
// The contracts every node type passes, as plain checks: Orogen's registry-wide tests, `orogen test-node` and
// the testing kit for node libraries (<orogen/testing.h>) all run these, so there is one implementation.
// Each check returns what is wrong, one message per problem, naming the node, the parameter or port and the
// cause; no GoogleTest here (the CLI runs them too).
#include <map>
#include <string>
#include <vector>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/param_value.h"
#include "graph/port_value.h"

namespace orogen::contracts {

enum class Status { Passed, Failed, Skipped };

struct ContractResult {
  std::string contract;  // "declaration", "cache key", "reach", "threads"
  Status status = Status::Passed;
  std::vector<std::string> failures;  // each names the cause
  std::string note;                   // what was checked, or why it was skipped
};

// Descriptions of the node, its ports and parameters; a unit (graph/units.h) on every number parameter
// (Unit::Unitless, Unit::InputUnits ... where no physical one holds); a hard range on every number; a soft
// range inside it; a declared reach.
ContractResult check_declaration_contract(const NodeType& type);

// For each parameter, a changed valid value (every component of vectors and colors, every other enum choice)
// changes the node's cache key and setting it back restores it; a changed domain changes the key unless the
// type is domain_independent; the node's id, its editor position and unrelated nodes do not.
std::vector<std::string> param_key_failures(const NodeType& type, const Domain& d);
// For each input: another upstream node, or a parameter change upstream, changes the key; reconnecting the
// original restores it; disconnecting an optional input changes it.
std::vector<std::string> input_key_failures(const NodeType& type, const Domain& d);
// What the key leaves out does not change the result: a domain_independent node gives the same outputs on
// another domain (else a result of one domain is served from the cache for another).
std::vector<std::string> key_coverage_failures(const NodeType& type, const Domain& d);
ContractResult check_cache_key(const NodeType& type, const Domain& d);

// Parameters for one run of a contract: the defaults, or the defaults with some set.
struct ParamCase {
  std::map<std::string, ParamValue> params;
  std::string label;
};
// The defaults and every other choice of each enum parameter.
std::vector<ParamCase> param_cases(const NodeType& type);

// A generated input for `port` on `d`: fields of smooth terrain plus per-sample detail hashed from the global
// lattice index (so a halo that is too small shows), 12-channel images, curves in fixed world coordinates, a
// polygon map from VoronoiIsland when it is registered. Null for a port type it cannot make.
PortValue contract_input(const PortDecl& port, const Domain& d);

// The tile contract for one case: a non-global node evaluated on a sub-domain expanded by its declared halo
// reproduces the full-domain result inside the sub-domain bit for bit. Skipped for global reach.
ContractResult check_reach(const NodeType& type, const ParamCase& c);
// The same outputs, bit for bit, with one worker thread and with `threads`.
ContractResult check_threads(const NodeType& type, const ParamCase& c, const Domain& d, int threads);

// Every contract above on every case, on small domains (a second or so per node type).
std::vector<ContractResult> check_node_contracts(const NodeType& type);

}  // namespace orogen::contracts
