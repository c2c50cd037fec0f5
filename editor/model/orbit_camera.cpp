#include "editor/model/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace orogen::editor {

namespace {
constexpr double kMaxPitch = 1.55;  // just short of straight down, where yaw would be undefined
}

glm::dvec3 OrbitCamera::forward() const {
  return {std::sin(yaw) * std::cos(pitch) * 1.0, std::cos(yaw) * std::cos(pitch), -std::sin(pitch)};
}

glm::dvec3 OrbitCamera::eye() const { return target - forward() * distance; }

glm::mat4 OrbitCamera::view() const { return glm::mat4(glm::lookAt(eye(), target, glm::dvec3(0.0, 0.0, 1.0))); }

glm::mat4 OrbitCamera::projection(double aspect) const {
  const double near_plane = std::max(0.01, distance * 0.01);
  const double far_plane = distance * 100.0 + 1.0;
  return glm::mat4(glm::perspective(fov_y, std::max(aspect, 1e-3), near_plane, far_plane));
}

void OrbitCamera::orbit(glm::dvec2 d) {
  yaw += d.x * 0.008;
  pitch = std::clamp(pitch + d.y * 0.008, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(glm::dvec2 d, double viewport_height) {
  const double world_per_pixel = 2.0 * distance * std::tan(fov_y * 0.5) / std::max(1.0, viewport_height);
  const glm::dvec3 f = forward();
  const glm::dvec3 right = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, f);
  target += (-d.x * right + d.y * up) * world_per_pixel;
}

void OrbitCamera::zoom(double notches) { distance = std::clamp(distance * std::pow(0.85, notches), 1e-2, 1e8); }

void OrbitCamera::frame(glm::dvec3 lo, glm::dvec3 hi, double aspect) {
  target = (lo + hi) * 0.5;
  const glm::dvec3 f = forward();
  const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1)));
  const glm::dvec3 u = glm::cross(r, f);
  const double tan_y = std::tan(fov_y * 0.5) / 1.08, tan_x = tan_y * std::max(aspect, 1e-3);  // 8% margin
  // A corner at (x, y) across the view and z along it is in view from distance d when
  // |x| <= (d + z) tan_x and |y| <= (d + z) tan_y.
  double d = 1e-3;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 c = glm::dvec3((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z) - target;
    const double x = glm::dot(c, r), y = glm::dot(c, u), z = glm::dot(c, f);
    d = std::max({d, std::abs(x) / tan_x - z, std::abs(y) / tan_y - z});
  }
  distance = d;
}

}  // namespace orogen::editor
