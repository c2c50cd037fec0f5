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
#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace orogen::tin::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using i64 = std::int64_t;

template <bool kStopAbove>
ScanResult ScanRows(const ScanRequest& r) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const int w = r.width;
  const double za = r.z[static_cast<std::size_t>(r.ay) * w + r.ax];
  const double zb = r.z[static_cast<std::size_t>(r.by) * w + r.bx];
  const double zc = r.z[static_cast<std::size_t>(r.cy) * w + r.cx];
  const double ux = r.bx - r.ax, uy = r.by - r.ay, vx = r.cx - r.ax, vy = r.cy - r.ay;
  const double inv_det = 1.0 / (ux * vy - vx * uy);
  const double gx = ((zb - za) * vy - (zc - za) * uy) * inv_det, gy = (ux * (zc - za) - vx * (zb - za)) * inv_det;
  // Rasterised as two trapezoids: with the corners sorted by row (p0 lowest, p2 highest), the long edge p0 -> p2
  // bounds every row on one side and the short edges p0 -> p1 (rows below p1) and p1 -> p2 (rows from p1 on)
  // on the other. Each edge is walked exactly: x = px + floor(dx (y - py) / dy) as a quotient and remainder
  // stepped row by row (the right side takes the floor, the left side the ceiling), without a division per row.
  struct Corner {
    int x, y;
  } p[3] = {{r.ax, r.ay}, {r.bx, r.by}, {r.cx, r.cy}};
  if (p[1].y < p[0].y) std::swap(p[0], p[1]);
  if (p[2].y < p[1].y) std::swap(p[1], p[2]);
  if (p[1].y < p[0].y) std::swap(p[0], p[1]);
  // int is wide enough: |q| stays below the grid width, the remainder below the edge's height, and their
  // product below the grid's sample count.
  struct Walk {
    int q, rem, den, step_q, step_r;
    int px;
    void start(Corner a, Corner b, int y) {  // the edge a -> b (a.y < b.y), at row y
      den = b.y - a.y;
      const int s = b.x - a.x;
      step_q = s / den - (s % den < 0 ? 1 : 0);  // floor(s / den), den > 0
      step_r = s - step_q * den;
      const int n = s * (y - a.y);
      q = n / den - (n % den < 0 ? 1 : 0);
      rem = n - q * den;
      px = a.x;
    }
    i64 floor_x() const { return px + q; }
    i64 ceil_x() const { return px + q + (rem != 0); }
    void step() {
      q += step_q;
      rem += step_r;
      const bool carry = rem >= den;  // branch-free: the carry is as good as random from row to row
      q += carry;
      rem -= carry ? den : 0;
    }
  };
  const int ymin = p[0].y, ymid = p[1].y, ymax = p[2].y;
  // The middle corner left of the long edge (seen from p0 towards p2): the short edges bound the rows on the left.
  const bool short_left =
      static_cast<i64>(p[2].x - p[0].x) * (p[1].y - p[0].y) - static_cast<i64>(p[2].y - p[0].y) * (p[1].x - p[0].x) > 0;
  const V iota = hn::Iota(d, 0.0f);
  const V vg = hn::Set(d, static_cast<float>(gx));
  const V none = hn::Set(d, -1.0f);  // the error of lanes past a row's end: below every real error
  const hn::RebindToSigned<decltype(d)> di;
  using VI = hn::Vec<decltype(di)>;
  const VI iota_i = hn::Iota(di, 0);
  const float* const end = r.z + r.size;
  HWY_ALIGN float tail[HWY_MAX_BYTES / sizeof(float)] = {};
  // Loads of up to `lanes` samples from p (only `count` of them valid) that never read past the field.
  auto load = [&](const float* p, std::size_t count) -> V {
    if (p + lanes <= end) return hn::LoadU(d, p);
    std::memcpy(tail, p, std::min(count, lanes) * sizeof(float));
    return hn::Load(d, tail);
  };
  // Per lane, the largest error so far and the index of the chunk where it first occurred (the lane's sample
  // is that plus the lane): rows need no reduction across lanes (most rows of a TIN triangle are shorter than
  // a vector), only the end of the scan does.
  V acc = none;
  VI where = hn::Set(di, -1);
  const V vlimit = hn::Set(d, r.limit);
  auto chunk = [&](const float* row, std::size_t k, std::size_t n, V plane, std::int32_t index) {
    V e = hn::Abs(hn::Sub(load(row + k, n - k), plane));
    if (n - k < lanes) e = hn::IfThenElse(hn::FirstN(d, n - k), e, none);
    if constexpr (kStopAbove) {
      acc = hn::Max(acc, e);
    } else {
      const auto larger = hn::Gt(e, acc);  // strictly: each lane keeps its first sample of its maximum
      acc = hn::IfThenElse(larger, e, acc);
      where = hn::IfThenElse(hn::RebindMask(di, larger), hn::Set(di, index), where);
    }
  };
  // Rows y0..y1 between the left walk's ceiling and the right walk's floor; true when the scan stops early.
  // (The walks are copies, so they stay in registers.)
  auto rows = [&](int y0, int y1, Walk left, Walk right) {
    // The plane at x = 0 of the row, stepped by gy (in double: its rounding stays far below the float scan's).
    double base = za - gx * r.ax + gy * (y0 - r.ay);
    const float* row_z = r.z + static_cast<std::size_t>(y0) * w;
    std::int32_t row_index = static_cast<std::int32_t>(static_cast<i64>(y0) * w);
    for (int y = y0; y <= y1; ++y, base += gy, row_z += w, row_index += w) {
      const i64 xl = left.ceil_x(), xr = right.floor_x();
      left.step();
      right.step();
      if (xl > xr) continue;
      const std::size_t n = static_cast<std::size_t>(xr - xl + 1);
      const float* row = row_z + xl;
      // The plane along the row: its value at xl plus gx per sample.
      const V vb = hn::Set(d, static_cast<float>(base + gx * static_cast<double>(xl)));
      const std::int32_t row_start = row_index + static_cast<std::int32_t>(xl);
      chunk(row, 0, n, hn::MulAdd(vg, iota, vb), row_start);
      for (std::size_t k = lanes; k < n; k += lanes)
        chunk(row, k, n, hn::MulAdd(vg, hn::Add(iota, hn::Set(d, static_cast<float>(k))), vb),
              row_start + static_cast<std::int32_t>(k));
      if constexpr (kStopAbove) {
        if (!hn::AllFalse(d, hn::Gt(acc, vlimit))) return true;
      }
    }
    return false;
  };
  Walk long_edge{}, short_edge{};
  bool stopped = false;
  if (ymin < ymid) {
    long_edge.start(p[0], p[2], ymin);
    short_edge.start(p[0], p[1], ymin);
    stopped = short_left ? rows(ymin, ymid - 1, short_edge, long_edge) : rows(ymin, ymid - 1, long_edge, short_edge);
  }
  if (!stopped) {
    long_edge.start(p[0], p[2], ymid);
    if (ymid < ymax) {
      short_edge.start(p[1], p[2], ymid);
    } else {
      short_edge = Walk{0, 0, 1, 0, 0, p[1].x};  // a flat top: the short side is p1 itself
    }
    stopped = short_left ? rows(ymid, ymax, short_edge, long_edge) : rows(ymid, ymax, long_edge, short_edge);
  }
  ScanResult best;
  const float largest = hn::GetLane(hn::MaxOfLanes(d, acc));
  if (!(largest >= 0.0f)) return best;  // no sample inside
  best.error = largest;
  if constexpr (!kStopAbove) {
    // The first sample (row-major) with the largest error: the smallest index among the lanes that reach it.
    const VI candidates = hn::IfThenElse(hn::RebindMask(di, hn::Eq(acc, hn::Set(d, largest))), hn::Add(where, iota_i),
                                         hn::Set(di, INT32_MAX));
    best.sample = hn::GetLane(hn::MinOfLanes(di, candidates));
  }
  return best;
}

ScanResult ScanTriangle(const ScanRequest& r) { return r.stop_above ? ScanRows<true>(r) : ScanRows<false>(r); }

}  // namespace orogen::tin::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace orogen::tin {

HWY_EXPORT(ScanTriangle);

ScanResult scan_triangle(const ScanRequest& request) { return HWY_DYNAMIC_DISPATCH(ScanTriangle)(request); }

}  // namespace orogen::tin
#endif
