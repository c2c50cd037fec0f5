// SIMD scan of a grid triangle for the terrain TIN (see tin_scan.h), written once with Highway and compiled
// for several x86-64 levels; foreach_target.h re-includes this file once per target.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif

#include "nodes/geometry/tin_scan.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "nodes/geometry/tin_scan.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace orogen::tin::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using i64 = std::int64_t;

inline i64 FloorDiv(i64 n, i64 d) {
  const i64 q = n / d;
  return (n % d != 0 && ((n < 0) != (d < 0))) ? q - 1 : q;
}

ScanResult ScanTriangle(const ScanRequest& r) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const int w = r.width;
  const double za = r.z[static_cast<std::size_t>(r.ay) * w + r.ax];
  const double zb = r.z[static_cast<std::size_t>(r.by) * w + r.bx];
  const double zc = r.z[static_cast<std::size_t>(r.cy) * w + r.cx];
  const double ux = r.bx - r.ax, uy = r.by - r.ay, vx = r.cx - r.ax, vy = r.cy - r.ay;
  const double det = ux * vy - vx * uy;
  const double gx = ((zb - za) * vy - (zc - za) * uy) / det, gy = (ux * (zc - za) - vx * (zb - za)) / det;
  const int ymin = std::min({r.ay, r.by, r.cy}), ymax = std::max({r.ay, r.by, r.cy});
  const int xmin = std::min({r.ax, r.bx, r.cx}), xmax = std::max({r.ax, r.bx, r.cx});
  // Row spans from the edges, stepped exactly (see terrain_tin.cpp's scalar scan).
  struct Walk {
    i64 q, rem, den, step_q, step_r;
    int px;
    bool right;
  } walks[3];
  int n_walks = 0;
  const int ex[3] = {r.ax, r.bx, r.cx}, ey[3] = {r.ay, r.by, r.cy};
  for (int k = 0; k < 3; ++k) {
    const int px = ex[k], py = ey[k];
    const i64 dy = ey[(k + 1) % 3] - py, dx = ex[(k + 1) % 3] - px;
    if (dy == 0) continue;
    Walk& wk = walks[n_walks++];
    wk.right = dy > 0;
    wk.den = dy > 0 ? dy : -dy;
    const i64 s = dy > 0 ? dx : -dx;
    const i64 n = s * (ymin - py);
    wk.q = FloorDiv(n, wk.den);
    wk.rem = n - wk.q * wk.den;
    wk.step_q = FloorDiv(s, wk.den);
    wk.step_r = s - wk.step_q * wk.den;
    wk.px = px;
  }
  const V iota = hn::Iota(d, 0.0f);
  const V vg = hn::Set(d, static_cast<float>(gx));
  const float* const end = r.z + r.size;
  HWY_ALIGN float tail[HWY_MAX_BYTES / sizeof(float)] = {};
  // Loads of up to `lanes` samples from p (only `count` of them valid) that never read past the field.
  auto load = [&](const float* p, std::size_t count) -> V {
    if (count >= lanes) return hn::LoadU(d, p);
    if (p + lanes <= end) return hn::LoadU(d, p);
    std::memcpy(tail, p, count * sizeof(float));
    return hn::Load(d, tail);
  };
  ScanResult best;
  for (int y = ymin; y <= ymax; ++y) {
    i64 xl = xmin, xr = xmax;
    for (int k = 0; k < n_walks; ++k) {
      Walk& wk = walks[k];
      if (wk.right) xr = std::min(xr, wk.px + wk.q);
      else xl = std::max(xl, wk.px + wk.q + (wk.rem != 0 ? 1 : 0));
      wk.q += wk.step_q;
      wk.rem += wk.step_r;
      if (wk.rem >= wk.den) {
        ++wk.q;
        wk.rem -= wk.den;
      }
    }
    if (xl > xr) continue;
    const std::size_t n = static_cast<std::size_t>(xr - xl + 1);
    const float* row = r.z + static_cast<std::size_t>(y) * w + static_cast<std::size_t>(xl);
    // The plane along the row: its value at xl plus gx per sample.
    const V vb = hn::Set(d, static_cast<float>(za + gx * static_cast<double>(xl - r.ax) + gy * (y - r.ay)));
    auto errors = [&](std::size_t k) {
      const V plane = hn::MulAdd(vg, hn::Add(iota, hn::Set(d, static_cast<float>(k))), vb);
      V e = hn::Abs(hn::Sub(load(row + k, n - k), plane));
      if (n - k < lanes) e = hn::IfThenElseZero(hn::FirstN(d, n - k), e);
      return e;
    };
    V m = hn::Zero(d);
    for (std::size_t k = 0; k < n; k += lanes) m = hn::Max(m, errors(k));
    const float row_max = hn::GetLane(hn::MaxOfLanes(d, m));
    if (!(row_max > best.error)) continue;
    best.error = row_max;
    if (r.stop_above) {
      if (row_max > r.limit) return best;
      continue;
    }
    const V target = hn::Set(d, row_max);
    for (std::size_t k = 0; k < n; k += lanes) {
      const intptr_t at = hn::FindFirstTrue(d, hn::Eq(errors(k), target));
      if (at >= 0) {
        best.sample = static_cast<std::int32_t>(static_cast<i64>(y) * w + xl + static_cast<i64>(k) + at);
        break;
      }
    }
  }
  return best;
}

}  // namespace orogen::tin::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace orogen::tin {

HWY_EXPORT(ScanTriangle);

ScanResult scan_triangle(const ScanRequest& request) { return HWY_DYNAMIC_DISPATCH(ScanTriangle)(request); }

}  // namespace orogen::tin
#endif
