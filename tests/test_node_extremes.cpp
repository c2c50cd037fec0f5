// Every registered node at the extremes of every parameter's range, on tiny, huge-coordinate and non-square
// domains, with non-finite inputs: no crash, no sanitizer report, and either a result or a clear error.
// Generated from the registry, so a new node type is covered without touching this file.
//
// "A clear error" is a NodeError / FileError / GraphError (std::runtime_error) with a message, or Cancelled
// when a run at an extreme takes longer than the watchdog allows (a cancelled run is a clean outcome; the
// node must notice the cancellation, and return within kCancelBound of it: the bound of
// tests/test_cancellation.cpp). std::logic_error, std::bad_alloc or any other exception fails.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "evaluator/run_node.h"
#include "graph/cancel.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "support/registered_types.h"
#include "support/sample_values.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

constexpr auto kWatchdog = std::chrono::seconds(1);
#ifdef OROGEN_TEST_ASAN
constexpr double kCancelBound = 5.0;  // seconds from the cancel to the return, under AddressSanitizer
#else
constexpr double kCancelBound = 1.0;  // seconds from the cancel to the return
#endif
// Parameter sweeps of one type stop after this much time (simulations at their largest settings are each cut
// by the watchdog; the sweep still covers every domain and input kind first).
constexpr auto kTypeBudget = std::chrono::seconds(20);

struct DomainCase {
  std::string name;
  Domain domain;
};

std::vector<DomainCase> domains() {
  return {
      {"non-square 23x7", Domain::from_extent({0, 0}, {300, 90}, {23, 7})},
      {"tiny spacing", Domain::from_extent({0, 0}, {3.2e-5, 3.2e-5}, {17, 17})},
      {"huge coordinates", Domain::from_extent({9e11, -9e11}, {5000, 5000}, {17, 17})},
      {"2x2", Domain::from_extent({0, 0}, {10, 10}, {2, 2})},
  };
}

HeightfieldPtr smooth_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(50.0 + 40.0 * std::sin(0.7 * i + 0.3 * j));
  return h;
}

HeightfieldPtr non_finite_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  const float special[] = {std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(),
                           3e38f,
                           -3e38f,
                           0.0f,
                           1e-38f};
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = special[static_cast<std::size_t>(i * 3 + j) % 7];
  return h;
}

HeightfieldPtr all_nan_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (auto& v : h->data) v = std::numeric_limits<float>::quiet_NaN();
  return h;
}

enum class Outcome { Result, Error, Cancelled };

// Runs the node with a watchdog; fails the test for anything but a result, a clear error or a cancel.
Outcome run_checked(const std::string& label, const std::string& type, const Domain& d,
                    const std::map<std::string, ParamValue>& params, const std::map<std::string, PortValue>& inputs,
                    const OutputPolicy& policy) {
  CancelToken cancel;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  std::chrono::steady_clock::time_point cancelled_at{};
  std::thread watchdog([&] {
    std::unique_lock lock(m);
    if (!cv.wait_for(lock, kWatchdog, [&] { return done; })) {
      cancelled_at = std::chrono::steady_clock::now();
      cancel.cancel();
    }
  });
  Outcome outcome = Outcome::Result;
  try {
    (void)run_node(type, d, params, inputs, policy, &cancel);
  } catch (const Cancelled&) {
    outcome = Outcome::Cancelled;
  } catch (const std::logic_error& e) {
    ADD_FAILURE() << label << ": logic_error (a bug, not a clear error): " << e.what();
    outcome = Outcome::Error;
  } catch (const std::runtime_error& e) {
    EXPECT_GT(std::string(e.what()).size(), 5u) << label << ": an error without a message";
    outcome = Outcome::Error;
  } catch (const std::exception& e) {
    ADD_FAILURE() << label << ": " << typeid(e).name() << ": " << e.what();
    outcome = Outcome::Error;
  }
  const auto returned = std::chrono::steady_clock::now();
  {
    std::lock_guard lock(m);
    done = true;
  }
  cv.notify_one();
  watchdog.join();
  if (cancelled_at != std::chrono::steady_clock::time_point{}) {
    const double latency = std::chrono::duration<double>(returned - cancelled_at).count();
    EXPECT_LE(latency, kCancelBound) << label << ": returned " << latency << " s after the cancel";
  }
  return outcome;
}

// Parameter values at the ends of each declared range (one parameter changed at a time).
std::vector<std::pair<std::string, ParamValue>> extremes(const ParamDecl& p) {
  std::vector<std::pair<std::string, ParamValue>> out;
  auto ends = [&](double lo_default, double hi_default) {
    return std::pair(p.min.value_or(lo_default), p.max.value_or(hi_default));
  };
  switch (p.type) {
    case ParamType::Float: {
      const auto [lo, hi] = ends(-1e6, 1e6);
      out.push_back({"min", lo});
      out.push_back({"max", hi});
      break;
    }
    case ParamType::Int: {
      const auto [lo, hi] = ends(-1e6, 1e6);
      out.push_back({"min", static_cast<std::int64_t>(lo)});
      out.push_back({"max", static_cast<std::int64_t>(hi)});
      break;
    }
    case ParamType::Vec2: {
      const auto [lo, hi] = ends(-1e6, 1e6);
      out.push_back({"min", glm::dvec2(lo)});
      out.push_back({"max", glm::dvec2(hi)});
      out.push_back({"mixed", glm::dvec2(lo, hi)});
      break;
    }
    case ParamType::Vec3: {
      const auto [lo, hi] = ends(-1e6, 1e6);
      out.push_back({"min", glm::dvec3(lo)});
      out.push_back({"max", glm::dvec3(hi)});
      break;
    }
    case ParamType::Bool:
      out.push_back({"false", false});
      out.push_back({"true", true});
      break;
    case ParamType::Enum:
      for (const auto& c : p.choices) out.push_back({c, c});
      break;
    case ParamType::Seed:
      out.push_back({"max", std::numeric_limits<std::uint64_t>::max()});
      break;
    case ParamType::Curve: {
      CurveValue steep;
      steep.points = {{-1e6, 1e6}, {-1e6 + 1e-9, -1e6}, {1e6, 1e6}};
      out.push_back({"steep", steep});
      break;
    }
    default:
      break;  // colours, strings, paths, gradients: the defaults
  }
  return out;
}

class NodeExtremes : public ::testing::TestWithParam<std::string> {};

TEST_P(NodeExtremes, ResultOrClearErrorEverywhere) {
  const NodeType* type = NodeRegistry::instance().find(GetParam());
  ASSERT_NE(type, nullptr);
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("extremes-" + type->name);

  const auto start = std::chrono::steady_clock::now();
  for (const auto& [dname, d] : domains()) {
    const auto values = test::sample_values(smooth_field(d), policy);
    auto inputs_with = [&](const std::function<HeightfieldPtr(const Domain&)>& field) {
      std::map<std::string, PortValue> inputs;
      for (const auto& in : type->inputs) {
        if (in.type == PortType::Heightfield)
          inputs[in.name] = PortValue(field(d));
        else if (auto it = values.find(in.type); it != values.end())
          inputs[in.name] = it->second;
      }
      return inputs;
    };
    bool missing = false;
    for (const auto& in : type->inputs)
      if (!in.optional && !values.count(in.type)) missing = true;
    if (missing) continue;  // no producer for this port type yet
    const std::string where = type->name + " on " + dname;
    run_checked(where + ", defaults", type->name, d, {}, inputs_with(smooth_field), policy);
    if (!type->inputs.empty()) {
      run_checked(where + ", non-finite inputs", type->name, d, {}, inputs_with(non_finite_field), policy);
      run_checked(where + ", all-NaN inputs", type->name, d, {}, inputs_with(all_nan_field), policy);
    }
    // Parameter extremes on the first two domains (the others add nothing for parameters but time).
    if (dname != "non-square 23x7" && dname != "tiny spacing") continue;
    for (const auto& p : type->params) {
      if (p.output_file || p.type == ::orogen::ParamType::Path) continue;
      for (const auto& [label, value] : extremes(p)) {
        if (!p.check(value).empty()) continue;  // outside what the loader accepts
        if (std::chrono::steady_clock::now() - start > kTypeBudget) break;
        const std::map<std::string, ParamValue> params{{p.name, value}};
        run_checked(where + ", " + p.name + " = " + label, type->name, d, params, inputs_with(smooth_field), policy);
        if (!type->inputs.empty())
          run_checked(where + ", " + p.name + " = " + label + ", non-finite inputs", type->name, d, params,
                      inputs_with(non_finite_field), policy);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Registry, NodeExtremes, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

}  // namespace
}  // namespace orogen
