#pragma once
// Counter-based hashing for every family: a random value is a pure function of (seed, integers), so results
// never depend on evaluation order, tiling or thread count.
//
// Two mixers, both from SplitMix64 (G. Steele, D. Lea and C. Flood (2014), "Fast splittable pseudorandom
// number generators", OOPSLA): `mix64` is its finalizer alone (D. Stafford's "Mix13" variant), and
// `splitmix64` is one full SplitMix64 output, the finalizer of the state advanced by the golden gamma. They
// give different bits for the same argument; each caller keeps the one its stored outputs were made with.
#include <cstdint>

namespace orogen {

// The golden-ratio increment of SplitMix64 (2^64 / phi, odd).
inline constexpr std::uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ull;

// SplitMix64's finalizer: a bijection of 64-bit words with full avalanche. mix64(0) == 0.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// One SplitMix64 output for `state`: mix64(state + kGoldenGamma).
constexpr std::uint64_t splitmix64(std::uint64_t state) { return mix64(state + kGoldenGamma); }

// The top 53 bits of a hash as a double in [0, 1).
constexpr double unit_double(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// A hash of (seed, index): both words spread by odd multipliers, then the finalizer. Used where one stream of
// draws per seed is indexed directly (droplets, rain drops, k-means seeding).
constexpr std::uint64_t hash64(std::uint64_t seed, std::uint64_t index) {
  return mix64(seed * kGoldenGamma ^ (index + 0x632BE59BD9B4E019ull) * 0xD1B54A32D192ED03ull);
}
// hash64 as a double in [0, 1).
constexpr double hash01(std::uint64_t seed, std::uint64_t index) { return unit_double(hash64(seed, index)); }

}  // namespace orogen
