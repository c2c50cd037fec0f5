#include "graph/scene.h"

#include <stdexcept>
#include <string>

#include "graph/mesh.h"

namespace orogen {

std::size_t Scene::count(std::int32_t cls) const {
  if (!instances) return 0;
  std::size_t n = 0;
  for (const std::int32_t c : instances->class_id) n += c == cls ? 1 : 0;
  return n;
}

void Scene::check_consistent() const {
  if (!instances) throw std::logic_error("Scene: no instances array");
  instances->check_consistent();
  for (const auto& [cls, c] : classes)
    if (!c.mesh) throw std::logic_error("Scene: class " + std::to_string(cls) + " has no mesh");
  for (const std::int32_t cls : instances->class_id)
    if (!classes.count(cls))
      throw std::logic_error("Scene: instances of class " + std::to_string(cls) + " have no mesh");
}

std::size_t Scene::byte_size() const {
  std::size_t bytes = sizeof(*this) + (instances ? instances->byte_size() : 0);
  for (const auto& [cls, c] : classes) bytes += sizeof(c) + c.name.size() + (c.mesh ? c.mesh->byte_size() : 0);
  return bytes;
}

}  // namespace orogen
