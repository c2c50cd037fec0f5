#pragma once
// How many rows an image writer hands the codec per call.
#include <algorithm>

namespace orogen {

// Enough zip chunks (16 rows each for EXR) for OpenEXR to compress them in parallel on every core, few enough
// that the converted block stays small (at most 256 rows: 4 MB at 4096 floats). Small images still go in a few
// blocks, so progress (and cancellation) happens during the write.
inline int block_rows(int height) { return std::clamp((height / 8 + 15) / 16 * 16, 16, 256); }

}  // namespace orogen
