#include "graph/module_string.h"

#include <charconv>
#include <stdexcept>

namespace orogen {

void ModuleString::clear() {
  symbols.clear();
  offsets.assign(1, 0);
  params.clear();
}

void ModuleString::append(char symbol, std::span<const float> values) {
  symbols.push_back(symbol);
  params.insert(params.end(), values.begin(), values.end());
  offsets.push_back(static_cast<std::uint32_t>(params.size()));
}

std::string ModuleString::text() const {
  std::string out;
  out.reserve(symbols.size() + params.size() * 4);
  char buffer[32];
  for (std::size_t k = 0; k < symbols.size(); ++k) {
    out.push_back(symbols[k]);
    const std::size_t n = param_count(k);
    if (n == 0) continue;
    out.push_back('(');
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out.push_back(',');
      const auto r = std::to_chars(buffer, buffer + sizeof buffer, params[offsets[k] + i]);
      out.append(buffer, r.ptr);
    }
    out.push_back(')');
  }
  return out;
}

void ModuleString::check_consistent() const {
  if (offsets.size() != symbols.size() + 1 || offsets.front() != 0 || offsets.back() != params.size())
    throw std::logic_error("ModuleString: offsets do not match the symbols and parameters");
  for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
    if (offsets[k] > offsets[k + 1]) throw std::logic_error("ModuleString: decreasing parameter offsets");
}

std::size_t ModuleString::byte_size() const {
  return sizeof(*this) + symbols.size() + offsets.size() * sizeof(std::uint32_t) + params.size() * sizeof(float);
}

}  // namespace orogen
