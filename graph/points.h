#pragma once
// A set of placed instances: scatter results, river sources, tree positions.
// Structure of arrays; every array has size() entries, every named attribute too.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace orogen {

struct Points {
  std::vector<glm::vec3> position;                       // world metres, z up
  std::vector<glm::quat> rotation;                       // orientation of the instance
  std::vector<glm::vec3> scale;                          // per-axis scale factor
  std::vector<std::int32_t> class_id;                    // species / object class
  std::map<std::string, std::vector<float>> attributes;  // named per-point floats (age, density, ...)

  std::size_t size() const { return position.size(); }
  // Appends a point with identity rotation, unit scale, class 0 and zero attributes.
  std::size_t add(glm::vec3 p, std::int32_t cls = 0);
  // Adds (or returns) a named attribute, filled with `fill` for existing points.
  std::vector<float>& attribute(const std::string& name, float fill = 0.0f);
  // Throws std::logic_error if some array's size differs from size().
  void check_consistent() const;
  std::size_t byte_size() const;
};

using PointsPtr = std::shared_ptr<const Points>;

}  // namespace orogen
