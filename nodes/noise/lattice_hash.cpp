#include "nodes/noise/lattice_hash.h"

#include <xxhash.h>

#include "nodes/common/hash.h"

namespace orogen::noise {

namespace {

std::uint64_t stream_hash(std::uint64_t seed, Stream stream, std::uint32_t octave, std::uint32_t index) {
  const std::uint32_t words[3] = {static_cast<std::uint32_t>(stream), octave, index};
  return XXH3_64bits_withSeed(words, sizeof words, seed);
}

}  // namespace

std::uint32_t stream_key(std::uint64_t seed, Stream stream, std::uint32_t octave) {
  const std::uint64_t h = stream_hash(seed, stream, octave, 0);
  return static_cast<std::uint32_t>(h ^ (h >> 32));
}

double stream_unit(std::uint64_t seed, Stream stream, std::uint32_t octave, std::uint32_t index) {
  return unit_double(stream_hash(seed, stream, octave, index + 1));
}

}  // namespace orogen::noise
