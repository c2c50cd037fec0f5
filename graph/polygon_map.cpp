#include "graph/polygon_map.h"

#include <stdexcept>

namespace orogen {
namespace {

void check_indices(const std::vector<int>& indices, std::size_t limit, bool allow_outside, const char* what) {
  for (int k : indices)
    if (k < (allow_outside ? -1 : 0) || k >= static_cast<int>(limit))
      throw std::logic_error(std::string("PolygonMap: ") + what + " index out of range");
}

void check_attributes(const PolygonMap::Attributes& attrs, std::size_t n, const char* what) {
  for (const auto& [name, values] : attrs)
    if (values.size() != n)
      throw std::logic_error(std::string("PolygonMap: ") + what + " attribute '" + name + "' has the wrong size");
}

}  // namespace

void PolygonMap::check_consistent() const {
  for (const auto& c : cells) {
    check_indices(c.corners, corners.size(), false, "cell corner");
    check_indices(c.neighbours, cells.size(), false, "cell neighbor");
    check_indices(c.edges, edges.size(), false, "cell edge");
  }
  for (const auto& q : corners) {
    check_indices(q.cells, cells.size(), false, "corner cell");
    check_indices(q.adjacent, corners.size(), false, "corner neighbor");
    check_indices(q.edges, edges.size(), false, "corner edge");
  }
  for (const auto& e : edges) {
    check_indices({e.cells[0], e.cells[1]}, cells.size(), true, "edge cell");
    check_indices({e.corners[0], e.corners[1]}, corners.size(), false, "edge corner");
  }
  check_attributes(cell_attributes, cells.size(), "cell");
  check_attributes(corner_attributes, corners.size(), "corner");
  check_attributes(edge_attributes, edges.size(), "edge");
}

std::size_t PolygonMap::byte_size() const {
  std::size_t bytes = sizeof(*this) + edges.size() * sizeof(Edge);
  for (const auto& c : cells)
    bytes += sizeof(Cell) + (c.corners.size() + c.neighbours.size() + c.edges.size()) * sizeof(int);
  for (const auto& q : corners)
    bytes += sizeof(Corner) + (q.cells.size() + q.adjacent.size() + q.edges.size()) * sizeof(int);
  for (const auto* attrs : {&cell_attributes, &corner_attributes, &edge_attributes})
    for (const auto& [name, values] : *attrs) bytes += name.size() + values.size() * sizeof(float);
  return bytes;
}

}  // namespace orogen
