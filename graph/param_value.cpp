#include "graph/param_value.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace orogen {

double CurveValue::evaluate(double x) const {
  const auto n = points.size();
  if (n == 0 || std::isnan(x)) return x;  // NaN in, NaN out: no segment to look up
  if (n == 1 || x <= points.front().x) return points.front().y;
  if (x >= points.back().x) return points.back().y;
  // Secant slopes, then Fritsch-Carlson tangents limited so each segment stays monotone.
  const auto k = static_cast<std::size_t>(
      std::upper_bound(points.begin(), points.end(), x, [](double v, const glm::dvec2& p) { return v < p.x; }) -
      points.begin() - 1);
  auto secant = [&](std::size_t i) { return (points[i + 1].y - points[i].y) / (points[i + 1].x - points[i].x); };
  auto tangent = [&](std::size_t i) {
    if (i == 0) return secant(0);
    if (i == n - 1) return secant(n - 2);
    const double a = secant(i - 1), b = secant(i);
    if (a * b <= 0.0) return 0.0;
    // Weighted harmonic mean (Fritsch-Butland), which satisfies the monotonicity constraint.
    const double h0 = points[i].x - points[i - 1].x, h1 = points[i + 1].x - points[i].x;
    const double w1 = 2 * h1 + h0, w2 = h1 + 2 * h0;
    return (w1 + w2) / (w1 / a + w2 / b);
  };
  double m0 = tangent(k), m1 = tangent(k + 1);
  const double d = secant(k);
  if (d == 0.0) {
    m0 = m1 = 0.0;
  } else {
    // Endpoint tangents can still overshoot; clamp to 3x the secant (Fritsch-Carlson condition).
    m0 = std::clamp(m0 / d, 0.0, 3.0) * d;
    m1 = std::clamp(m1 / d, 0.0, 3.0) * d;
  }
  const double h = points[k + 1].x - points[k].x;
  const double t = (x - points[k].x) / h, t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * points[k].y + (t3 - 2 * t2 + t) * h * m0 + (-2 * t3 + 3 * t2) * points[k + 1].y +
         (t3 - t2) * h * m1;
}

glm::vec4 GradientValue::evaluate(double t) const {
  if (std::isnan(t)) return glm::vec4(std::numeric_limits<float>::quiet_NaN());  // NaN in, NaN out
  if (stops.empty()) return glm::vec4(static_cast<float>(t), static_cast<float>(t), static_cast<float>(t), 1.0f);
  if (t <= stops.front().position) return stops.front().color;
  if (t >= stops.back().position) return stops.back().color;
  for (std::size_t i = 1; i < stops.size(); ++i) {
    if (t <= stops[i].position) {
      const double span = stops[i].position - stops[i - 1].position;
      const float f = span > 0 ? static_cast<float>((t - stops[i - 1].position) / span) : 1.0f;
      return stops[i - 1].color * (1.0f - f) + stops[i].color * f;
    }
  }
  return stops.back().color;
}

bool holds_param_type(const ParamValue& v, ParamType t) {
  switch (t) {
    case ParamType::Float:
      return std::holds_alternative<double>(v);
    case ParamType::Int:
      return std::holds_alternative<std::int64_t>(v);
    case ParamType::Bool:
      return std::holds_alternative<bool>(v);
    case ParamType::Vec2:
      return std::holds_alternative<glm::dvec2>(v);
    case ParamType::Vec3:
      return std::holds_alternative<glm::dvec3>(v);
    case ParamType::Color:
      return std::holds_alternative<glm::vec4>(v);
    case ParamType::Enum:
    case ParamType::String:
    case ParamType::Path:
      return std::holds_alternative<std::string>(v);
    case ParamType::Seed:
      return std::holds_alternative<std::uint64_t>(v);
    case ParamType::Curve:
      return std::holds_alternative<CurveValue>(v);
    case ParamType::Gradient:
      return std::holds_alternative<GradientValue>(v);
    case ParamType::Table:
      return std::holds_alternative<TableValue>(v);
  }
  return false;
}

std::string describe(const ParamValue& v) {
  std::ostringstream s;
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>)
          s << (x ? "true" : "false");
        else if constexpr (std::is_same_v<T, std::int64_t> || std::is_same_v<T, std::uint64_t> ||
                           std::is_same_v<T, double>)
          s << x;
        else if constexpr (std::is_same_v<T, glm::dvec2>)
          s << "[" << x.x << ", " << x.y << "]";
        else if constexpr (std::is_same_v<T, glm::dvec3>)
          s << "[" << x.x << ", " << x.y << ", " << x.z << "]";
        else if constexpr (std::is_same_v<T, glm::vec4>)
          s << "[" << x.r << ", " << x.g << ", " << x.b << ", " << x.a << "]";
        else if constexpr (std::is_same_v<T, std::string>)
          s << '"' << x << '"';
        else if constexpr (std::is_same_v<T, CurveValue>)
          s << "curve(" << x.points.size() << " points)";
        else if constexpr (std::is_same_v<T, GradientValue>)
          s << "gradient(" << x.stops.size() << " stops)";
        else if constexpr (std::is_same_v<T, TableValue>)
          s << "table(" << x.rows.size() << " rows)";
      },
      v);
  return s.str();
}

}  // namespace orogen
