// The only translation unit that includes CGAL (slow to compile).
#include <map>
#include <stdexcept>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/convex_hull_3.h>
#include <glm/geometric.hpp>

#include "nodes/rocks/hull_rock.h"

namespace orogen::rocks {

Hull convex_hull_cgal(const std::vector<glm::dvec3>& points) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using P = K::Point_3;
  using SM = CGAL::Surface_mesh<P>;
  std::vector<P> pts;
  pts.reserve(points.size());
  for (const auto& p : points) pts.emplace_back(p.x, p.y, p.z);
  if (pts.size() < 4) throw std::invalid_argument("a convex hull needs at least 4 points");
  SM sm;
  CGAL::convex_hull_3(pts.begin(), pts.end(), sm);
  Hull h;
  if (sm.number_of_faces() < 4 || !CGAL::is_closed(sm))
    throw std::invalid_argument("the points span less than three dimensions");
  std::vector<int> index(sm.number_of_vertices(), -1);
  for (auto v : sm.vertices()) {
    const P& p = sm.point(v);
    index[v.idx()] = static_cast<int>(h.vertices.size());
    h.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k == 3) throw std::invalid_argument("hull face is not a triangle");
      tri[static_cast<std::size_t>(k++)] = index[v.idx()];
    }
    if (k != 3) throw std::invalid_argument("hull face is not a triangle");
    h.faces.push_back(tri);
  }
  // A coplanar set gives an open, flat triangulation (rejected above) or a zero volume.
  glm::dvec3 lo(h.vertices[0]), hi(h.vertices[0]);
  for (const auto& v : h.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
  const double extent = glm::length(hi - lo);
  double volume = 0.0;
  for (const auto& t : h.faces)
    volume += glm::dot(h.vertices[t[0]] - lo, glm::cross(h.vertices[t[1]] - lo, h.vertices[t[2]] - lo));
  if (!(volume > 1e-12 * extent * extent * extent))
    throw std::invalid_argument("the points span less than three dimensions");
  return h;
}

}  // namespace orogen::rocks
