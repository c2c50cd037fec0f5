#pragma once
// Shared pieces of the erosion family: the maps every erosion model returns and small helpers.
#include <algorithm>
#include <cstdint>
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/common/hash.h"  // hash64 / hash01 of (seed, index): droplets and rain

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

inline void check_cancelled(const ExecContext* ctx) {
  if (ctx) ctx->check_cancelled();
}
inline void report(const ExecContext* ctx, double f) {
  if (ctx) ctx->progress(std::clamp(f, 0.0, 1.0));
}

}  // namespace orogen::erosion
