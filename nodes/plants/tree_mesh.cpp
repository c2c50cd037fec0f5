#include "nodes/plants/tree_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "nodes/rocks/hull_rock.h"

namespace orogen::plants {
namespace {

using V3 = glm::dvec3;

OpenMesh::Vec3f to_om(const V3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

// Any unit vector perpendicular to unit t.
V3 perpendicular(const V3& t) {
  const V3 a = std::abs(t.x) < 0.9 ? V3(1, 0, 0) : V3(0, 1, 0);
  return glm::normalize(glm::cross(t, a));
}

struct Branch {
  std::vector<V3> p;
  std::vector<double> radius;
  std::vector<glm::vec3> color;
};

// The curve's distinct consecutive points (zero-length segments removed).
Branch prepare(const Curve& c) {
  Branch b;
  const auto find = [&](const char* name) -> const std::vector<float>* {
    const auto it = c.attributes.find(name);
    return it != c.attributes.end() && it->second.size() == c.points.size() ? &it->second : nullptr;
  };
  const auto *r = find("r"), *g = find("g"), *bl = find("b");
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const V3 p(c.points[i]);
    if (!b.p.empty() && glm::length(p - b.p.back()) < 1e-7) {
      b.radius.back() = std::max(b.radius.back(), 0.5 * static_cast<double>(c.width[i]));
      continue;
    }
    b.p.push_back(p);
    b.radius.push_back(std::max(0.0, 0.5 * static_cast<double>(i < c.width.size() ? c.width[i] : 0.0f)));
    b.color.emplace_back(r ? (*r)[i] : 0.5f, g ? (*g)[i] : 0.5f, bl ? (*bl)[i] : 0.5f);
  }
  return b;
}

std::size_t tube_triangles(std::size_t points, int k) {
  return points >= 2 ? 2 * static_cast<std::size_t>(k) * points : 0;
}

// Returns the ring normal at the last point (children continue from it, so their rings line up).
V3 add_tube(TriMesh& m, const Branch& b, int k, const V3* start_normal) {
  const std::size_t n = b.p.size();
  std::vector<V3> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const V3 in = i > 0 ? glm::normalize(b.p[i] - b.p[i - 1]) : V3(0.0);
    const V3 out = i + 1 < n ? glm::normalize(b.p[i + 1] - b.p[i]) : V3(0.0);
    V3 s = in + out;
    if (glm::length(s) < 1e-6) s = i + 1 < n ? out : in;
    t[i] = glm::normalize(s);
  }
  std::vector<TriMesh::VertexHandle> ring(static_cast<std::size_t>(k) * n);
  V3 normal = perpendicular(t[0]);
  if (start_normal) {
    const V3 q = *start_normal - glm::dot(*start_normal, t[0]) * t[0];
    if (glm::length(q) > 1e-3) normal = glm::normalize(q);
  }
  double arc = 0.0;
  const bool uv = m.has_vertex_texcoords2D();
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) {
      arc += glm::length(b.p[i] - b.p[i - 1]);
      // Parallel transport: project the previous normal onto the new ring plane.
      V3 q = normal - glm::dot(normal, t[i]) * t[i];
      normal = glm::length(q) > 1e-6 ? glm::normalize(q) : perpendicular(t[i]);
    }
    const V3 binormal = glm::cross(t[i], normal);
    const TriMesh::Color col(b.color[i].r, b.color[i].g, b.color[i].b, 1.0f);
    for (int j = 0; j < k; ++j) {
      const double a = 2.0 * std::numbers::pi * j / k;
      const V3 radial = std::cos(a) * normal + std::sin(a) * binormal;
      const auto vh = m.add_vertex(to_om(b.p[i] + b.radius[i] * radial));
      m.set_normal(vh, to_om(radial));
      m.set_color(vh, col);
      if (uv) m.set_texcoord2D(vh, {static_cast<float>(j) / static_cast<float>(k), static_cast<float>(arc)});
      ring[i * static_cast<std::size_t>(k) + static_cast<std::size_t>(j)] = vh;
    }
  }
  auto at = [&](std::size_t i, int j) {
    return ring[i * static_cast<std::size_t>(k) + static_cast<std::size_t>((j + k) % k)];
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (int j = 0; j < k; ++j) {
      m.add_face(at(i, j), at(i, j + 1), at(i + 1, j + 1));
      m.add_face(at(i, j), at(i + 1, j + 1), at(i + 1, j));
    }
  // Caps: fans around the end points.
  const auto base = m.add_vertex(to_om(b.p[0]));
  m.set_normal(base, to_om(-t[0]));
  m.set_color(base, TriMesh::Color(b.color[0].r, b.color[0].g, b.color[0].b, 1.0f));
  const auto tip = m.add_vertex(to_om(b.p[n - 1]));
  m.set_normal(tip, to_om(t[n - 1]));
  m.set_color(tip, TriMesh::Color(b.color[n - 1].r, b.color[n - 1].g, b.color[n - 1].b, 1.0f));
  if (uv) {
    m.set_texcoord2D(base, {0.5f, 0.0f});
    m.set_texcoord2D(tip, {0.5f, static_cast<float>(arc)});
  }
  for (int j = 0; j < k; ++j) {
    m.add_face(base, at(0, j + 1), at(0, j));
    m.add_face(tip, at(n - 1, j), at(n - 1, j + 1));
  }
  return normal;
}

void add_leaf_quad(TriMesh& m, const V3& p, const glm::dquat& q, double s, const TriMesh::Color& col) {
  const V3 h = q * V3(1, 0, 0), l = q * V3(0, 1, 0), u = q * V3(0, 0, 1);
  const V3 c[4] = {p, p + 0.5 * s * h - 0.3 * s * l, p + s * h, p + 0.5 * s * h + 0.3 * s * l};
  TriMesh::VertexHandle v[4];
  for (int i = 0; i < 4; ++i) {
    v[i] = m.add_vertex(to_om(c[i]));
    m.set_normal(v[i], to_om(u));
    m.set_color(v[i], col);
    if (m.has_vertex_texcoords2D())
      m.set_texcoord2D(
          v[i], {static_cast<float>(glm::dot(c[i] - p, l) / s + 0.5), static_cast<float>(glm::dot(c[i] - p, h) / s)});
  }
  // Counter-clockwise seen from the leaf's up axis: the winding whose normal agrees with u.
  const V3 nrm = glm::cross(c[1] - c[0], c[2] - c[0]);
  if (glm::dot(nrm, u) >= 0.0) {
    m.add_face(v[0], v[1], v[2]);
    m.add_face(v[0], v[2], v[3]);
  } else {
    m.add_face(v[0], v[2], v[1]);
    m.add_face(v[0], v[3], v[2]);
  }
}

}  // namespace

Mesh tree_mesh(const Curves& skeleton, const Points* leaves, const TreeMeshOptions& o, TreeMeshStats* stats) {
  const std::size_t nc = skeleton.curves.size();
  std::vector<Branch> branches(nc);
  for (std::size_t c = 0; c < nc; ++c) branches[c] = prepare(skeleton.curves[c]);
  // Continuations: the widest child that starts where its parent ends takes the parent's end radius at its
  // start, so the axis tapers through the joint instead of stepping down at the parent's end cap.
  {
    std::vector<int> widest(nc, -1);
    for (std::size_t c = 0; c < nc; ++c) {
      const int parent = skeleton.curves[c].parent;
      if (parent < 0 || static_cast<std::size_t>(parent) >= nc || branches[c].p.size() < 2) continue;
      const Branch& pb = branches[static_cast<std::size_t>(parent)];
      if (pb.p.size() < 2) continue;
      const double tol = 1e-6 * std::max(1.0, glm::length(pb.p.back()));
      if (glm::length(branches[c].p.front() - pb.p.back()) > tol) continue;
      int& w = widest[static_cast<std::size_t>(parent)];
      if (w < 0 || branches[c].radius.front() > branches[static_cast<std::size_t>(w)].radius.front())
        w = static_cast<int>(c);
    }
    for (std::size_t p = 0; p < nc; ++p)
      if (widest[p] >= 0) {
        auto& r = branches[static_cast<std::size_t>(widest[p])].radius.front();
        r = std::max(r, branches[p].radius.back());
      }
  }
  const std::size_t nl = leaves && o.leaf_shape != LeafShape::None ? leaves->size() : 0;
  const std::size_t leaf_tris = o.leaf_shape == LeafShape::Rock ? static_cast<std::size_t>(2 * o.rock_points - 4) : 2;

  std::vector<char> keep_curve(nc, 1), keep_leaf(nl, 1);
  auto total = [&](int k) {
    std::size_t t = 0;
    for (std::size_t c = 0; c < nc; ++c)
      if (keep_curve[c]) t += tube_triangles(branches[c].p.size(), k);
    for (std::size_t l = 0; l < nl; ++l)
      if (keep_leaf[l]) t += leaf_tris;
    return t;
  };
  int k = std::clamp(o.sides, 3, 64);
  while (k > 3 && total(k) > o.max_triangles) --k;
  TreeMeshStats st;
  if (total(k) > o.max_triangles) {
    // Drop twigs (curves without remaining children), thinnest first, with the leaves on them.
    std::vector<int> children(nc, 0);
    for (std::size_t c = 0; c < nc; ++c)
      if (skeleton.curves[c].parent >= 0) ++children[static_cast<std::size_t>(skeleton.curves[c].parent)];
    std::vector<std::vector<std::size_t>> leaves_on(nc);
    std::vector<std::size_t> free_leaves;
    const std::vector<float>* branch_of = nullptr;
    if (nl) {
      const auto it = leaves->attributes.find("branch");
      if (it != leaves->attributes.end()) branch_of = &it->second;
    }
    for (std::size_t l = 0; l < nl; ++l) {
      const int b = branch_of ? static_cast<int>((*branch_of)[l]) : -1;
      if (b >= 0 && static_cast<std::size_t>(b) < nc)
        leaves_on[static_cast<std::size_t>(b)].push_back(l);
      else
        free_leaves.push_back(l);
    }
    auto width_of = [&](std::size_t c) {
      double w = 0.0;
      for (double r : branches[c].radius) w = std::max(w, r);
      return w;
    };
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (std::size_t c = 0; c < nc; ++c)
      if (children[c] == 0) heap.push({width_of(c), c});
    std::size_t t = total(k);
    // Leaves not attached to a branch go first (from the last).
    while (t > o.max_triangles && !free_leaves.empty()) {
      keep_leaf[free_leaves.back()] = 0;
      free_leaves.pop_back();
      t -= leaf_tris;
      ++st.dropped_leaves;
    }
    while (t > o.max_triangles && !heap.empty()) {
      const std::size_t c = heap.top().second;
      heap.pop();
      keep_curve[c] = 0;
      ++st.dropped_branches;
      t -= tube_triangles(branches[c].p.size(), k);
      for (std::size_t l : leaves_on[c]) {
        keep_leaf[l] = 0;
        t -= leaf_tris;
        ++st.dropped_leaves;
      }
      const int parent = skeleton.curves[c].parent;
      if (parent >= 0 && --children[static_cast<std::size_t>(parent)] == 0)
        heap.push({width_of(static_cast<std::size_t>(parent)), static_cast<std::size_t>(parent)});
    }
  }
  st.sides = k;

  Mesh out;
  TriMesh& m = out.mesh;
  m.request_vertex_texcoords2D();
  std::vector<V3> end_normal(nc, V3(0.0));
  for (std::size_t c = 0; c < nc; ++c) {
    if ((c & 255) == 255 && o.should_stop && o.should_stop()) break;
    if (!keep_curve[c] || branches[c].p.size() < 2) continue;
    const int parent = skeleton.curves[c].parent;
    // Parents come before their children (the turtle numbers branches as it starts them).
    const bool from_parent =
        parent >= 0 && static_cast<std::size_t>(parent) < c && end_normal[static_cast<std::size_t>(parent)] != V3(0.0);
    end_normal[c] = add_tube(m, branches[c], k, from_parent ? &end_normal[static_cast<std::size_t>(parent)] : nullptr);
  }
  st.branch_triangles = m.n_faces();
  for (std::size_t l = 0; l < nl; ++l) {
    if (!keep_leaf[l]) continue;
    const auto attr = [&](const char* name, float fallback) {
      const auto it = leaves->attributes.find(name);
      return it != leaves->attributes.end() ? it->second[l] : fallback;
    };
    const TriMesh::Color col(attr("r", 0.1f), attr("g", 0.35f), attr("b", 0.05f), 1.0f);
    const V3 p(leaves->position[l]);
    const glm::dquat q(leaves->rotation[l]);
    const double s = leaves->scale[l].x;
    if (o.leaf_shape == LeafShape::Quad) {
      add_leaf_quad(m, p, q, s, col);
    } else {
      rocks::HullRockOptions r;
      r.points = o.rock_points;
      r.radii = {0.5 * s, 0.3 * s, 0.12 * s};
      r.sigma = 0.05 * s;
      r.seed = o.seed;
      r.variant = l;
      rocks::append_hull_rock(m, r, p + q * V3(0.5 * s, 0, 0), q, col);
    }
  }
  st.leaf_triangles = m.n_faces() - st.branch_triangles;
  m.update_face_normals();
  if (stats) *stats = st;
  return out;
}

}  // namespace orogen::plants
