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
  // The points `keep` says to keep (a predicate on the index), in order, with every array and attribute.
  template <class Keep>
  Points subset(Keep keep) const {
    Points out;
    for (const auto& [name, values] : attributes) out.attributes[name];
    for (std::size_t i = 0; i < size(); ++i) {
      if (!keep(i)) continue;
      out.position.push_back(position[i]);
      out.rotation.push_back(rotation[i]);
      out.scale.push_back(scale[i]);
      out.class_id.push_back(class_id[i]);
      auto from = attributes.begin();  // the same names in the same order
      for (auto& [name, values] : out.attributes) values.push_back((from++)->second[i]);
    }
    return out;
  }
  // Throws std::logic_error if some array's size differs from size().
  void check_consistent() const;
  std::size_t byte_size() const;
};

using PointsPtr = std::shared_ptr<const Points>;

}  // namespace orogen
