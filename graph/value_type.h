#pragma once
// The types that flow along links (port types) and the types of parameters.
#include <optional>
#include <string_view>

namespace orogen {

// What a port carries. Links connect ports of the same type only.
enum class PortType { Heightfield, Image, Points, Curves, Mesh, PolygonMap, Report, ModuleString, Scene };

// What a parameter holds.
enum class ParamType { Float, Int, Bool, Vec2, Vec3, Color, Enum, String, Path, Seed, Curve, Gradient, Table };

std::string_view to_string(PortType t);
std::string_view to_string(ParamType t);
std::optional<PortType> port_type_from_string(std::string_view s);
std::optional<ParamType> param_type_from_string(std::string_view s);

inline constexpr PortType kAllPortTypes[] = {PortType::Heightfield, PortType::Image,        PortType::Points,
                                             PortType::Curves,      PortType::Mesh,         PortType::PolygonMap,
                                             PortType::Report,      PortType::ModuleString, PortType::Scene};

}  // namespace orogen
