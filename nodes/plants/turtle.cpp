#include "nodes/plants/turtle.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "nodes/common/color_space.h"

namespace orogen::plants {
namespace {

void orthonormalize(TurtleFrame& f) {
  f.heading = glm::normalize(f.heading);
  f.left = glm::normalize(f.left - glm::dot(f.left, f.heading) * f.heading);
  f.up = glm::cross(f.heading, f.left);
}

glm::dvec3 rodrigues(const glm::dvec3& v, const glm::dvec3& k, double c, double s) {
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0 - c);
}

struct OpenBranch {  // a curve under construction
  std::vector<float> r, g, b, depth;
};

}  // namespace

// An sRGB channel 0..255 (clamped) to linear 0..1.
double byte_to_linear(double v255) { return srgb_to_linear(v255 / 255.0); }

void rotate(TurtleFrame& f, int axis, double degrees) {
  const double a = degrees * std::numbers::pi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  const glm::dvec3 h = f.heading, l = f.left, u = f.up;
  switch (axis) {
    case 0:  // about up: turn left towards L
      f.heading = h * c + l * s;
      f.left = l * c - h * s;
      break;
    case 1:  // about left: pitch down towards -U
      f.heading = h * c - u * s;
      f.up = u * c + h * s;
      break;
    default:  // about heading: roll left (L towards U)
      f.left = l * c + u * s;
      f.up = u * c - l * s;
      break;
  }
  orthonormalize(f);
}

TurtleResult interpret(const ModuleString& word, const TurtleOptions& o) {
  struct State {
    TurtleFrame frame;
    double width;
    glm::dvec3 color;
    int curve;   // the branch being drawn (-1: none yet)
    bool fresh;  // the next F starts a new branch (child of `curve`)
    int depth;
  };
  TurtleResult result;
  std::vector<OpenBranch> extra;
  State st{TurtleFrame{}, o.width, o.color, -1, true, 0};
  std::vector<State> stack;
  const glm::dvec3 tropism = glm::length(o.tropism) > 0.0 ? glm::normalize(o.tropism) : glm::dvec3(0.0);
  const double inv_factor = o.width_factor > 0.0 ? 1.0 / o.width_factor : 1.0;

  auto add_point = [&](int curve) {
    Curve& c = result.skeleton.curves[static_cast<std::size_t>(curve)];
    OpenBranch& x = extra[static_cast<std::size_t>(curve)];
    c.points.push_back(glm::vec3(st.frame.position));
    c.width.push_back(static_cast<float>(st.width));
    x.r.push_back(static_cast<float>(st.color.r));
    x.g.push_back(static_cast<float>(st.color.g));
    x.b.push_back(static_cast<float>(st.color.b));
    x.depth.push_back(static_cast<float>(st.depth));
  };

  const std::size_t n = word.size();
  for (std::size_t k = 0; k < n; ++k) {
    if ((k & 8191) == 8191 && o.should_stop && o.should_stop()) break;
    const char sym = word.symbols[k];
    const std::size_t np = word.param_count(k);
    auto p = [&](std::size_t i, double fallback) {
      return i < np ? static_cast<double>(word.params[word.offsets[k] + i]) : fallback;
    };
    switch (sym) {
      case 'F': {
        if (st.fresh) {
          Curve c;
          c.parent = st.curve;
          result.skeleton.curves.push_back(std::move(c));
          extra.emplace_back();
          st.curve = static_cast<int>(result.skeleton.curves.size()) - 1;
          st.fresh = false;
          add_point(st.curve);
        }
        st.frame.position += st.frame.heading * p(0, o.step);
        add_point(st.curve);
        if (o.tropism_strength != 0.0 && tropism != glm::dvec3(0.0)) {
          const glm::dvec3 axis = glm::cross(st.frame.heading, tropism);
          const double len = glm::length(axis);
          if (len > 1e-12) {
            const double a = o.tropism_strength * len;
            const glm::dvec3 kx = axis / len;
            const double c = std::cos(a), s = std::sin(a);
            st.frame.heading = rodrigues(st.frame.heading, kx, c, s);
            st.frame.left = rodrigues(st.frame.left, kx, c, s);
            orthonormalize(st.frame);
          }
        }
        break;
      }
      case 'f':
        st.frame.position += st.frame.heading * p(0, o.step);
        st.fresh = true;
        st.curve = -1;  // a jump: the next branch is a new root
        break;
      case '+':
        rotate(st.frame, 0, p(0, o.angle));
        break;
      case '-':
        rotate(st.frame, 0, -p(0, o.angle));
        break;
      case '|':
        rotate(st.frame, 0, 180.0);
        break;
      case '&':
        rotate(st.frame, 1, p(0, o.angle));
        break;
      case '^':
        rotate(st.frame, 1, -p(0, o.angle));
        break;
      case '\\':
        rotate(st.frame, 2, p(0, o.angle));
        break;
      case '/':
        rotate(st.frame, 2, -p(0, o.angle));
        break;
      case '$': {
        const glm::dvec3 v(0.0, 0.0, 1.0);
        const glm::dvec3 l = glm::cross(v, st.frame.heading);
        if (glm::length(l) > 1e-9) {
          st.frame.left = glm::normalize(l);
          orthonormalize(st.frame);
        }
        break;
      }
      case '[':
        stack.push_back(st);
        st.fresh = true;
        ++st.depth;
        break;
      case ']':
        if (!stack.empty()) {
          st = stack.back();
          stack.pop_back();
        }
        break;
      case '#':
        if (np >= 3)
          st.color = {byte_to_linear(p(0, 0)), byte_to_linear(p(1, 0)), byte_to_linear(p(2, 0))};
        else if (np >= 1)
          st.color = glm::dvec3(byte_to_linear(p(0, 0)));
        break;
      case '<':
        st.width *= p(0, inv_factor);
        break;
      case '>':
        st.width *= p(0, o.width_factor);
        break;
      case '!':
        st.width = np >= 1 ? p(0, st.width) : st.width * o.width_factor;
        break;
      case 'L': {
        const double size = p(0, o.leaf_size);
        const glm::dvec3 color =
            np >= 4 ? glm::dvec3(byte_to_linear(p(1, 0)), byte_to_linear(p(2, 0)), byte_to_linear(p(3, 0)))
                    : o.leaf_color;
        auto& L = result.leaves;
        L.add(glm::vec3(st.frame.position));
        L.rotation.back() =
            glm::quat_cast(glm::mat3(glm::vec3(st.frame.heading), glm::vec3(st.frame.left), glm::vec3(st.frame.up)));
        L.scale.back() = glm::vec3(static_cast<float>(size));
        L.attribute("r").back() = static_cast<float>(color.r);
        L.attribute("g").back() = static_cast<float>(color.g);
        L.attribute("b").back() = static_cast<float>(color.b);
        L.attribute("branch", -1.0f).back() = static_cast<float>(st.curve);
        break;
      }
      default:
        break;
    }
  }
  for (std::size_t c = 0; c < extra.size(); ++c) {
    auto& attrs = result.skeleton.curves[c].attributes;
    attrs["r"] = std::move(extra[c].r);
    attrs["g"] = std::move(extra[c].g);
    attrs["b"] = std::move(extra[c].b);
    attrs["depth"] = std::move(extra[c].depth);
  }
  result.final_frame = st.frame;
  return result;
}

}  // namespace orogen::plants
