#pragma once
// Counter-based random numbers for the island family: a value is a pure function of (seed, stream, counter),
// so results never depend on evaluation order or thread count.
#include <cstdint>

#include "nodes/common/hash.h"

namespace orogen::island {

// Chained SplitMix64 outputs of (seed, stream, counter).
constexpr std::uint64_t hash64(std::uint64_t seed, std::uint64_t stream, std::uint64_t counter) {
  return splitmix64(splitmix64(splitmix64(seed) ^ stream) ^ counter);
}

// A double in [0, 1) with 53 random bits.
constexpr double unit_hash(std::uint64_t seed, std::uint64_t stream, std::uint64_t counter) {
  return unit_double(hash64(seed, stream, counter));
}

}  // namespace orogen::island
