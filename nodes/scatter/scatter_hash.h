#pragma once
// Counter-based randomness for the scatter family: every draw is a pure function of (seed, integers), so a
// point gets the same value whichever tile, domain, thread or evaluation order asks for it.
#include <bit>
#include <cstdint>

#include "nodes/common/hash.h"

namespace orogen::scatter {

// Hash of a tuple of integers under `key` (order matters), chained SplitMix64 outputs.
constexpr std::uint64_t hash(std::uint64_t key, std::uint64_t a) { return splitmix64(key ^ splitmix64(a)); }
constexpr std::uint64_t hash(std::uint64_t key, std::uint64_t a, std::uint64_t b) { return hash(hash(key, a), b); }
constexpr std::uint64_t hash(std::uint64_t key, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return hash(hash(hash(key, a), b), c);
}
constexpr std::uint64_t hash(std::uint64_t key, std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
  return hash(hash(hash(hash(key, a), b), c), d);
}

// The top 53 bits of a hash as a double in [0, 1).
constexpr double unit(std::uint64_t h) { return unit_double(h); }

// Signed integers as hash inputs (two's complement bits).
constexpr std::uint64_t bits(std::int64_t v) { return static_cast<std::uint64_t>(v); }
inline std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v + 0.0); }  // +0.0: -0 == 0
inline std::uint64_t bits(float v) { return std::bit_cast<std::uint32_t>(v + 0.0f); }

// Two values in [0, 1) with 32 bits each from one hash.
inline void unit2(std::uint64_t h, double& a, double& b) {
  a = static_cast<double>(h >> 32) * 0x1.0p-32;
  b = static_cast<double>(h & 0xFFFFFFFFull) * 0x1.0p-32;
}

// A stream of draws: (key, counter) -> hash. Sequential use only.
struct Draws {
  std::uint64_t key;
  std::uint64_t counter = 0;
  std::uint64_t bits() { return hash(key, counter++); }
  double next() { return unit(bits()); }
  void next2(double& a, double& b) { unit2(bits(), a, b); }
};

// The same with one mixing per draw, SplitMix64's sequence from the key (Draws hashes the counter first: twice
// the latency, which matters on a critical path such as Bridson's).
struct FastDraws {
  std::uint64_t key;
  std::uint64_t counter = 0;
  std::uint64_t bits() { return splitmix64(key + kGoldenGamma * counter++); }
  double next() { return unit(bits()); }
  void next2(double& a, double& b) { unit2(bits(), a, b); }
};

}  // namespace orogen::scatter
