#pragma once
// Requests and result lookups that the evaluator tests share: a request for some nodes on a domain, a node's
// status, and a Heightfield output by node and port.
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "evaluator/evaluator.h"

namespace orogen::test {

// The 16 x 16 samples over 100 m that the evaluator tests evaluate on.
inline const Domain kEvalDomain = Domain::from_extent({0.0, 0.0}, {100.0, 100.0}, {16, 16});

inline EvalRequest request(std::vector<std::string> nodes, const Domain& d = kEvalDomain) {
  EvalRequest r;
  r.domain = d;
  r.nodes = std::move(nodes);
  return r;
}

// Pending when the result has no report of the node.
inline NodeStatus status(const EvalResult& r, const std::string& id) {
  const auto it = r.nodes.find(id);
  return it == r.nodes.end() ? NodeStatus::Pending : it->second.status;
}

// Null when the output is unset or not a Heightfield.
inline HeightfieldPtr field(const EvalResult& r, const Graph& g, const std::string& id,
                            const std::string& port = "out") {
  const auto v = r.output(id, port, g);
  const auto* p = std::get_if<HeightfieldPtr>(&v);
  return p ? *p : nullptr;
}

}  // namespace orogen::test
