#pragma once
// Runs one node type directly, without a graph or cache: the third front door, for unit tests of single
// nodes and for library use.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "graph/cancel.h"
#include "graph/domain.h"
#include "graph/output_path.h"
#include "graph/param_value.h"
#include "graph/port_value.h"

namespace orogen {

struct NodeRun {
  std::vector<PortValue> outputs;  // by output index
  template <class T>
  std::shared_ptr<const T> get(std::size_t index = 0) const {
    return std::get<std::shared_ptr<const T>>(outputs.at(index));
  }
};

// Params not given take their defaults; params are checked like in a graph (GraphError on a bad value).
// Throws NodeError if the node fails (or leaves an output unset), Cancelled if it was cancelled,
// std::logic_error for unknown names. `on_progress` receives the node's progress reports (fractions in [0, 1]).
NodeRun run_node(const std::string& type_name, const Domain& domain,
                 const std::map<std::string, ParamValue>& params = {},
                 const std::map<std::string, PortValue>& inputs = {}, const OutputPolicy& output = {},
                 const CancelToken* cancel = nullptr, std::function<void(double)> on_progress = {});

// run_node as the evaluator runs a node of which only `outputs` are used (ExecContext::output_requested): those
// must be set, the others may be left unset (monostate). Throws std::logic_error for an unknown output name.
NodeRun run_node_for_outputs(const std::vector<std::string>& outputs, const std::string& type_name,
                             const Domain& domain, const std::map<std::string, ParamValue>& params = {},
                             const std::map<std::string, PortValue>& inputs = {});

}  // namespace orogen
