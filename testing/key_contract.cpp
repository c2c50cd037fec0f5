// The cache-key contract (testing/contracts.h): the Gaffer idea, every input must change the hash and nothing
// else may; and what a type leaves out of its key must not change its result.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "evaluator/value_serialization.h"
#include "graph/exec_context.h"
#include "graph/graph.h"
#include "graph/registry.h"
#include "testing/contracts.h"

namespace orogen::contracts {
namespace {

const std::string kNode = "under_test";

// Upstream stand-ins, one per port type: only their key matters (the "variant" parameter makes different
// ones), they are never evaluated. Not registered, so they never show up in node listings.
const NodeType& source_type(PortType t) {
  static const auto types = [] {
    std::vector<NodeType> v;
    for (PortType pt : kAllPortTypes) {
      NodeType type;
      type.name = "TestKeySource" + std::string(to_string(pt));
      type.category = "test";
      type.description = "Stand-in upstream node for cache-key checks";
      NodeBuilder b(type);
      b.output("out", pt).description("A value of the port type");
      b.param_int("variant", 0).unit(Unit::Count).description("Distinguishes stand-ins");
      b.execute([](ExecContext&) { throw NodeError("key-check stand-ins are not evaluable"); });
      v.push_back(std::move(type));
    }
    return v;
  }();
  return types.at(static_cast<std::size_t>(t));
}

std::optional<CacheKey> key_of(const Graph& g, const Domain& d, const std::string& id = kNode) {
  const auto keys = compute_cache_keys(g, d);
  const auto it = keys.find(id);
  if (it == keys.end()) return std::nullopt;
  return it->second;
}

std::string hex(const std::optional<CacheKey>& k) { return k ? k->hex() : std::string("<no key>"); }

// Valid numbers different from v: halfway towards each bound, else steps of max(1, |v|/2), else v +- 1.
std::vector<double> other_numbers(double v, const ParamDecl& decl, bool integer) {
  std::vector<double> out;
  const double step = integer ? 1.0 : std::max(1.0, std::abs(v) * 0.5);
  std::vector<double> tries;
  if (integer) {
    tries = {v + 1, v - 1};
  } else {
    if (decl.max) tries.push_back(v + (*decl.max - v) * 0.5);
    if (decl.min) tries.push_back(v + (*decl.min - v) * 0.5);
    tries.push_back(v + step);
    tries.push_back(v - step);
    tries.push_back(v + 1e-3 * step);
    tries.push_back(v - 1e-3 * step);
  }
  for (double x : tries) {
    if (!std::isfinite(x) || x == v) continue;
    if ((decl.min && x < *decl.min) || (decl.max && x > *decl.max)) continue;
    out.push_back(x);
    break;  // one is enough
  }
  return out;
}

float other_colour(float c) { return c < 0.5f ? c + 0.25f : c - 0.25f; }

std::string changed_path(const std::string& v, const ParamDecl& decl) {
  if (v.empty()) return "key_check" + (decl.extensions.empty() ? std::string(".dat") : decl.extensions.front());
  for (const auto& ext : decl.extensions)
    if (v.size() > ext.size() && v.compare(v.size() - ext.size(), ext.size(), ext) == 0)
      return v.substr(0, v.size() - ext.size()) + "_changed" + ext;
  return v + "_changed";
}

// Changed values of a parameter to try, each with a label naming what was changed.
std::vector<std::pair<std::string, ParamValue>> perturbations(const ParamDecl& decl, const ParamValue& v) {
  std::vector<std::pair<std::string, ParamValue>> out;
  switch (decl.type) {
    case ParamType::Float:
      for (double x : other_numbers(std::get<double>(v), decl, false)) out.push_back({"", x});
      break;
    case ParamType::Int:
      for (double x : other_numbers(static_cast<double>(std::get<std::int64_t>(v)), decl, true))
        out.push_back({"", static_cast<std::int64_t>(x)});
      break;
    case ParamType::Bool:
      out.push_back({"", !std::get<bool>(v)});
      break;
    case ParamType::Vec2:
      for (int c = 0; c < 2; ++c) {
        for (double x : other_numbers(std::get<glm::dvec2>(v)[c], decl, false)) {
          auto p = std::get<glm::dvec2>(v);
          p[c] = x;
          out.push_back({"component " + std::to_string(c), p});
        }
      }
      break;
    case ParamType::Vec3:
      for (int c = 0; c < 3; ++c) {
        for (double x : other_numbers(std::get<glm::dvec3>(v)[c], decl, false)) {
          auto p = std::get<glm::dvec3>(v);
          p[c] = x;
          out.push_back({"component " + std::to_string(c), p});
        }
      }
      break;
    case ParamType::Color:
      for (int c = 0; c < 4; ++c) {
        auto p = std::get<glm::vec4>(v);
        p[c] = other_colour(p[c]);
        out.push_back({"component " + std::to_string(c), p});
      }
      break;
    case ParamType::Enum:
      for (const auto& choice : decl.choices)
        if (choice != std::get<std::string>(v)) out.push_back({"choice " + choice, choice});
      break;
    case ParamType::String:
      out.push_back({"", std::get<std::string>(v) + "_changed"});
      break;
    case ParamType::Path:
      out.push_back({"", changed_path(std::get<std::string>(v), decl)});
      break;
    case ParamType::Seed:
      out.push_back({"", std::get<std::uint64_t>(v) + 1});
      break;
    case ParamType::Curve: {
      auto c = std::get<CurveValue>(v);
      if (c.points.empty())
        c.points.push_back({0.0, 0.0});
      else
        c.points.front().y += 0.25;
      out.push_back({"first point", c});
      auto more = std::get<CurveValue>(v);
      more.points.push_back({more.points.empty() ? 0.0 : more.points.back().x + 1.0, 0.5});
      out.push_back({"added point", more});
      break;
    }
    case ParamType::Gradient: {
      auto g = std::get<GradientValue>(v);
      if (g.stops.empty())
        g.stops.push_back({});
      else
        g.stops.front().color.r = other_colour(g.stops.front().color.r);
      out.push_back({"first stop color", g});
      auto more = std::get<GradientValue>(v);
      more.stops.push_back({more.stops.empty() ? 0.0 : more.stops.back().position + 0.0, {0.3f, 0.6f, 0.9f, 1.0f}});
      out.push_back({"added stop", more});
      break;
    }
    case ParamType::Table: {
      const auto& t = std::get<TableValue>(v);
      if (t.rows.empty()) {
        // An empty default: one row of valid cells must change the key.
        auto one = t;
        std::vector<TableCell> row;
        for (const auto& c : decl.table.columns) {
          const double x = std::clamp(1.0, c.min.value_or(-1e300), c.max.value_or(1e300));
          switch (c.type) {
            case ColumnType::Text:
              row.push_back(std::string("key_check"));
              break;
            case ColumnType::Enum:
              row.push_back(c.choices.front());
              break;
            case ColumnType::Number:
              row.push_back(x);
              break;
            case ColumnType::Integer:
              row.push_back(static_cast<std::int64_t>(std::ceil(x)));
              break;
            case ColumnType::Range:
              row.push_back(glm::dvec2(x, x));
              break;
            case ColumnType::Color:
              row.push_back(Srgb8{1, 2, 3});
              break;
          }
        }
        one.rows.push_back(std::move(row));
        out.push_back({"one row added", one});
      }
      if (!t.rows.empty()) {
        auto fewer = t;
        fewer.rows.pop_back();
        out.push_back({"last row removed", fewer});
        // Every cell of the first row, changed within its column's bounds.
        for (std::size_t c = 0; c < t.columns.size(); ++c) {
          const TableColumn& col = decl.table.columns[c];
          auto changed = t;
          TableCell& cell = changed.rows.front()[c];
          if (auto* s = std::get_if<std::string>(&cell)) {
            if (col.type == ColumnType::Enum) {
              for (const auto& choice : col.choices)
                if (choice != *s) {
                  *s = choice;
                  break;
                }
            } else {
              *s += "_changed";
            }
          } else if (auto* x = std::get_if<double>(&cell)) {
            TableColumn bounds = col;
            ParamDecl as_float;
            as_float.min = bounds.min;
            as_float.max = bounds.max;
            for (double y : other_numbers(*x, as_float, false)) *x = y;
          } else if (auto* i = std::get_if<std::int64_t>(&cell)) {
            *i = (col.max && static_cast<double>(*i + 1) > *col.max) ? *i - 1 : *i + 1;
          } else if (auto* r = std::get_if<glm::dvec2>(&cell)) {
            if (std::isfinite(r->y))
              r->y += 0.5 * (std::isfinite(r->x) ? std::max(r->y - r->x, 0.5) : 1.0);
            else
              r->x -= 1.0;
          } else if (auto* color = std::get_if<Srgb8>(&cell)) {
            color->r = static_cast<std::uint8_t>(color->r ^ 0x40);
          }
          out.push_back({"row 0 column " + col.name, changed});
        }
      }
      break;
    }
  }
  std::erase_if(out, [&](const auto& entry) { return entry.second == v || !decl.check(entry.second).empty(); });
  return out;
}

}  // namespace

std::vector<std::string> param_key_failures(const NodeType& type, const Domain& d) {
  std::vector<std::string> fail;
  const std::string& type_name = type.name;
  Graph g;
  g.add_node(type, kNode);
  const auto k0 = key_of(g, d);
  if (!k0) return {type_name + ": the node has no cache key"};

  for (const ParamDecl& decl : type.params) {
    const ParamValue original = g.param(kNode, decl.name);
    const auto changes = perturbations(decl, original);
    const bool no_alternative = (decl.type == ParamType::Enum && decl.choices.size() < 2) ||
                                ((decl.type == ParamType::Float || decl.type == ParamType::Int) && decl.min &&
                                 decl.max && *decl.min == *decl.max);
    if (changes.empty() && !no_alternative)
      fail.push_back(type_name + "." + decl.name + ": found no valid value other than " + describe(original) +
                     " to check the key with");
    for (const auto& [what, value] : changes) {
      g.set_param(kNode, decl.name, value);
      const auto k1 = key_of(g, d);
      if (!(k1 && *k1 != *k0))
        fail.push_back(type_name + "." + decl.name + (what.empty() ? "" : " (" + what + ")") + ": changing it from " +
                       describe(original) + " to " + describe(value) + " did not change the cache key " + hex(k0));
      g.set_param(kNode, decl.name, original);
      if (hex(key_of(g, d)) != hex(k0))
        fail.push_back(type_name + "." + decl.name + ": setting it back to " + describe(original) +
                       " did not restore the cache key");
    }
  }

  // The domain: another resolution of the same rectangle, and the same resolution somewhere else.
  const Domain other_resolution = d.resampled(d.resolution + glm::ivec2(1, 1));
  Domain shifted = d;
  shifted.origin += glm::dvec2(d.spacing.x * 3.0, -d.spacing.y * 2.0);
  for (const Domain& other : {other_resolution, shifted}) {
    const auto k1 = key_of(g, other);
    if (type.domain_independent && hex(k1) != hex(k0))
      fail.push_back(type_name + " is domain_independent, but its key changed with the domain (" + d.describe() +
                     " -> " + other.describe() + ")");
    if (!type.domain_independent && hex(k1) == hex(k0))
      fail.push_back(type_name + ": changing the domain (" + d.describe() + " -> " + other.describe() +
                     ") did not change the cache key");
  }

  // Nothing else: the node's id, its editor position, other nodes.
  g.editor.positions[kNode] = {123.0, -45.0};
  if (hex(key_of(g, d)) != hex(k0)) fail.push_back(type_name + ": the editor position changed the cache key");
  g.rename_node(kNode, "renamed_node");
  if (hex(key_of(g, d, "renamed_node")) != hex(k0)) fail.push_back(type_name + ": the node id changed the cache key");
  g.add_node(type, "an_unrelated_node");
  if (hex(key_of(g, d, "renamed_node")) != hex(k0))
    fail.push_back(type_name + ": an unrelated node changed the cache key");
  return fail;
}

std::vector<std::string> input_key_failures(const NodeType& type, const Domain& d) {
  std::vector<std::string> fail;
  const std::string& type_name = type.name;
  Graph g;
  g.add_node(type, kNode);
  // Every input connected to its own stand-in, all different.
  std::vector<std::string> sources;
  for (std::size_t i = 0; i < type.inputs.size(); ++i) {
    const auto& port = type.inputs[i];
    const std::string src = "source_" + std::to_string(i);
    g.add_node(source_type(port.type), src);
    g.set_param(src, "variant", static_cast<std::int64_t>(i));
    g.connect({src, "out"}, kNode, port.name);
    sources.push_back(src);
  }
  const auto k0 = key_of(g, d);
  if (!k0) return {type_name + ": the node has no cache key with every input connected"};

  for (std::size_t i = 0; i < type.inputs.size(); ++i) {
    const auto& port = type.inputs[i];
    const std::string alt = "other_source_" + std::to_string(i);
    g.add_node(source_type(port.type), alt);
    g.set_param(alt, "variant", static_cast<std::int64_t>(1000 + i));
    g.connect({alt, "out"}, kNode, port.name);
    const auto k1 = key_of(g, d);
    if (!(k1 && *k1 != *k0))
      fail.push_back(type_name + ": connecting a different upstream node to input '" + port.name +
                     "' did not change the cache key");
    g.connect({sources[i], "out"}, kNode, port.name);
    if (hex(key_of(g, d)) != hex(k0))
      fail.push_back(type_name + ": reconnecting the original upstream node to input '" + port.name +
                     "' did not restore the cache key");
    if (port.optional) {
      g.disconnect(kNode, port.name);
      if (hex(key_of(g, d)) == hex(k0))
        fail.push_back(type_name + ": disconnecting the optional input '" + port.name +
                       "' did not change the cache key");
      g.connect({sources[i], "out"}, kNode, port.name);
    }
    g.remove_node(alt);
    // Changing the upstream node's parameters must reach this node's key too.
    g.set_param(sources[i], "variant", static_cast<std::int64_t>(2000 + i));
    if (hex(key_of(g, d)) == hex(k0))
      fail.push_back(type_name + ": a parameter change upstream of input '" + port.name +
                     "' did not change the cache key");
    g.set_param(sources[i], "variant", static_cast<std::int64_t>(i));
  }
  if (hex(key_of(g, d)) != hex(k0)) fail.push_back(type_name + ": the key did not come back after the input checks");
  return fail;
}

std::vector<std::string> key_coverage_failures(const NodeType& type, const Domain& d) {
  if (!type.domain_independent || type.writes_files) return {};
  std::map<std::string, PortValue> inputs;
  for (const auto& port : type.inputs) {
    auto v = contract_input(port, d);
    if (std::holds_alternative<std::monostate>(v)) return {};  // an input the kit cannot make: not checked
    inputs[port.name] = v;
  }
  Domain other = d.resampled(d.resolution + glm::ivec2(7, 5));
  other.origin += glm::dvec2(d.spacing.x * 11.0, -d.spacing.y * 3.0);
  NodeRun a, b;
  try {
    a = run_node(type.name, d, {}, inputs);
    b = run_node(type.name, other, {}, inputs);
  } catch (const std::exception& e) {
    return {};  // a node that fails with its defaults is reported by the other contracts
  }
  for (std::size_t k = 0; k < a.outputs.size() && k < b.outputs.size(); ++k)
    if (serialize_value(a.outputs[k]) != serialize_value(b.outputs[k]))
      return {type.name + " is declared domain_independent, so the domain is left out of its cache key, but output '" +
              type.outputs[k].name + "' changed with the domain (" + d.describe() + " -> " + other.describe() +
              "): the cache would serve a result computed for another domain. Drop domain_independent() or make "
              "the result independent of the domain"};
  return {};
}

ContractResult check_cache_key(const NodeType& type, const Domain& d) {
  ContractResult r{"cache key", Status::Passed, {}, "every parameter and input changes the key, nothing else does"};
  for (auto* part : {&param_key_failures, &input_key_failures, &key_coverage_failures})
    for (auto& f : (*part)(type, d)) r.failures.push_back(std::move(f));
  if (!r.failures.empty()) r.status = Status::Failed;
  return r;
}

}  // namespace orogen::contracts
