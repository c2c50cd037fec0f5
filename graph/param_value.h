#pragma once
// Parameter values. The variant alternative follows the declared ParamType:
//   Float -> double, Int -> int64_t, Bool -> bool, Vec2 -> dvec2, Vec3 -> dvec3, Color -> vec4 (linear RGBA),
//   Enum / String / Path -> std::string, Seed -> uint64_t, Curve -> CurveValue, Gradient -> GradientValue,
//   Table -> TableValue (graph/table_value.h).
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "graph/table_value.h"
#include "graph/value_type.h"

namespace orogen {

// A remapping curve y = f(x) through control points, interpolated by a monotone cubic (Fritsch-Carlson):
// it never overshoots between points, so monotone points give a monotone curve. Outside the first and last
// point the curve is constant.
struct CurveValue {
  std::vector<glm::dvec2> points;  // sorted by x, x strictly increasing

  double evaluate(double x) const;
  bool operator==(const CurveValue&) const = default;
  static CurveValue identity() { return {{{0.0, 0.0}, {1.0, 1.0}}}; }
};

// A colour gradient: linear interpolation of linear-RGBA stops by position in 0..1.
struct GradientValue {
  struct Stop {
    double position = 0.0;
    glm::vec4 color{0, 0, 0, 1};
    bool operator==(const Stop&) const = default;
  };
  std::vector<Stop> stops;  // sorted by position

  glm::vec4 evaluate(double t) const;
  bool operator==(const GradientValue&) const = default;
};

using ParamValue = std::variant<bool, std::int64_t, double, glm::dvec2, glm::dvec3, glm::vec4, std::string,
                                std::uint64_t, CurveValue, GradientValue, TableValue>;

// Whether `v` holds the alternative that parameters of type `t` use.
bool holds_param_type(const ParamValue& v, ParamType t);
// A short human-readable rendering, for messages and the CLI.
std::string describe(const ParamValue& v);

}  // namespace orogen
