#pragma once
// The testing kit for node libraries, for GoogleTest: build inputs, run one node on a domain, read its
// outputs, and check it against the contracts every Orogen node passes (the same checks as Orogen's own
// registry-wide tests and `orogen test-node`: testing/contracts.h).
//
//   #include <orogen/testing.h>
//   TEST(Canyon, Contracts) { orogen::kit::expect_node_contracts("Canyon"); }
//   TEST(Canyon, CutsDown) {
//     const auto d = orogen::kit::domain(1000.0, 65);
//     const auto out = orogen::kit::run("Canyon", d, {{"depth", 50.0}}, {{"in", orogen::kit::field(d, 100.0)}});
//     EXPECT_LE(orogen::kit::output_field(out)->at(32, 32), 100.0f);
//   }
//
// Link the test program with Orogen::testing and GTest::gtest_main, and compile the node sources into it.
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "orogen/node.h"
#include "testing/contracts.h"

namespace orogen::kit {

// A square domain of `size` metres with `samples` samples along each side, its first sample at `origin`.
inline Domain domain(double size, int samples, glm::dvec2 origin = {0.0, 0.0}) {
  return Domain::from_extent(origin, {size, size}, {samples, samples});
}

// A field on `d` with f(x, y) at each sample's world position (metres).
inline PortValue field(const Domain& d, const std::function<double(double x, double y)>& f) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(f(d.x(i), d.y(j)));
  return PortValue(HeightfieldPtr(h));
}
inline PortValue field(const Domain& d, double value) {
  return field(d, [value](double, double) { return value; });
}

// The kit's generated input for a port (what the contracts feed a node): terrain-like heights with detail.
inline PortValue generated_input(const NodeType& type, const std::string& port, const Domain& d) {
  const PortDecl* p = type.find_input(port);
  if (!p) throw std::logic_error(type.name + " has no input '" + port + "'");
  return contracts::contract_input(*p, d);
}

// Runs one node (run_node): parameters not given take their defaults.
inline NodeRun run(const std::string& type, const Domain& d, const std::map<std::string, ParamValue>& params = {},
                   const std::map<std::string, PortValue>& inputs = {}) {
  return run_node(type, d, params, inputs);
}

// Output `index` of a run as a field (throws std::bad_variant_access if it is not one).
inline HeightfieldPtr output_field(const NodeRun& run, std::size_t index = 0) { return run.get<Heightfield>(index); }

// One contract's failures as GoogleTest failures.
inline void expect_passes(const contracts::ContractResult& r) {
  for (const auto& f : r.failures) ADD_FAILURE() << "contract '" << r.contract << "': " << f;
}

// Every contract (declaration, cache key, reach, threads, extremes) on a registered type.
inline void expect_node_contracts(const std::string& type_name) {
  const NodeType* t = NodeRegistry::instance().find(type_name);
  ASSERT_NE(t, nullptr) << "no registered node type '" << type_name << "': are its sources compiled into the test?";
  for (const auto& r : contracts::check_node_contracts(*t)) expect_passes(r);
}

// The extremes contract alone (every parameter at the ends of its range, non-finite inputs: a finite result, a
// NodeError or a prompt stop after a cancel), with your own limits, e.g. a longer budget for a slow simulation:
//   orogen::contracts::ExtremesOptions o;
//   o.budget_seconds = 30.0;
//   orogen::kit::expect_extremes("Canyon", o);
inline void expect_extremes(const std::string& type_name, const contracts::ExtremesOptions& options = {}) {
  const NodeType* t = NodeRegistry::instance().find(type_name);
  ASSERT_NE(t, nullptr) << "no registered node type '" << type_name << "': are its sources compiled into the test?";
  expect_passes(contracts::check_extremes(*t, options));
}

}  // namespace orogen::kit
