#pragma once
// The contracts every node type passes, as plain checks: Orogen's registry-wide tests, `orogen test-node` and
// the testing kit for node libraries (<orogen/testing.h>) all run these, so there is one implementation.
// Each check returns what is wrong, one message per problem, naming the node, the parameter or port and the
// cause; no GoogleTest here (the CLI runs them too).
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/output_path.h"
#include "graph/param_value.h"
#include "graph/port_value.h"

namespace orogen::contracts {

enum class Status { Passed, Failed, Skipped };

struct ContractResult {
  std::string contract;  // "declaration", "cache key", "reach", "threads", "extremes"
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

// The extremes contract: the node at each end of every parameter's hard range (one at a time, the others at
// their defaults; every enum choice, both booleans, the largest seed) and with fields of NaN, infinities and
// +-3e38 as inputs, on small odd domains. Each run must end in one of:
//   - a result, all finite (fields and images) wherever every input was finite;
//   - a NodeError with a message (refusing a value: name the parameter);
//   - Cancelled: a run still going after run_seconds is cancelled and must return within cancel_bound (a late
//     run is repeated once before it counts: a busy machine can delay one return).
// A std::exception that is not a NodeError (std::runtime_error, std::bad_alloc, std::out_of_range ...), a
// non-std exception, NaN or infinity from finite inputs, or ignoring the cancel fails. A node that keeps
// running long after the cancel is left running and the sweep stops, so the table is still printed; a crash
// ends the process (the caller's exit status shows it).
struct ExtremesDomain {
  std::string name;
  Domain domain;
  bool parameter_extremes = true;  // run the parameter sweep here too, not only defaults and non-finite inputs
};
// A 23 x 7 non-square domain, a 17 x 17 one of 2 micrometre spacing (parameter sweeps on both), 17 x 17 at
// coordinates of 9e11 m and a 2 x 2 one.
std::vector<ExtremesDomain> extremes_domains();
struct ExtremesOptions {
  std::vector<ExtremesDomain> domains;  // empty: extremes_domains()
  double run_seconds = 0.25;            // a run is cancelled after this long
  double cancel_bound = 1.0;            // seconds from the cancel to the return
  double budget_seconds = 3.0;          // the sweep stops (and says so) after this long
  // Values for input port types the kit cannot generate (points, meshes, scenes ...), on a domain.
  std::function<std::map<PortType, PortValue>(const Domain&)> inputs;
  OutputPolicy output;  // writers: the default "out" means a scratch folder, removed afterwards
};
// The values of a parameter the sweep tries, each with a label ("min", "max", an enum choice ...); only
// values the parameter accepts.
std::vector<std::pair<std::string, ParamValue>> extreme_values(const ParamDecl& p);
ContractResult check_extremes(const NodeType& type, const ExtremesOptions& options = {});
// Runs the extremes contract left running (ignoring their cancel) that have not returned yet. A program must
// not run its static destructors under them: `orogen test-node` ends with std::_Exit when this is not 0.
int runs_left_running();

// Every contract above on every case, on small domains (a second or so per node type; the extremes sweep at
// most ExtremesOptions::budget_seconds more).
// Which contracts check_node_contracts runs (a caller that runs some of them itself, with its own bounds or
// wider sweeps, leaves them out).
enum ContractSet : unsigned {
  kDeclarationContract = 1u << 0,
  kCacheKeyContract = 1u << 1,
  kReachContract = 1u << 2,
  kThreadsContract = 1u << 3,
  kExtremesContract = 1u << 4,
  kAllContracts = (1u << 5) - 1,
};
std::vector<ContractResult> check_node_contracts(const NodeType& type, unsigned contracts = kAllContracts);

}  // namespace orogen::contracts
