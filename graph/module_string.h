#pragma once
// A bracketed, parametric L-system word (Prusinkiewicz & Lindenmayer 1990, The Algorithmic Beauty of
// Plants): a sequence of modules, each a one-character symbol with zero or more real parameters, such as
// F(1.5,0.2)[+(30)A]. Produced by LSystem, consumed by Turtle3D.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace orogen {

struct ModuleString {
  std::vector<char> symbols;              // one per module (printable ASCII)
  std::vector<std::uint32_t> offsets{0};  // size() + 1 entries: module k's parameters are params[offsets[k] ..
                                          // offsets[k + 1])
  std::vector<float> params;

  std::size_t size() const { return symbols.size(); }
  std::size_t param_count(std::size_t k) const { return offsets[k + 1] - offsets[k]; }
  std::span<const float> params_of(std::size_t k) const {
    return {params.data() + offsets[k], params.data() + offsets[k + 1]};
  }
  float param(std::size_t k, std::size_t i, float fallback) const {
    return i < param_count(k) ? params[offsets[k] + i] : fallback;
  }
  void clear();
  void append(char symbol, std::span<const float> values = {});
  // The word in ABOP notation: symbols, parameters in parentheses separated by commas (shortest
  // round-trip float text), e.g. "F(1.5,2)[+A]".
  std::string text() const;
  // Throws std::logic_error if the offsets are not a non-decreasing sequence ending at params.size().
  void check_consistent() const;
  std::size_t byte_size() const;
};

using ModuleStringPtr = std::shared_ptr<const ModuleString>;

}  // namespace orogen
