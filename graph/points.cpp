#include "graph/points.h"

#include <stdexcept>

namespace orogen {

std::size_t Points::add(glm::vec3 p, std::int32_t cls) {
  position.push_back(p);
  rotation.emplace_back(1.0f, 0.0f, 0.0f, 0.0f);
  scale.emplace_back(1.0f);
  class_id.push_back(cls);
  for (auto& [name, values] : attributes) values.push_back(0.0f);
  return position.size() - 1;
}

std::vector<float>& Points::attribute(const std::string& name, float fill) {
  auto [it, inserted] = attributes.try_emplace(name);
  if (inserted) it->second.assign(size(), fill);
  return it->second;
}

void Points::check_consistent() const {
  const auto n = size();
  if (rotation.size() != n || scale.size() != n || class_id.size() != n)
    throw std::logic_error("Points: per-point arrays differ in size");
  for (const auto& [name, values] : attributes)
    if (values.size() != n) throw std::logic_error("Points: attribute '" + name + "' has the wrong size");
}

std::size_t Points::byte_size() const {
  std::size_t bytes = sizeof(*this) + size() * (sizeof(glm::vec3) * 2 + sizeof(glm::quat) + sizeof(std::int32_t));
  for (const auto& [name, values] : attributes) bytes += name.size() + values.size() * sizeof(float);
  return bytes;
}

}  // namespace orogen
