// libFuzzer target: every parameter text grammar a user types or a graph file carries, through
// param_from_text (the --set and editor syntax) and param_from_json, for every parameter of every node
// type (curves, gradients, vectors, colours, enums, paths, seeds ...). The first byte picks the parameter.
// Values that are accepted are then evaluated where they are functions (curves, gradients).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/registry.h"

namespace {

std::vector<const orogen::ParamDecl*> all_params() {
  std::vector<const orogen::ParamDecl*> params;
  for (const auto* type : orogen::NodeRegistry::instance().all())
    for (const auto& p : type->params) params.push_back(&p);
  return params;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto params = all_params();
  if (size < 1 || params.empty()) return 0;
  const orogen::ParamDecl& decl = *params[data[0] % params.size()];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string error;
  std::vector<orogen::ParamValue> values;
  if (auto v = orogen::param_from_text(text, decl, error)) values.push_back(*v);
  const auto json = nlohmann::json::parse(text, nullptr, false);
  if (!json.is_discarded())
    if (auto v = orogen::param_from_json(json, decl, error)) values.push_back(*v);
  const double probes[] = {-1e300, -1.0, 0.0, 0.25, 0.5, 1.0, 1e300, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()};
  for (const auto& v : values) {
    if (!decl.check(v).empty()) continue;
    if (const auto* curve = std::get_if<orogen::CurveValue>(&v))
      for (double x : probes) (void)curve->evaluate(x);
    if (const auto* gradient = std::get_if<orogen::GradientValue>(&v))
      for (double x : probes) (void)gradient->evaluate(x);
  }
  return 0;
}
