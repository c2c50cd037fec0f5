#pragma once
// Shared pieces of the erosion family: the maps every erosion model returns and small helpers.
#include <algorithm>
#include <cstdint>
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen::erosion {

// What every erosion model produces besides its own extras.
struct ErosionMaps {
  std::shared_ptr<Heightfield> out;         // eroded height, m
  std::shared_ptr<Heightfield> erosion;     // material removed, m (>= 0)
  std::shared_ptr<Heightfield> deposition;  // material laid down, m (>= 0)
  std::shared_ptr<Heightfield> flow;        // where water ran, 0..1
};

// Fills erosion/deposition from the difference out - in (erosion = max(0, in - out), deposition = max(0,
// out - in)), rows in parallel.
void fill_change_maps(const Heightfield& in, ErosionMaps& maps, const ExecContext* ctx);

// 1 where mask is absent, else the mask clamped to [0, 1].
inline float mask_at(const Heightfield* mask, std::size_t k) {
  return mask ? std::clamp(mask->data[k], 0.0f, 1.0f) : 1.0f;
}

// Counter-based hash (splitmix64 finaliser of a combined key): randomness from (seed, index).
inline std::uint64_t hash64(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull ^ (index + 0x632BE59BD9B4E019ull) * 0xD1B54A32D192ED03ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
inline double hash01(std::uint64_t seed, std::uint64_t index) {
  return static_cast<double>(hash64(seed, index) >> 11) * (1.0 / 9007199254740992.0);
}

inline void check_cancelled(const ExecContext* ctx) {
  if (ctx) ctx->check_cancelled();
}
inline void report(const ExecContext* ctx, double f) {
  if (ctx) ctx->progress(std::clamp(f, 0.0, 1.0));
}

}  // namespace orogen::erosion
