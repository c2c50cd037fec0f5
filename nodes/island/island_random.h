#pragma once
// Counter-based random numbers for the island family: a value is a pure function of (seed, stream, counter),
// so results never depend on evaluation order or thread count.
#include <cstdint>

namespace orogen::island {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer with full avalanche.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

constexpr std::uint64_t hash64(std::uint64_t seed, std::uint64_t stream, std::uint64_t counter) {
  return mix64(mix64(mix64(seed) ^ stream) ^ counter);
}

// A double in [0, 1) with 53 random bits.
constexpr double unit_hash(std::uint64_t seed, std::uint64_t stream, std::uint64_t counter) {
  return static_cast<double>(hash64(seed, stream, counter) >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace orogen::island
