#pragma once
// Polylines with per-vertex width and named attributes: river networks, feature curves, roads.
// Vertex positions carry height in z (metres).
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace orogen {

struct Curve {
  std::vector<glm::vec3> points;                         // world metres, z = height
  std::vector<float> width;                              // metres, one per point
  std::map<std::string, std::vector<float>> attributes;  // per-point named floats (flow, size, ...)
  int parent = -1;  // index of the curve this one flows into / branches from (-1: a root)
};

struct Curves {
  std::vector<Curve> curves;

  std::size_t size() const { return curves.size(); }
  std::size_t vertex_count() const;
  // Throws std::logic_error if a curve's per-point arrays differ from its point count or a parent is
  // out of range.
  void check_consistent() const;
  std::size_t byte_size() const;
};

using CurvesPtr = std::shared_ptr<const Curves>;

}  // namespace orogen
