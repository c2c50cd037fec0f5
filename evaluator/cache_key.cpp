#include "evaluator/cache_key.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <type_traits>

#define XXH_STATIC_LINKING_ONLY  // for the size of XXH3_state_t
#include <xxhash.h>

namespace orogen {
namespace {

// One tag byte in front of every value, so e.g. the int 1 and the double 1.0, or a string "ab" followed by
// "c" and "a" followed by "bc", never produce the same stream.
enum Tag : unsigned char {
  kString = 's',
  kInt = 'i',
  kUInt = 'u',
  kDouble = 'd',
  kBool = 'b',
  kKey = 'k',
  kDomain = 'D',
  kParam = 'P',
};

// The XXH3-128 streaming state plus a small buffer: a key is built from many values of a few bytes each,
// and handing them to XXH3 in batches costs far less than one update call per value. The digest is the
// same as for one update per value.
struct HasherState {
  XXH3_state_t xxh;
  std::size_t used = 0;
  unsigned char buffer[512];

  void flush() {
    if (used) XXH3_128bits_update(&xxh, buffer, used);
    used = 0;
  }
};

HasherState* state_of(void* p) { return static_cast<HasherState*>(p); }

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string CacheKey::hex() const {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s(32, '0');
  for (int i = 0; i < 16; ++i) {
    s[static_cast<std::size_t>(15 - i)] = kDigits[(high >> (4 * i)) & 0xF];
    s[static_cast<std::size_t>(31 - i)] = kDigits[(low >> (4 * i)) & 0xF];
  }
  return s;
}

CacheKey CacheKey::from_hex(std::string_view s) {
  if (s.size() != 32) throw std::invalid_argument("a cache key has 32 hex digits, got '" + std::string(s) + "'");
  CacheKey k;
  for (std::size_t i = 0; i < 32; ++i) {
    const int d = hex_digit(s[i]);
    if (d < 0) throw std::invalid_argument("invalid hex digit in cache key '" + std::string(s) + "'");
    auto& half = i < 16 ? k.high : k.low;
    half = (half << 4) | static_cast<std::uint64_t>(d);
  }
  return k;
}

KeyHasher::KeyHasher() : state_(new HasherState) { XXH3_128bits_reset(&state_of(state_)->xxh); }

KeyHasher::~KeyHasher() { delete state_of(state_); }

void KeyHasher::bytes(const void* data, std::size_t n) {
  if (n == 0) return;
  HasherState& s = *state_of(state_);
  if (s.used + n > sizeof s.buffer) {
    s.flush();
    if (n > sizeof s.buffer) {
      XXH3_128bits_update(&s.xxh, data, n);
      return;
    }
  }
  std::memcpy(s.buffer + s.used, data, n);
  s.used += n;
}

// Integers are written little-endian whatever the host, so keys (and the disk cache) agree across machines.
namespace {
template <class T>
void put_le(unsigned char* out, T v) {
  using U = std::make_unsigned_t<T>;
  auto u = static_cast<U>(v);
  for (std::size_t i = 0; i < sizeof(T); ++i) out[i] = static_cast<unsigned char>(u >> (8 * i));
}
}  // namespace

KeyHasher& KeyHasher::add(std::string_view s) {
  unsigned char head[9];
  head[0] = kString;
  put_le(head + 1, static_cast<std::uint64_t>(s.size()));
  bytes(head, sizeof head);
  bytes(s.data(), s.size());
  return *this;
}

KeyHasher& KeyHasher::add(std::int64_t v) {
  unsigned char b[9];
  b[0] = kInt;
  put_le(b + 1, v);
  bytes(b, sizeof b);
  return *this;
}

KeyHasher& KeyHasher::add(std::uint64_t v) {
  unsigned char b[9];
  b[0] = kUInt;
  put_le(b + 1, v);
  bytes(b, sizeof b);
  return *this;
}

KeyHasher& KeyHasher::add(double v) {
  // -0.0 and 0.0 compare equal and must give the same key; every NaN is folded into one pattern.
  if (v == 0.0) v = 0.0;
  if (std::isnan(v)) v = std::numeric_limits<double>::quiet_NaN();
  unsigned char b[9];
  b[0] = kDouble;
  put_le(b + 1, std::bit_cast<std::uint64_t>(v));
  bytes(b, sizeof b);
  return *this;
}

KeyHasher& KeyHasher::add(bool v) {
  const unsigned char b[2] = {kBool, static_cast<unsigned char>(v ? 1 : 0)};
  bytes(b, sizeof b);
  return *this;
}

KeyHasher& KeyHasher::add(const CacheKey& k) {
  unsigned char b[17];
  b[0] = kKey;
  put_le(b + 1, k.high);
  put_le(b + 9, k.low);
  bytes(b, sizeof b);
  return *this;
}

KeyHasher& KeyHasher::add(const Domain& d) {
  const unsigned char tag = kDomain;
  bytes(&tag, 1);
  add(d.origin.x).add(d.origin.y).add(d.spacing.x).add(d.spacing.y);
  add(static_cast<std::int64_t>(d.first.x)).add(static_cast<std::int64_t>(d.first.y));
  add(static_cast<std::int64_t>(d.resolution.x)).add(static_cast<std::int64_t>(d.resolution.y));
  return *this;
}

KeyHasher& KeyHasher::add(const ParamValue& v) {
  // The alternative index comes first so e.g. an Int 3 and a Seed 3 differ; the value follows in a fixed
  // component order. Colour components are widened to double (exactly) so they share the double rules.
  const unsigned char head[2] = {kParam, static_cast<unsigned char>(v.index())};
  bytes(head, sizeof head);
  std::visit(
      [this](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> || std::is_same_v<T, double> ||
                      std::is_same_v<T, std::uint64_t>) {
          add(x);
        } else if constexpr (std::is_same_v<T, std::string>) {
          add(std::string_view(x));
        } else if constexpr (std::is_same_v<T, glm::dvec2>) {
          add(x.x).add(x.y);
        } else if constexpr (std::is_same_v<T, glm::dvec3>) {
          add(x.x).add(x.y).add(x.z);
        } else if constexpr (std::is_same_v<T, glm::vec4>) {
          for (int c = 0; c < 4; ++c) add(static_cast<double>(x[c]));
        } else if constexpr (std::is_same_v<T, CurveValue>) {
          add(static_cast<std::uint64_t>(x.points.size()));
          for (const auto& p : x.points) add(p.x).add(p.y);
        } else if constexpr (std::is_same_v<T, GradientValue>) {
          add(static_cast<std::uint64_t>(x.stops.size()));
          for (const auto& s : x.stops) {
            add(s.position);
            for (int c = 0; c < 4; ++c) add(static_cast<double>(s.color[c]));
          }
        } else if constexpr (std::is_same_v<T, TableValue>) {
          // Column names, then every cell as its alternative index and value, row by row.
          add(static_cast<std::uint64_t>(x.columns.size()));
          for (const auto& c : x.columns) add(std::string_view(c));
          add(static_cast<std::uint64_t>(x.rows.size()));
          for (const auto& row : x.rows) {
            add(static_cast<std::uint64_t>(row.size()));
            for (const auto& cell : row) {
              add(static_cast<std::uint64_t>(cell.index()));
              std::visit(
                  [this](const auto& c) {
                    using C = std::decay_t<decltype(c)>;
                    if constexpr (std::is_same_v<C, std::string>)
                      add(std::string_view(c));
                    else if constexpr (std::is_same_v<C, double> || std::is_same_v<C, std::int64_t>)
                      add(c);
                    else if constexpr (std::is_same_v<C, glm::dvec2>)
                      add(c.x).add(c.y);
                    else if constexpr (std::is_same_v<C, Srgb8>)
                      add(std::int64_t{c.r}).add(std::int64_t{c.g}).add(std::int64_t{c.b});
                  },
                  cell);
            }
          }
        } else {
          static_assert(sizeof(T) == 0, "every ParamValue alternative needs a canonical encoding");
        }
      },
      v);
  return *this;
}

CacheKey KeyHasher::finish() const {
  HasherState& s = *state_of(state_);
  s.flush();
  const XXH128_hash_t h = XXH3_128bits_digest(&s.xxh);
  return CacheKey{h.high64, h.low64};
}

}  // namespace orogen
