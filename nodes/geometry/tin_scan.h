#pragma once
// The inner loop of the terrain TIN (terrain_tin.cpp): the largest vertical distance between the samples
// inside a grid triangle and the triangle's plane, in single precision with SIMD (Highway, dispatched to the
// best instruction set of the CPU).
#include <cstddef>
#include <cstdint>

namespace orogen::tin {

struct ScanRequest {
  const float* z = nullptr;  // the heightfield, row-major
  std::size_t size = 0;      // its sample count (loads never read past it)
  int width = 0;
  int ax = 0, ay = 0, bx = 0, by = 0, cx = 0, cy = 0;  // grid corners, counter-clockwise, not collinear
  // With stop_above, the scan ends at the first row whose error exceeds `limit` (the result is then some
  // error above the limit and no sample); otherwise it finds the largest error and its first sample.
  bool stop_above = false;
  float limit = 0.0f;
};

struct ScanResult {
  float error = -1.0f;       // the largest |z - plane| of the samples inside, edges included
  std::int32_t sample = -1;  // j * width + i of the first sample with that error (not with stop_above)
};

// Float rounding: |result.error - exact error| <= 1e-6 * max(|z| of the field) (see terrain_tin.cpp).
ScanResult scan_triangle(const ScanRequest& request);

}  // namespace orogen::tin
