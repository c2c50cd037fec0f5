// Parameter values <-> JSON (the "params" object of a node in a graph file, and `--set` on the command line).
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/table_json.h"

namespace orogen {
namespace {

using json_util::describe;
using nlohmann::json;

json color_to_json(const glm::vec4& c) {
  // Colours are float32; write each component as its shortest text so 0.1f is saved as 0.1.
  json out = json::array();
  for (int k = 0; k < 4; ++k) out.push_back(json_util::float_as_short_double(c[k]));
  return out;
}

std::optional<double> read_number(const json& j, const std::string& what, std::string& error) {
  if (!j.is_number()) {
    error = what + "expected a number, found " + describe(j);
    return std::nullopt;
  }
  return j.get<double>();
}

// An array of exactly `n` numbers (or, when `n_alt` is set, of n_alt numbers), for vectors and colours.
std::optional<std::vector<double>> read_numbers(const json& j, std::size_t n, std::size_t n_alt,
                                                const std::string& shape, const std::string& what, std::string& error) {
  if (!j.is_array() || (j.size() != n && j.size() != n_alt)) {
    error = what + "expected " + shape + ", found " + describe(j);
    return std::nullopt;
  }
  std::vector<double> out;
  for (std::size_t k = 0; k < j.size(); ++k) {
    auto v = read_number(j[k], what + "component " + std::to_string(k) + ": ", error);
    if (!v) return std::nullopt;
    out.push_back(*v);
  }
  return out;
}

std::optional<glm::vec4> read_color(const json& j, const std::string& what, std::string& error) {
  auto c = read_numbers(j, 4, 3, "a color [r, g, b] or [r, g, b, a]", what, error);
  if (!c) return std::nullopt;
  return glm::vec4(static_cast<float>((*c)[0]), static_cast<float>((*c)[1]), static_cast<float>((*c)[2]),
                   c->size() == 4 ? static_cast<float>((*c)[3]) : 1.0f);
}

std::optional<ParamValue> convert(const json& j, const ParamDecl& decl, std::string& error) {
  switch (decl.type) {
    case ParamType::Float: {
      auto v = read_number(j, "", error);
      if (!v) return std::nullopt;
      return ParamValue(*v);
    }
    case ParamType::Int: {
      if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
        error = "the integer " + j.dump() + " is too large";
        return std::nullopt;
      }
      if (!j.is_number_integer()) {
        error = "expected an integer, found " + describe(j);
        return std::nullopt;
      }
      return ParamValue(j.get<std::int64_t>());
    }
    case ParamType::Bool:
      if (!j.is_boolean()) {
        error = "expected true or false, found " + describe(j);
        return std::nullopt;
      }
      return ParamValue(j.get<bool>());
    case ParamType::Vec2: {
      auto v = read_numbers(j, 2, 2, "[x, y] (2 numbers)", "", error);
      if (!v) return std::nullopt;
      return ParamValue(glm::dvec2((*v)[0], (*v)[1]));
    }
    case ParamType::Vec3: {
      auto v = read_numbers(j, 3, 3, "[x, y, z] (3 numbers)", "", error);
      if (!v) return std::nullopt;
      return ParamValue(glm::dvec3((*v)[0], (*v)[1], (*v)[2]));
    }
    case ParamType::Color: {
      auto c = read_color(j, "", error);
      if (!c) return std::nullopt;
      return ParamValue(*c);
    }
    case ParamType::Enum:
    case ParamType::String:
    case ParamType::Path:
      if (!j.is_string()) {
        error = "expected a string, found " + describe(j);
        return std::nullopt;
      }
      return ParamValue(j.get<std::string>());
    case ParamType::Seed: {
      if (j.is_number_integer() && !j.is_number_unsigned() && j.get<std::int64_t>() < 0) {
        error = "a seed must not be negative, found " + j.dump();
        return std::nullopt;
      }
      if (!j.is_number_integer()) {
        error = "expected a seed (an integer from 0 to 18446744073709551615), found " + describe(j);
        return std::nullopt;
      }
      return ParamValue(j.get<std::uint64_t>());
    }
    case ParamType::Curve: {
      if (!j.is_array()) {
        error = "expected a curve [[x, y], ...], found " + describe(j);
        return std::nullopt;
      }
      CurveValue curve;
      for (std::size_t i = 0; i < j.size(); ++i) {
        auto p = read_numbers(j[i], 2, 2, "a point [x, y]", "point " + std::to_string(i) + ": ", error);
        if (!p) return std::nullopt;
        curve.points.emplace_back((*p)[0], (*p)[1]);
      }
      return ParamValue(std::move(curve));
    }
    case ParamType::Gradient: {
      if (!j.is_array()) {
        error = "expected a gradient [[position, [r, g, b, a]], ...], found " + describe(j);
        return std::nullopt;
      }
      GradientValue gradient;
      for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string what = "stop " + std::to_string(i) + ": ";
        const json& s = j[i];
        if (!s.is_array() || s.size() != 2) {
          error = what + "expected [position, [r, g, b, a]], found " + describe(s);
          return std::nullopt;
        }
        auto position = read_number(s[0], what + "position: ", error);
        if (!position) return std::nullopt;
        auto color = read_color(s[1], what + "color: ", error);
        if (!color) return std::nullopt;
        gradient.stops.push_back({*position, *color});
      }
      return ParamValue(std::move(gradient));
    }
    case ParamType::Table: {
      TableProblem problem;
      auto table = table_from_json(j, decl.table, problem);
      if (!table) {
        error = problem.str(decl.name);
        return std::nullopt;
      }
      return ParamValue(std::move(*table));
    }
  }
  error = "unsupported parameter type";
  return std::nullopt;
}

}  // namespace

nlohmann::json param_to_json(const ParamValue& value) {
  return std::visit(
      [](const auto& x) -> json {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, glm::dvec2>)
          return json::array({x.x, x.y});
        else if constexpr (std::is_same_v<T, glm::dvec3>)
          return json::array({x.x, x.y, x.z});
        else if constexpr (std::is_same_v<T, glm::vec4>)
          return color_to_json(x);
        else if constexpr (std::is_same_v<T, CurveValue>) {
          json out = json::array();
          for (const auto& p : x.points) out.push_back(json::array({p.x, p.y}));
          return out;
        } else if constexpr (std::is_same_v<T, GradientValue>) {
          json out = json::array();
          for (const auto& s : x.stops) out.push_back(json::array({json(s.position), color_to_json(s.color)}));
          return out;
        } else if constexpr (std::is_same_v<T, TableValue>) {
          return table_to_json(x);
        } else {
          return json(x);  // bool, int64, double, string, uint64
        }
      },
      value);
}

std::optional<ParamValue> param_from_json(const nlohmann::json& j, const ParamDecl& decl, std::string& error) {
  error.clear();
  auto value = convert(j, decl, error);
  if (!value) return std::nullopt;
  if (auto why = decl.check(*value); !why.empty()) {
    error = why;
    if (decl.type == ParamType::Enum) {
      const auto hint = json_util::closest_name(std::get<std::string>(*value), decl.choices);
      if (!hint.empty()) error += " (did you mean '" + hint + "'?)";
    }
    return std::nullopt;
  }
  return value;
}

std::optional<ParamValue> param_from_text(const std::string& text, const ParamDecl& decl, std::string& error) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  const bool textual = decl.type == ParamType::Enum || decl.type == ParamType::String || decl.type == ParamType::Path;
  // Text that is not JSON is a bare string; for textual parameters even JSON-looking text (123, true) is
  // taken literally unless it is a quoted JSON string.
  if (j.is_discarded() || (textual && !j.is_string())) j = text;
  return param_from_json(j, decl, error);
}

}  // namespace orogen
