#include "graph/curves.h"

#include <stdexcept>

namespace orogen {

std::size_t Curves::vertex_count() const {
  std::size_t n = 0;
  for (const auto& c : curves) n += c.points.size();
  return n;
}

void Curves::check_consistent() const {
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const auto& c = curves[k];
    if (c.width.size() != c.points.size())
      throw std::logic_error("Curves: curve " + std::to_string(k) + " width count differs from point count");
    for (const auto& [name, values] : c.attributes)
      if (values.size() != c.points.size())
        throw std::logic_error("Curves: curve " + std::to_string(k) + " attribute '" + name + "' has the wrong size");
    if (c.parent < -1 || c.parent >= static_cast<int>(curves.size()))
      throw std::logic_error("Curves: curve " + std::to_string(k) + " has an invalid parent");
  }
}

std::size_t Curves::byte_size() const {
  std::size_t bytes = sizeof(*this);
  for (const auto& c : curves) {
    bytes += sizeof(Curve) + c.points.size() * (sizeof(glm::vec3) + sizeof(float));
    for (const auto& [name, values] : c.attributes) bytes += name.size() + values.size() * sizeof(float);
  }
  return bytes;
}

}  // namespace orogen
