#include "graph/value_type.h"

#include <array>
#include <utility>

namespace orogen {
namespace {

constexpr std::array<std::pair<PortType, std::string_view>, 9> kPortNames{{
    {PortType::Heightfield, "Heightfield"},
    {PortType::Image, "Image"},
    {PortType::Points, "Points"},
    {PortType::Curves, "Curves"},
    {PortType::Mesh, "Mesh"},
    {PortType::PolygonMap, "PolygonMap"},
    {PortType::Report, "Report"},
    {PortType::ModuleString, "ModuleString"},
    {PortType::Scene, "Scene"},
}};

constexpr std::array<std::pair<ParamType, std::string_view>, 13> kParamNames{{
    {ParamType::Float, "float"},
    {ParamType::Int, "int"},
    {ParamType::Bool, "bool"},
    {ParamType::Vec2, "vec2"},
    {ParamType::Vec3, "vec3"},
    {ParamType::Color, "color"},
    {ParamType::Enum, "enum"},
    {ParamType::String, "string"},
    {ParamType::Path, "path"},
    {ParamType::Seed, "seed"},
    {ParamType::Curve, "curve"},
    {ParamType::Gradient, "gradient"},
    {ParamType::Table, "table"},
}};

}  // namespace

std::string_view to_string(PortType t) {
  for (const auto& [type, name] : kPortNames)
    if (type == t) return name;
  return "?";
}

std::string_view to_string(ParamType t) {
  for (const auto& [type, name] : kParamNames)
    if (type == t) return name;
  return "?";
}

std::optional<PortType> port_type_from_string(std::string_view s) {
  for (const auto& [type, name] : kPortNames)
    if (name == s) return type;
  return std::nullopt;
}

std::optional<ParamType> param_type_from_string(std::string_view s) {
  for (const auto& [type, name] : kParamNames)
    if (name == s) return type;
  return std::nullopt;
}

}  // namespace orogen
