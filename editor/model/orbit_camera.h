#pragma once
// The 3D viewport's camera: orbits a target point (left drag), pans in the view plane (right or middle
// drag), dollies toward the target (wheel). World z is up.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace orogen::editor {

class OrbitCamera {
 public:
  glm::dvec3 target{0.0};
  double distance = 1000.0;
  double yaw = -0.6;   // radians around +z, 0 looks along +y
  double pitch = 0.6;  // radians above the horizon
  double fov_y = 0.7;  // radians

  glm::dvec3 eye() const;
  glm::dvec3 forward() const;  // unit, from eye to target
  glm::mat4 view() const;
  glm::mat4 projection(double aspect) const;  // near/far follow the distance

  // Mouse deltas in pixels; `viewport_height` converts pan pixels to world units at the target.
  void orbit(glm::dvec2 delta_pixels);
  void pan(glm::dvec2 delta_pixels, double viewport_height);
  void zoom(double notches);
  // Looks at the centre of a box from the distance at which all of its corners are in view (with a small
  // margin) for the current direction and the viewport's aspect ratio.
  void frame(glm::dvec3 min, glm::dvec3 max, double aspect = 1.0);
};

}  // namespace orogen::editor
