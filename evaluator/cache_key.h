#pragma once
// 128-bit content address of a node result (XXH3-128 over a canonical byte stream).
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "graph/domain.h"
#include "graph/param_value.h"

namespace orogen {

struct CacheKey {
  std::uint64_t high = 0, low = 0;
  bool operator==(const CacheKey&) const = default;
  bool operator<(const CacheKey& o) const { return high != o.high ? high < o.high : low < o.low; }
  std::string hex() const;                       // 32 lowercase hex digits
  static CacheKey from_hex(std::string_view s);  // throws std::invalid_argument
};

struct CacheKeyHash {
  std::size_t operator()(const CacheKey& k) const {
    return static_cast<std::size_t>(k.low ^ (k.high * 0x9E3779B97F4A7C15ull));
  }
};

// Streaming canonical hasher: every value is written with a type tag (and strings with their length) so
// distinct inputs cannot produce the same byte stream; -0.0 is folded into 0.0.
class KeyHasher {
 public:
  KeyHasher();
  ~KeyHasher();
  KeyHasher(const KeyHasher&) = delete;
  KeyHasher& operator=(const KeyHasher&) = delete;

  KeyHasher& add(std::string_view s);
  KeyHasher& add(std::int64_t v);
  KeyHasher& add(std::uint64_t v);
  KeyHasher& add(double v);
  KeyHasher& add(bool v);
  KeyHasher& add(const CacheKey& k);
  KeyHasher& add(const Domain& d);
  KeyHasher& add(const ParamValue& v);
  CacheKey finish() const;

 private:
  void bytes(const void* data, std::size_t n);
  void* state_;
};

}  // namespace orogen
