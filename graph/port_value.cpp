#include "graph/port_value.h"

#include "graph/mesh.h"

namespace orogen {

PortType port_type_of(const PortValue& v) { return static_cast<PortType>(v.index() - 1); }

bool has_value(const PortValue& v) {
  return std::visit(
      [](const auto& p) {
        if constexpr (std::is_same_v<std::decay_t<decltype(p)>, std::monostate>)
          return false;
        else
          return p != nullptr;
      },
      v);
}

std::size_t byte_size(const PortValue& v) {
  return std::visit(
      [](const auto& p) -> std::size_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(p)>, std::monostate>)
          return 0;
        else
          return p ? p->byte_size() : 0;
      },
      v);
}

}  // namespace orogen
