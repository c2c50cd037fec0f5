#pragma once
// Counter-based randomness for the noise generators: every random number is a pure function of
// (seed, stream, integer lattice coordinates), so a lattice point gets the same value whichever tile,
// domain, thread or evaluation order asks for it.
//
// Two levels:
//  - `stream_key` (once per evaluation, scalar): XXH3-64 of (seed, stream tag, octave) folded to 32 bits.
//    It decorrelates generators and octaves that share a node seed.
//  - `lattice_hash` (per lattice point, in the SIMD inner loops): the coordinates are multiplied by two odd
//    constants, combined with the key, and finished with Chris Wellons' "lowbias32" integer mixer (two
//    multiplies, full avalanche). 32-bit lane arithmetic keeps it cheap in SIMD; the lattice indices are
//    taken modulo 2^32, which is the period of the noise (2^32 cells).
//
// The SIMD kernels (noise_kernels.cpp) implement exactly the same arithmetic on vectors.
#include <cstdint>

namespace orogen::noise {

inline constexpr std::uint32_t kHashPrimeX = 0x9E3779B1u;  // odd: multiplication is a bijection mod 2^32
inline constexpr std::uint32_t kHashPrimeY = 0x85EBCA77u;
inline constexpr std::uint32_t kMixA = 0x21F0AAADu;  // lowbias32 constants (hash-prospector)
inline constexpr std::uint32_t kMixB = 0x735A2D97u;
inline constexpr std::uint32_t kSecondDraw = 0x93D765DDu;  // spectrally good LCG multiplier (Steele & Vigna 2021)

// lowbias32: a bijective 32-bit mixer with very low avalanche bias.
constexpr std::uint32_t mix32(std::uint32_t h) {
  h ^= h >> 16;
  h *= kMixA;
  h ^= h >> 15;
  h *= kMixB;
  h ^= h >> 15;
  return h;
}

// Hash of the lattice point (x, y) (indices modulo 2^32) under `key`.
constexpr std::uint32_t lattice_hash(std::uint32_t x, std::uint32_t y, std::uint32_t key) {
  return mix32((x * kHashPrimeX) ^ (y * kHashPrimeY) ^ key);
}

// The top 24 bits of a hash as a float in [0, 1) (exact: 24 bits fit a float mantissa).
constexpr float unit_float(std::uint32_t h) { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }

// A second draw from the same hash (Worley needs two coordinates per cell): one multiplicative
// congruential step. Pairs (h, h * M mod 2^32) lie on a lattice whose lines are ~2^-16 apart for this
// spectrally good multiplier, far below anything visible, and it costs one multiply instead of a new hash.
constexpr std::uint32_t second_draw(std::uint32_t h) { return h * kSecondDraw; }

// Stream tags: one per generator family, so equal seeds of different generators are unrelated.
enum class Stream : std::uint32_t { Perlin = 1, Simplex = 2, Value = 3, White = 4, Worley = 5, OctaveOffset = 6 };

// Key of `stream` for octave `octave` of a node seeded with `seed` (XXH3-64 folded to 32 bits).
std::uint32_t stream_key(std::uint64_t seed, Stream stream, std::uint32_t octave = 0);

// A reproducible value in [0, 1) for (seed, stream, octave, index): per-octave lattice offsets.
double stream_unit(std::uint64_t seed, Stream stream, std::uint32_t octave, std::uint32_t index);

}  // namespace orogen::noise
