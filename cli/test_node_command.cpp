// `orogen test-node TYPE`: the contracts every node passes (testing/contracts.h), on any registered type,
// built in or from a node library, as a pass/fail table with the cause of every failure.
#include <cstdlib>
#include <iostream>

#include "cli/commands.h"
#include "graph/registry.h"
#include "testing/contracts.h"

namespace orogen::cli {
namespace {

const char* status_text(contracts::Status s) {
  switch (s) {
    case contracts::Status::Passed:
      return "pass";
    case contracts::Status::Failed:
      return "FAIL";
    case contracts::Status::Skipped:
      return "skip";
  }
  return "?";
}

}  // namespace

int run_test_node(const std::vector<std::string>& types) {
  bool failed = false;
  for (const auto& name : types) {
    const NodeType* t = NodeRegistry::instance().find(name);
    if (!t) {
      const auto hint = NodeRegistry::instance().closest(name);
      std::cerr << "error: unknown node type '" << name << "'"
                << (hint.empty() ? "" : " (did you mean '" + hint + "'?)") << "\n";
      return kExitInvalid;
    }
    std::cout << t->name << (t->library.empty() ? "" : " (node library '" + t->library + "')") << "\n";
    for (const auto& r : contracts::check_node_contracts(*t)) {
      std::cout << "  " << status_text(r.status) << "  " << r.contract
                << std::string(r.contract.size() < 12 ? 12 - r.contract.size() : 1, ' ') << r.note << "\n";
      for (const auto& f : r.failures) std::cout << "        - " << f << "\n";
      failed = failed || r.status == contracts::Status::Failed;
    }
  }
  const int code = failed ? kExitEvalFailed : kExitOk;
  if (contracts::runs_left_running() > 0) {
    // A node that ignored its cancel is still running on a detached thread: the table is printed, so leave
    // without the static destructors it could run into (the registry, TBB).
    std::cout.flush();
    std::cerr.flush();
    std::_Exit(code);
  }
  return code;
}

}  // namespace orogen::cli
