#pragma once
// A planar polygon map (dual Voronoi / Delaunay structure, after Patel's polygon map generation used by
// Weiss 2015): cells around centres, the corners where cells meet, and the edges between corners. Named
// float attributes per element carry elevation, moisture, water, biome id, river volume, ...
#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen {

struct PolygonMap {
  struct Cell {
    glm::dvec2 centre;
    std::vector<int> corners;     // counter-clockwise
    std::vector<int> neighbours;  // adjacent cells
    std::vector<int> edges;
    bool border = false;  // touches the map boundary
  };
  struct Corner {
    glm::dvec2 position;
    std::vector<int> cells;     // cells meeting here
    std::vector<int> adjacent;  // corners joined to this one by an edge
    std::vector<int> edges;
    bool border = false;
  };
  struct Edge {
    std::array<int, 2> cells{-1, -1};    // the two cells the edge separates (-1 outside the map)
    std::array<int, 2> corners{-1, -1};  // its two end corners
  };
  using Attributes = std::map<std::string, std::vector<float>>;

  glm::dvec2 min_corner{0.0, 0.0}, max_corner{1.0, 1.0};  // world rectangle, metres
  std::vector<Cell> cells;
  std::vector<Corner> corners;
  std::vector<Edge> edges;
  Attributes cell_attributes, corner_attributes, edge_attributes;

  // Throws std::logic_error if an index is out of range or an attribute has the wrong length.
  void check_consistent() const;
  std::size_t byte_size() const;
};

using PolygonMapPtr = std::shared_ptr<const PolygonMap>;

}  // namespace orogen
