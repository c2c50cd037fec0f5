#pragma once
// A value on a link: an immutable, shared result of a node. Links never copy data.
#include <cstddef>
#include <memory>
#include <variant>

#include "graph/curves.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/module_string.h"
#include "graph/points.h"
#include "graph/polygon_map.h"
#include "graph/report.h"
#include "graph/scene.h"
#include "graph/value_type.h"

namespace orogen {

struct Mesh;  // graph/mesh.h; kept out of this header so OpenMesh is only compiled where meshes are used
using MeshPtr = std::shared_ptr<const Mesh>;

// Alternative order matches PortType; monostate = no value.
using PortValue = std::variant<std::monostate, HeightfieldPtr, ImagePtr, PointsPtr, CurvesPtr, MeshPtr, PolygonMapPtr,
                               ReportPtr, ModuleStringPtr, ScenePtr>;

// The PortType a value holds (undefined for monostate; check has_value first).
PortType port_type_of(const PortValue& v);
bool has_value(const PortValue& v);
// Approximate memory held by the value, for the cache's byte bound.
std::size_t byte_size(const PortValue& v);

template <class T>
struct PortTypeOf;
template <>
struct PortTypeOf<Heightfield> {
  static constexpr PortType value = PortType::Heightfield;
};
template <>
struct PortTypeOf<Image> {
  static constexpr PortType value = PortType::Image;
};
template <>
struct PortTypeOf<Points> {
  static constexpr PortType value = PortType::Points;
};
template <>
struct PortTypeOf<Curves> {
  static constexpr PortType value = PortType::Curves;
};
template <>
struct PortTypeOf<Mesh> {
  static constexpr PortType value = PortType::Mesh;
};
template <>
struct PortTypeOf<PolygonMap> {
  static constexpr PortType value = PortType::PolygonMap;
};
template <>
struct PortTypeOf<Report> {
  static constexpr PortType value = PortType::Report;
};
template <>
struct PortTypeOf<ModuleString> {
  static constexpr PortType value = PortType::ModuleString;
};
template <>
struct PortTypeOf<Scene> {
  static constexpr PortType value = PortType::Scene;
};

}  // namespace orogen
