#include "nodes/plants/plant_sprite.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::plants {
namespace {

// A quad in the drawing plane (x, z): corners in order around it, and its colour.
struct Quad {
  glm::dvec2 c[4];
  bool leaf;
};

}  // namespace

Mesh plant_sprite(const ModuleString& word, const PlantSpriteOptions& o, PlantSpriteStats* stats) {
  struct State {
    glm::dvec2 position{0.0};  // (x, z)
    double heading = 0.0;      // radians from +z, positive towards -x (a left turn seen from -y)
    double width = 0.0;
  };
  constexpr double kDegree = std::numbers::pi / 180.0;
  State st;
  st.width = o.width;
  std::vector<State> stack;
  std::vector<Quad> quads;
  const int planes = o.crossed ? 2 : 1;
  const std::size_t budget_quads = o.max_triangles / (2 * static_cast<std::size_t>(planes));
  PlantSpriteStats s;
  auto direction = [](double heading) { return glm::dvec2(-std::sin(heading), std::cos(heading)); };
  auto add = [&](const Quad& q) {
    if (quads.size() >= budget_quads)
      throw std::invalid_argument("the plant needs more than max_triangles = " + std::to_string(o.max_triangles) +
                                  " triangles: raise it, or derive fewer modules");
    quads.push_back(q);
  };

  const std::size_t n = word.size();
  for (std::size_t k = 0; k < n; ++k) {
    if ((k & 8191) == 8191 && o.should_stop && o.should_stop()) break;
    const char sym = word.symbols[k];
    auto p = [&](double fallback) {
      return word.param_count(k) > 0 ? static_cast<double>(word.params[word.offsets[k]]) : fallback;
    };
    if (sym == 'F') {
      const glm::dvec2 h = direction(st.heading);
      const glm::dvec2 side(h.y, -h.x);  // to the right of the heading
      const glm::dvec2 a = st.position, b = st.position + h * p(o.step);
      const glm::dvec2 w = side * (0.5 * st.width);
      add({{a - w, a + w, b + w, b - w}, false});
      st.position = b;
      ++s.segments;
    } else if (sym == 'f') {
      st.position += direction(st.heading) * p(o.step);
    } else if (sym == '+') {
      st.heading += p(o.angle) * kDegree;
    } else if (sym == '-') {
      st.heading -= p(o.angle) * kDegree;
    } else if (sym == '|') {
      st.heading += std::numbers::pi;
    } else if (sym == '[') {
      stack.push_back(st);
      st.width *= o.taper;
    } else if (sym == ']') {
      if (!stack.empty()) {
        st = stack.back();
        stack.pop_back();
      }
    } else if (sym == '!') {
      st.width = std::max(0.0, p(st.width));
    } else if (o.leaf_symbol != '\0' && sym == o.leaf_symbol) {
      // A rhombus from the turtle's position along its heading: length s, width s / 2.
      const double size = p(o.leaf_size);
      const glm::dvec2 h = direction(st.heading);
      const glm::dvec2 side(h.y, -h.x);
      const glm::dvec2 a = st.position, mid = st.position + h * (0.5 * size), tip = st.position + h * size;
      add({{a, mid + side * (0.25 * size), tip, mid - side * (0.25 * size)}, true});
      ++s.leaves;
    }
  }

  // Lift so the lowest corner is at z = 0 (non-finite corners are left to the checks of the consumers).
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Quad& q : quads)
    for (const auto& c : q.c)
      if (std::isfinite(c.y)) lo = std::min(lo, c.y), hi = std::max(hi, c.y);
  const double lift = std::isfinite(lo) ? -lo : 0.0;
  s.height = std::isfinite(lo) ? hi - lo : 0.0;

  Mesh out;
  TriMesh& m = out.mesh;
  m.reserve(quads.size() * 4 * planes, quads.size() * 5 * planes, quads.size() * 2 * planes);
  for (int plane = 0; plane < planes; ++plane) {
    // The x-z plane faces -y (a viewer looking along +y sees the drawing as written); the crossed copy
    // is the same drawing turned 90 degrees about z (x -> y), facing +x.
    const OpenMesh::Vec3f normal = plane == 0 ? OpenMesh::Vec3f(0, -1, 0) : OpenMesh::Vec3f(1, 0, 0);
    for (const Quad& q : quads) {
      TriMesh::VertexHandle v[4];
      const glm::vec4& c = q.leaf ? o.leaf_color : o.color;
      for (int i = 0; i < 4; ++i) {
        const float u = static_cast<float>(q.c[i].x), z = static_cast<float>(q.c[i].y + lift);
        v[i] = m.add_vertex(plane == 0 ? OpenMesh::Vec3f(u, 0, z) : OpenMesh::Vec3f(0, u, z));
        m.set_normal(v[i], normal);
        m.set_color(v[i], OpenMesh::Vec4f(c.r, c.g, c.b, c.a));
      }
      // Corners run a-w, a+w, b+w, b-w (counter-clockwise seen from the normal's side in both planes).
      const auto f0 = m.add_face(v[0], v[1], v[2]);
      const auto f1 = m.add_face(v[0], v[2], v[3]);
      if (f0.is_valid()) m.set_normal(f0, normal);
      if (f1.is_valid()) m.set_normal(f1, normal);
    }
  }
  if (stats) *stats = s;
  return out;
}

}  // namespace orogen::plants
