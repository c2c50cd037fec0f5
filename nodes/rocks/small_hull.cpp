// A convex hull for small point sets (tens to hundreds of points): incremental insertion (Clarkson & Shor
// 1989; Barber, Dobkin & Huhdanpaa 1996 for the horizon construction) with a flat face array, which beats a
// general-purpose hull at this size. Faces are re-checked at the end (every edge shared by exactly two faces,
// F = 2V - 4); a set on which the floating-point visibility tests produced anything else is handed to CGAL.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "nodes/rocks/hull_rock.h"

namespace orogen::rocks {
namespace {

struct Face {
  int v[3];
  glm::dvec3 n;  // unit outward normal
  double d;      // plane offset: dot(n, x) = d on the face
};

bool make_face(Face& f, const std::vector<glm::dvec3>& p, int a, int b, int c) {
  f.v[0] = a, f.v[1] = b, f.v[2] = c;
  const glm::dvec3 n = glm::cross(p[static_cast<std::size_t>(b)] - p[static_cast<std::size_t>(a)],
                                  p[static_cast<std::size_t>(c)] - p[static_cast<std::size_t>(a)]);
  const double l = glm::length(n);
  if (!(l > 0.0)) return false;
  f.n = n / l;
  f.d = glm::dot(f.n, p[static_cast<std::size_t>(a)]);
  return true;
}

struct Degenerate {};
struct Inconsistent {};

Hull incremental(const std::vector<glm::dvec3>& p) {
  const int n = static_cast<int>(p.size());
  glm::dvec3 lo(p[0]), hi(p[0]);
  for (const auto& q : p) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double scale = std::max(glm::length(hi - lo), 1e-300);
  if (!std::isfinite(scale)) throw std::invalid_argument("the points are not finite");
  const double eps = 1e-11 * scale;

  // Initial tetrahedron: the farthest pair among the axis extremes, the farthest point from their line, the
  // farthest from their plane.
  int ext[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      if (p[static_cast<std::size_t>(i)][a] < p[static_cast<std::size_t>(ext[2 * a])][a]) ext[2 * a] = i;
      if (p[static_cast<std::size_t>(i)][a] > p[static_cast<std::size_t>(ext[2 * a + 1])][a]) ext[2 * a + 1] = i;
    }
  int i0 = 0, i1 = 0;
  double best = -1.0;
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b) {
      const double d = glm::length(p[static_cast<std::size_t>(ext[a])] - p[static_cast<std::size_t>(ext[b])]);
      if (d > best) best = d, i0 = ext[a], i1 = ext[b];
    }
  if (!(best > eps)) throw Degenerate{};
  const glm::dvec3 axis = glm::normalize(p[static_cast<std::size_t>(i1)] - p[static_cast<std::size_t>(i0)]);
  int i2 = -1;
  best = eps;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 r = p[static_cast<std::size_t>(i)] - p[static_cast<std::size_t>(i0)];
    const double d = glm::length(r - glm::dot(r, axis) * axis);
    if (d > best) best = d, i2 = i;
  }
  if (i2 < 0) throw Degenerate{};
  Face base;
  if (!make_face(base, p, i0, i1, i2)) throw Degenerate{};
  int i3 = -1;
  best = eps;
  for (int i = 0; i < n; ++i) {
    const double d = std::abs(glm::dot(base.n, p[static_cast<std::size_t>(i)]) - base.d);
    if (d > best) best = d, i3 = i;
  }
  if (i3 < 0) throw Degenerate{};
  if (glm::dot(base.n, p[static_cast<std::size_t>(i3)]) - base.d > 0.0) std::swap(i1, i2);  // i3 behind (i0 i1 i2)

  std::vector<Face> faces(4);
  faces.reserve(static_cast<std::size_t>(2 * n + 8));
  if (!make_face(faces[0], p, i0, i1, i2) || !make_face(faces[1], p, i0, i3, i1) ||
      !make_face(faces[2], p, i1, i3, i2) || !make_face(faces[3], p, i2, i3, i0))
    throw Degenerate{};

  std::vector<int> visible;
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < n; ++i) {
    if (i == i0 || i == i1 || i == i2 || i == i3) continue;
    const glm::dvec3& q = p[static_cast<std::size_t>(i)];
    visible.clear();
    for (int f = 0; f < static_cast<int>(faces.size()); ++f)
      if (glm::dot(faces[static_cast<std::size_t>(f)].n, q) - faces[static_cast<std::size_t>(f)].d > eps)
        visible.push_back(f);
    if (visible.empty()) continue;
    edges.clear();
    for (int f : visible)
      for (int k = 0; k < 3; ++k)
        edges.emplace_back(faces[static_cast<std::size_t>(f)].v[k], faces[static_cast<std::size_t>(f)].v[(k + 1) % 3]);
    // Remove the visible faces in place (from the highest index, so a face moved down is never visible).
    for (auto it = visible.rbegin(); it != visible.rend(); ++it) {
      faces[static_cast<std::size_t>(*it)] = faces.back();
      faces.pop_back();
    }
    for (const auto& [a, b] : edges) {
      bool inner = false;
      for (const auto& [c, d] : edges)
        if (c == b && d == a) {
          inner = true;
          break;
        }
      if (inner) continue;
      Face nf;
      if (!make_face(nf, p, a, b, i)) throw Inconsistent{};
      faces.push_back(nf);
    }
  }

  // Check: a closed surface, every directed edge once with its twin, and F = 2V - 4.
  Hull h;
  std::vector<int> index(static_cast<std::size_t>(n), -1);
  edges.clear();
  for (const Face& f : faces)
    for (int k = 0; k < 3; ++k) {
      edges.emplace_back(f.v[k], f.v[(k + 1) % 3]);
      if (index[static_cast<std::size_t>(f.v[k])] < 0) {
        index[static_cast<std::size_t>(f.v[k])] = static_cast<int>(h.vertices.size());
        h.vertices.push_back(p[static_cast<std::size_t>(f.v[k])]);
      }
    }
  if (faces.size() != 2 * h.vertices.size() - 4) throw Inconsistent{};
  std::vector<std::uint8_t> used(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0);
  for (const auto& [a, b] : edges) {
    auto& u = used[static_cast<std::size_t>(a) * static_cast<std::size_t>(n) + static_cast<std::size_t>(b)];
    if (u) throw Inconsistent{};  // a directed edge twice: not a 2-manifold
    u = 1;
  }
  for (const auto& [a, b] : edges)
    if (!used[static_cast<std::size_t>(b) * static_cast<std::size_t>(n) + static_cast<std::size_t>(a)])
      throw Inconsistent{};
  h.faces.reserve(faces.size());
  for (const Face& f : faces)
    h.faces.push_back({index[static_cast<std::size_t>(f.v[0])], index[static_cast<std::size_t>(f.v[1])],
                       index[static_cast<std::size_t>(f.v[2])]});
  return h;
}

}  // namespace

Hull convex_hull_small(const std::vector<glm::dvec3>& points) {
  if (points.size() < 4) throw std::invalid_argument("a convex hull needs at least 4 points");
  try {
    return incremental(points);
  } catch (const Degenerate&) {
    throw std::invalid_argument("the points span less than three dimensions");
  } catch (const Inconsistent&) {
    return convex_hull_cgal(points);  // near-degenerate input: the exact predicates decide
  }
}

Hull convex_hull(const std::vector<glm::dvec3>& points) {
  return points.size() <= 512 ? convex_hull_small(points) : convex_hull_cgal(points);
}

}  // namespace orogen::rocks
