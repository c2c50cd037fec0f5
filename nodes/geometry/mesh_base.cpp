#include "nodes/geometry/mesh_base.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

namespace orogen {

Mesh mesh_with_base(const Mesh& mesh, double depth) {
  if (!(depth > 0.0)) throw std::invalid_argument("the base depth must be positive");
  Mesh result = mesh;
  TriMesh& m = result.mesh;
  if (m.n_vertices() == 0) return result;
  float zmin = std::numeric_limits<float>::infinity();
  for (auto v : m.vertices()) zmin = std::min(zmin, m.point(v)[2]);
  const float zb = static_cast<float>(zmin - depth);

  // The boundary loops, each as its boundary half-edges in order (collected before any face is added).
  std::vector<std::vector<TriMesh::HalfedgeHandle>> loops;
  std::vector<char> seen(m.n_halfedges(), 0);
  for (auto h : m.halfedges()) {
    if (!m.is_boundary(h) || seen[h.idx()]) continue;
    loops.emplace_back();
    for (auto g = h; !seen[g.idx()]; g = m.next_halfedge_handle(g)) {
      seen[g.idx()] = 1;
      loops.back().push_back(g);
    }
  }
  std::vector<TriMesh::VertexHandle> below(m.n_vertices());
  for (const auto& loop : loops) {
    double cx = 0.0, cy = 0.0;
    for (auto h : loop) {
      const auto a = m.from_vertex_handle(h);
      const auto p = m.point(a);
      cx += p[0];
      cy += p[1];
      below[a.idx()] = m.add_vertex({p[0], p[1], zb});
      m.set_color(below[a.idx()], m.color(a));
    }
    cx /= static_cast<double>(loop.size());
    cy /= static_cast<double>(loop.size());
    // Horizontal outward normals of the wall vertices: the average of the two wall directions at the vertex.
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const auto h = loop[k], g = loop[(k + loop.size() - 1) % loop.size()];
      const auto a = m.from_vertex_handle(h);
      const auto d1 = m.point(m.to_vertex_handle(h)) - m.point(a), d0 = m.point(a) - m.point(m.from_vertex_handle(g));
      // A boundary half-edge of an upward surface runs clockwise seen from +z; outward is to its left.
      OpenMesh::Vec3f n(-(d0[1] + d1[1]), d0[0] + d1[0], 0.0f);
      const float len = n.norm();
      m.set_normal(below[a.idx()], len > 0.0f ? n / len : OpenMesh::Vec3f(0, 0, -1));
    }
    const auto centre = m.add_vertex({static_cast<float>(cx), static_cast<float>(cy), zb});
    m.set_normal(centre, {0.0f, 0.0f, -1.0f});
    m.set_color(centre, m.color(m.from_vertex_handle(loop.front())));
    for (auto h : loop) {
      const auto a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
      m.add_face(a, b, below[b.idx()]);  // uses the free half-edge a -> b
      m.add_face(a, below[b.idx()], below[a.idx()]);
    }
    for (auto h : loop) {
      const auto a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
      m.add_face(below[a.idx()], below[b.idx()], centre);
    }
  }
  m.update_face_normals();
  return result;
}

}  // namespace orogen
