// SIMD batch kernels of the noise generators (see noise_kernels.h), written once with Highway and
// compiled for several x86-64 levels; HWY_DYNAMIC_DISPATCH picks the best one the CPU supports.
//
// This file is compiled once per target: foreach_target.h re-includes it with HWY_NAMESPACE set to each
// target's namespace, and the HWY_ONCE section at the end holds the dispatching entry points.

// SSSE3 and AVX3_DL bring nothing over SSE4 and AVX3 for these kernels; leaving them out halves the
// compile time of this file. Older CPUs run the scalar target.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif

#include "nodes/noise/noise_kernels.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "nodes/noise/noise_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <cassert>
#include <limits>

#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_reference.h"

HWY_BEFORE_NAMESPACE();
namespace orogen::noise::kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DU = hn::RebindToUnsigned<DF>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VU = hn::Vec<DU>;
using DD = hn::ScalableTag<double>;
using VD = hn::Vec<DD>;
using DFH = hn::Rebind<float, DD>;  // floats, as many lanes as a double vector
using DIH = hn::Rebind<std::int32_t, DD>;
using DUH = hn::Rebind<std::uint32_t, DD>;

// ---------------------------------------------------------------------------------------------------
// Shared pieces (the vector forms of lattice_hash.h and noise_reference.h)

// lowbias32
HWY_INLINE VU Mix(VU h) {
  const DU du;
  h = hn::Xor(h, hn::ShiftRight<16>(h));
  h = hn::Mul(h, hn::Set(du, kMixA));
  h = hn::Xor(h, hn::ShiftRight<15>(h));
  h = hn::Mul(h, hn::Set(du, kMixB));
  return hn::Xor(h, hn::ShiftRight<15>(h));
}

// lowbias32 without its last step (h ^= h >> 15), which changes only the low 15 bits: enough where only the
// top bits are used (the gradient number h >> 28 and the sign bit), with the same result as Mix.
HWY_INLINE VU MixTop(VU h) {
  const DU du;
  h = hn::Xor(h, hn::ShiftRight<16>(h));
  h = hn::Mul(h, hn::Set(du, kMixA));
  h = hn::Xor(h, hn::ShiftRight<15>(h));
  return hn::Mul(h, hn::Set(du, kMixB));
}

// Top 24 bits as a float in [0, 1).
HWY_INLINE VF UnitFloat(VU h) {
  const DF df;
  const DI di;
  return hn::Mul(hn::ConvertTo(df, hn::BitCast(di, hn::ShiftRight<8>(h))), hn::Set(df, 1.0f / 16777216.0f));
}

HWY_INLINE VF SignedUnit(VU h) {
  const DF df;
  return hn::MulAdd(UnitFloat(h), hn::Set(df, 2.0f), hn::Set(df, -1.0f));
}

// The gradient table of noise_reference.h: 16 unit vectors at 22.5-degree steps, the second half the
// negated first half. With 16 float lanes (AVX-512) the whole table sits in a register and the top 4 hash
// bits index it directly; with 8 lanes (AVX2) the first half does and bit 31 flips the sign; narrower
// targets gather the first half from memory. The vectors are the same exact constants on every target and
// negation commutes with rounding, so every target computes the same dot products.
struct Gradients {
  static constexpr std::size_t kLanes = HWY_LANES(float);
  VF x, y;
  Gradients() {
    const DF df;
    if constexpr (kLanes >= 8) {
      alignas(64) float tx[kLanes], ty[kLanes];
      for (std::size_t i = 0; i < kLanes; ++i) {
        const float sign = (i % 16) >= 8 ? -1.0f : 1.0f;
        tx[i] = sign * reference::kGradientX[i % 8];
        ty[i] = sign * reference::kGradientY[i % 8];
      }
      x = hn::Load(df, tx);
      y = hn::Load(df, ty);
    } else {
      x = y = hn::Zero(df);
    }
  }

  struct Vector {
    VF x, y;
  };

  // Gradient number h >> 28.
  HWY_INLINE Vector Lookup(VU h) const {
    const DF df;
    const DU du;
    const DI di;
    if constexpr (kLanes >= 16) {
      const auto lanes = hn::IndicesFromVec(df, hn::BitCast(di, hn::ShiftRight<28>(h)));
      return {hn::TableLookupLanes(x, lanes), hn::TableLookupLanes(y, lanes)};
    } else {
      const auto index = hn::BitCast(di, hn::And(hn::ShiftRight<28>(h), hn::Set(du, 7u)));
      VF gx, gy;
      if constexpr (kLanes >= 8) {
        const auto lanes = hn::IndicesFromVec(df, index);
        gx = hn::TableLookupLanes(x, lanes);
        gy = hn::TableLookupLanes(y, lanes);
      } else {
        gx = hn::GatherIndex(df, reference::kGradientX, index);
        gy = hn::GatherIndex(df, reference::kGradientY, index);
      }
      const VU sign = hn::And(h, hn::Set(du, 0x80000000u));  // vectors 8..15 are the negated 0..7
      return {hn::BitCast(df, hn::Xor(hn::BitCast(du, gx), sign)), hn::BitCast(df, hn::Xor(hn::BitCast(du, gy), sign))};
    }
  }

  static HWY_INLINE VF Dot(const Vector& g, VF dx, VF dy) { return hn::MulAdd(g.x, dx, hn::Mul(g.y, dy)); }
  HWY_INLINE VF Dot(VU h, VF dx, VF dy) const { return Dot(Lookup(h), dx, dy); }
};

HWY_INLINE VF Fade(VF t) {
  const DF df;
  const VF inner = hn::MulAdd(t, hn::MulAdd(t, hn::Set(df, 6.0f), hn::Set(df, -15.0f)), hn::Set(df, 10.0f));
  return hn::Mul(hn::Mul(hn::Mul(t, t), t), inner);
}

HWY_INLINE VF Lerp(VF a, VF b, VF t) { return hn::MulAdd(t, hn::Sub(b, a), a); }

template <bool kAccumulate>
HWY_INLINE void Put(VF v, float* out, std::size_t i) {
  const DF df;
  if constexpr (kAccumulate) v = hn::Add(v, hn::LoadU(df, out + i));
  hn::StoreU(v, df, out + i);
}

// Lattice coordinates of lanes i.. of a single-row run; y from the arrays or the row constants (which the
// compiler hoists out of the loop: runs are passed by value so no store can alias them).
struct LatticeLanes {
  VU hx;
  VF fx;
  VU hy;
  VF fy;
};

template <bool kRowY>
HWY_INLINE LatticeLanes LoadLattice(const LatticeRun& in, std::size_t i) {
  const DF df;
  const DU du;
  if constexpr (kRowY) {
    return {hn::LoadU(du, in.hx + i), hn::LoadU(df, in.fx + i), hn::Set(du, in.row_hy), hn::Set(df, in.row_fy[0])};
  } else {
    return {hn::LoadU(du, in.hx + i), hn::LoadU(df, in.fx + i), hn::LoadU(du, in.hy + i), hn::LoadU(df, in.fy + i)};
  }
}

// ---------------------------------------------------------------------------------------------------
// Coordinate stages

void Displaced(const double* x, double x_const, const float* warp, double frequency, double shift, int n, double* u) {
  const DD dd;
  const DFH dfh;
  const VD f = hn::Set(dd, frequency), s = hn::Set(dd, shift);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(dd)) {
    VD xv = x ? hn::LoadU(dd, x + i) : hn::Set(dd, x_const);
    if (warp) xv = hn::Add(xv, hn::PromoteTo(dd, hn::LoadU(dfh, warp + i)));
    hn::StoreU(hn::Add(hn::Mul(xv, f), s), dd, u + i);
  }
}

// floor(c) mod 2^32 for an integer-valued c in [0, 2^32), through int32 (the conversion x86 has).
HWY_INLINE hn::Vec<DUH> WrapCell(VD c_reduced) {
  const DD dd;
  const DIH dih;
  const DUH duh;
  const auto as_int = hn::DemoteTo(dih, hn::Sub(c_reduced, hn::Set(dd, 2147483648.0)));
  return hn::Xor(hn::BitCast(duh, as_int), hn::Set(duh, 0x80000000u));
}

// An integer-valued c reduced modulo 2^32 (exact in double for any magnitude).
HWY_INLINE VD Reduce(VD c) {
  const DD dd;
  return hn::Sub(c, hn::Mul(hn::Floor(hn::Mul(c, hn::Set(dd, 0x1.0p-32))), hn::Set(dd, 0x1.0p32)));
}

void SplitLattice(const double* u, std::uint32_t multiplier, int n, std::uint32_t* cell, float* frac) {
  const DD dd;
  const DFH dfh;
  const DUH duh;
  const auto m = hn::Set(duh, multiplier);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(dd)) {
    const VD uv = hn::LoadU(dd, u + i);
    const VD c = hn::Floor(uv);
    hn::StoreU(hn::DemoteTo(dfh, hn::Sub(uv, c)), dfh, frac + i);
    hn::StoreU(hn::Mul(WrapCell(Reduce(c)), m), duh, cell + i);
  }
}

void SimplexSkew(const double* u, const double* v, double v_const, int n, std::uint32_t* ci, std::uint32_t* cj,
                 float* x0, float* y0) {
  const DD dd;
  const DFH dfh;
  const DUH duh;
  const VD f2 = hn::Set(dd, reference::kSimplexF2), g2 = hn::Set(dd, reference::kSimplexG2);
  for (std::size_t k = 0; k < static_cast<std::size_t>(n); k += hn::Lanes(dd)) {
    const VD uv = hn::LoadU(dd, u + k);
    const VD vv = v ? hn::LoadU(dd, v + k) : hn::Set(dd, v_const);
    const VD s = hn::Mul(hn::Add(uv, vv), f2);
    const VD i = hn::Floor(hn::Add(uv, s)), j = hn::Floor(hn::Add(vv, s));
    const VD t = hn::Mul(hn::Add(i, j), g2);
    hn::StoreU(hn::DemoteTo(dfh, hn::Sub(uv, hn::Sub(i, t))), dfh, x0 + k);
    hn::StoreU(hn::DemoteTo(dfh, hn::Sub(vv, hn::Sub(j, t))), dfh, y0 + k);
    hn::StoreU(hn::Mul(WrapCell(Reduce(i)), hn::Set(duh, kHashPrimeX)), duh, ci + k);
    hn::StoreU(hn::Mul(WrapCell(Reduce(j)), hn::Set(duh, kHashPrimeY)), duh, cj + k);
  }
}

// ---------------------------------------------------------------------------------------------------
// Bases

// Per-row y constants of a multi-row run, computed with the same vector operations as the per-sample path.
struct RowY {
  VF fy[kMaxRows], fy1[kMaxRows], uy[kMaxRows];
  explicit RowY(const LatticeRun& in) {
    const DF df;
    for (int r = 0; r < in.rows; ++r) {
      fy[r] = hn::Set(df, in.row_fy[r]);
      fy1[r] = hn::Sub(fy[r], hn::Set(df, 1.0f));
      uy[r] = Fade(fy[r]);
    }
  }
};

// Perlin: the four corner gradients of a lattice cell, looked up once per vector and shared by every row
// of a multi-row run; then per row the four dot products and the fade-weighted blend.
template <bool kRowY, bool kAccumulate>
void PerlinImpl(const LatticeRun in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
  const DF df;
  const DU du;
  const VU px = hn::Set(du, kHashPrimeX), py = hn::Set(du, kHashPrimeY), vkey = hn::Set(du, key);
  const VF one = hn::Set(df, 1.0f), vscale = hn::Set(df, scale * reference::kPerlinScale);
  const Gradients g;
  if constexpr (kRowY) {
    const RowY ry(in);
    const VU y0 = hn::Xor(hn::Set(du, in.row_hy), vkey), y1 = hn::Xor(hn::Set(du, in.row_hy + kHashPrimeY), vkey);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const VU x0 = hn::LoadU(du, in.hx + i), x1 = hn::Add(x0, px);
      const VF fx = hn::LoadU(df, in.fx + i), fx1 = hn::Sub(fx, one), ux = Fade(fx);
      const auto g00 = g.Lookup(Mix(hn::Xor(x0, y0))), g10 = g.Lookup(Mix(hn::Xor(x1, y0)));
      const auto g01 = g.Lookup(Mix(hn::Xor(x0, y1))), g11 = g.Lookup(Mix(hn::Xor(x1, y1)));
      for (int r = 0; r < in.rows; ++r) {
        const VF n00 = Gradients::Dot(g00, fx, ry.fy[r]), n10 = Gradients::Dot(g10, fx1, ry.fy[r]);
        const VF n01 = Gradients::Dot(g01, fx, ry.fy1[r]), n11 = Gradients::Dot(g11, fx1, ry.fy1[r]);
        const VF v = Lerp(Lerp(n00, n10, ux), Lerp(n01, n11, ux), ry.uy[r]);
        Put<kAccumulate>(hn::Mul(v, vscale), out + r * stride, i);
      }
    }
  } else {
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const LatticeLanes c = LoadLattice<false>(in, i);
      const VU x0 = c.hx, x1 = hn::Add(x0, px);
      const VU y0 = hn::Xor(c.hy, vkey), y1 = hn::Xor(hn::Add(c.hy, py), vkey);
      const VF fx1 = hn::Sub(c.fx, one), fy1 = hn::Sub(c.fy, one);
      const VF n00 = g.Dot(Mix(hn::Xor(x0, y0)), c.fx, c.fy);
      const VF n10 = g.Dot(Mix(hn::Xor(x1, y0)), fx1, c.fy);
      const VF n01 = g.Dot(Mix(hn::Xor(x0, y1)), c.fx, fy1);
      const VF n11 = g.Dot(Mix(hn::Xor(x1, y1)), fx1, fy1);
      const VF ux = Fade(c.fx), uy = Fade(c.fy);
      const VF v = Lerp(Lerp(n00, n10, ux), Lerp(n01, n11, ux), uy);
      Put<kAccumulate>(hn::Mul(v, vscale), out, i);
    }
  }
}

// Value: the x blends of the lattice row pair are shared by every row of a multi-row run.
template <bool kRowY, bool kAccumulate>
void ValueImpl(const LatticeRun in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
  const DF df;
  const DU du;
  const VU px = hn::Set(du, kHashPrimeX), py = hn::Set(du, kHashPrimeY), vkey = hn::Set(du, key);
  const VF vscale = hn::Set(df, scale);
  if constexpr (kRowY) {
    const RowY ry(in);
    const VU y0 = hn::Xor(hn::Set(du, in.row_hy), vkey), y1 = hn::Xor(hn::Set(du, in.row_hy + kHashPrimeY), vkey);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const VU x0 = hn::LoadU(du, in.hx + i), x1 = hn::Add(x0, px);
      const VF ux = Fade(hn::LoadU(df, in.fx + i));
      const VF a = Lerp(SignedUnit(Mix(hn::Xor(x0, y0))), SignedUnit(Mix(hn::Xor(x1, y0))), ux);
      const VF b = Lerp(SignedUnit(Mix(hn::Xor(x0, y1))), SignedUnit(Mix(hn::Xor(x1, y1))), ux);
      for (int r = 0; r < in.rows; ++r) Put<kAccumulate>(hn::Mul(Lerp(a, b, ry.uy[r]), vscale), out + r * stride, i);
    }
  } else {
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const LatticeLanes c = LoadLattice<false>(in, i);
      const VU x0 = c.hx, x1 = hn::Add(x0, px);
      const VU y0 = hn::Xor(c.hy, vkey), y1 = hn::Xor(hn::Add(c.hy, py), vkey);
      const VF ux = Fade(c.fx), uy = Fade(c.fy);
      const VF a = Lerp(SignedUnit(Mix(hn::Xor(x0, y0))), SignedUnit(Mix(hn::Xor(x1, y0))), ux);
      const VF b = Lerp(SignedUnit(Mix(hn::Xor(x0, y1))), SignedUnit(Mix(hn::Xor(x1, y1))), ux);
      Put<kAccumulate>(hn::Mul(Lerp(a, b, uy), vscale), out, i);
    }
  }
}

// White: one value per lattice cell, the same for every row of a multi-row run.
template <bool kRowY, bool kAccumulate>
void WhiteImpl(const LatticeRun in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
  const DF df;
  const DU du;
  const VU vkey = hn::Set(du, key);
  const VF vscale = hn::Set(df, scale);
  const int rows = kRowY ? in.rows : 1;
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    const LatticeLanes c = LoadLattice<kRowY>(in, i);
    const VF v = hn::Mul(SignedUnit(Mix(hn::Xor(hn::Xor(c.hx, c.hy), vkey))), vscale);
    for (int r = 0; r < rows; ++r) Put<kAccumulate>(v, out + r * stride, i);
  }
}

// One simplex corner: (max(0, 1/2 - x^2 - y^2))^4 (g . (x, y)).
HWY_INLINE VF SimplexCorner(VF x, VF y, const Gradients::Vector& g) {
  const DF df;
  const VF w =
      hn::Max(hn::Zero(df), hn::NegMulAdd(y, y, hn::NegMulAdd(x, x, hn::Set(df, 0.5f))));  // 0 beyond the radius
  const VF w2 = hn::Mul(w, w);
  return hn::Mul(hn::Mul(w2, w2), Gradients::Dot(g, x, y));
}

// The three corners of the simplex (x0, y0) lies in, relative to its origin: the middle corner is (1, 0) in
// the lower triangle (x0 > y0), else (0, 1).
struct SimplexCorners {
  hn::Mask<DF> lower;
  VF x1, y1, x2, y2;
  HWY_INLINE SimplexCorners(VF x0, VF y0) {
    const DF df;
    constexpr float g2 = static_cast<float>(reference::kSimplexG2);
    const VF one = hn::Set(df, 1.0f), vg2 = hn::Set(df, g2);
    lower = x0 > y0;
    const VF x0m1 = hn::Sub(x0, one), y0m1 = hn::Sub(y0, one);
    x1 = hn::Add(hn::IfThenElse(lower, x0m1, x0), vg2);
    y1 = hn::Add(hn::IfThenElse(lower, y0, y0m1), vg2);
    x2 = hn::Add(x0m1, hn::Set(df, 2.0f * g2));
    y2 = hn::Add(y0m1, hn::Set(df, 2.0f * g2));
  }
};

// The three corner hashes from the pre-multiplied cell (ib, jb) and the sum of the corners.
HWY_INLINE VF SimplexHashed(VF x0, VF y0, const SimplexCorners& c, VU ib, VU jb, VU vkey, const Gradients& g) {
  const DU du;
  const VU px = hn::Set(du, kHashPrimeX), py = hn::Set(du, kHashPrimeY);
  const auto lower_u = hn::RebindMask(du, c.lower);
  const VU ib1 = hn::Add(ib, px), jb1 = hn::Add(jb, py);
  const VU jk = hn::Xor(jb, vkey), jk1 = hn::Xor(jb1, vkey);
  const VU h0 = MixTop(hn::Xor(ib, jk));
  const VU h1 = MixTop(hn::IfThenElse(lower_u, hn::Xor(ib1, jk), hn::Xor(ib, jk1)));
  const VU h2 = MixTop(hn::Xor(ib1, jk1));
  return hn::Add(hn::Add(SimplexCorner(x0, y0, g.Lookup(h0)), SimplexCorner(c.x1, c.y1, g.Lookup(h1))),
                 SimplexCorner(c.x2, c.y2, g.Lookup(h2)));
}

// Warped samples: per-sample cells and offsets.
template <bool kAccumulate>
void SimplexImpl(const SimplexRun in, std::uint32_t key, int n, float* out, float scale) {
  const DF df;
  const DU du;
  const VU vkey = hn::Set(du, key);
  const VF vscale = hn::Set(df, scale * reference::kSimplexScale);
  const Gradients g;
  for (std::size_t k = 0; k < static_cast<std::size_t>(n); k += hn::Lanes(df)) {
    const VF x0 = hn::LoadU(df, in.x0 + k), y0 = hn::LoadU(df, in.y0 + k);
    const VU ib = hn::LoadU(du, in.hi + k), jb = hn::LoadU(du, in.hj + k);
    const SimplexCorners c(x0, y0);
    Put<kAccumulate>(hn::Mul(SimplexHashed(x0, y0, c, ib, jb, vkey, g), vscale), out, k);
  }
}

// Unwarped rows sharing their columns (SimplexRows). Per vector of columns, a block of kBlockW x kBlockH
// lattice vertices from the first row's first sample: vertex (ib + a, jb + b) in lane b * kBlockW + a, its
// gradient looked up once. A sample with cell (ib + di, jb + dj) takes its corners from lanes
// dj * kBlockW + di, that + (1 or kBlockW), that + kBlockW + 1, if every lane of its vector has
// di <= kBlockW - 2 and dj <= kBlockH - 2; otherwise its vector hashes the corners itself.
template <bool kAccumulate>
void SimplexRowsImpl(const SimplexRows& in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
  const DF df;
  const DU du;
  const DI di;
  constexpr std::size_t kLanes = HWY_LANES(float);
  constexpr int kBlockW = kLanes >= 8 ? 4 : kLanes >= 4 ? 2 : 0;
  constexpr int kBlockH = kLanes >= 16 ? 4 : kLanes >= 4 ? 2 : 0;
  constexpr int kShiftW = kBlockW == 4 ? 2 : 1;
  const VU px = hn::Set(du, kHashPrimeX), py = hn::Set(du, kHashPrimeY), vkey = hn::Set(du, key);
  const VU one_u = hn::Set(du, 1u);
  const VF one = hn::Set(df, 1.0f), vg2 = hn::Set(df, static_cast<float>(reference::kSimplexG2));
  const VF vscale = hn::Set(df, scale * reference::kSimplexScale);
  const Gradients g;
  VU block_x = hn::Zero(du), block_y = hn::Zero(du);
  if constexpr (kBlockW > 0) {
    alignas(64) std::uint32_t ox[kLanes], oy[kLanes];
    for (std::size_t l = 0; l < kLanes; ++l) {
      // (the max() keeps the scalar target, where this branch is compiled but never taken, free of / 0)
      ox[l] = static_cast<std::uint32_t>(l % std::max(kBlockW, 1)) * kHashPrimeX;
      oy[l] = static_cast<std::uint32_t>((l / std::max(kBlockW, 1)) % std::max(kBlockH, 1)) * kHashPrimeY;
    }
    block_x = hn::Load(du, ox);
    block_y = hn::Load(du, oy);
  }
  VF row_fi[kMaxRows], row_fj[kMaxRows];
  VU row_ci[kMaxRows], row_cj[kMaxRows];
  for (int r = 0; r < in.rows; ++r) {
    row_fi[r] = hn::Set(df, in.row_fi[r]);
    row_fj[r] = hn::Set(df, in.row_fj[r]);
    row_ci[r] = hn::Set(du, in.row_ci[r]);
    row_cj[r] = hn::Set(du, in.row_cj[r]);
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(n); k += hn::Lanes(df)) {
    const VU ca = hn::LoadU(du, in.ci + k), cd = hn::LoadU(du, in.cj + k);
    const VF fa = hn::LoadU(df, in.fi + k), fd = hn::LoadU(df, in.fj + k);
    // The block's origin: the cell of the first row's first sample (any cell would do; this one makes the
    // block cover the run).
    const float sx0 = in.fi[k] + in.row_fi[0], sy0 = in.fj[k] + in.row_fj[0];
    const std::uint32_t ib = in.ci[k] + in.row_ci[0] + (sx0 >= 1.0f ? 1u : 0u);
    const std::uint32_t jb = in.cj[k] + in.row_cj[0] + (sy0 >= 1.0f ? 1u : 0u);
    Gradients::Vector block{};
    if constexpr (kBlockW > 0) {
      const VU vertex = hn::Xor(hn::Add(hn::Set(du, ib * kHashPrimeX), block_x),
                                hn::Xor(hn::Add(hn::Set(du, jb * kHashPrimeY), block_y), vkey));
      block = g.Lookup(MixTop(vertex));
    }
    for (int r = 0; r < in.rows; ++r) {
      // Skewed fractions X, Y in [0, 1) with their carries into the cells, then unskewed.
      VF sx = hn::Add(fa, row_fi[r]), sy = hn::Add(fd, row_fj[r]);
      const auto carry_x = sx >= one, carry_y = sy >= one;
      sx = hn::Sub(sx, hn::IfThenElseZero(carry_x, one));
      sy = hn::Sub(sy, hn::IfThenElseZero(carry_y, one));
      const VU ci = hn::Add(hn::Add(ca, row_ci[r]), hn::IfThenElseZero(hn::RebindMask(du, carry_x), one_u));
      const VU cj = hn::Add(hn::Add(cd, row_cj[r]), hn::IfThenElseZero(hn::RebindMask(du, carry_y), one_u));
      const VF t = hn::Mul(hn::Add(sx, sy), vg2);
      const VF x0 = hn::Sub(sx, t), y0 = hn::Sub(sy, t);
      const SimplexCorners c(x0, y0);
      VF sum;
      bool in_block = false;
      VU i0;
      if constexpr (kBlockW > 0) {
        const VU dx = hn::Sub(ci, hn::Set(du, ib)), dy = hn::Sub(cj, hn::Set(du, jb));
        // Unsigned: a cell before the block's origin wraps to a large number.
        in_block = hn::AllTrue(du, hn::And(hn::Lt(dx, hn::Set(du, kBlockW - 1)), hn::Lt(dy, hn::Set(du, kBlockH - 1))));
        i0 = hn::Add(hn::ShiftLeft<kShiftW>(dy), dx);
      }
      if (in_block) {
        const VU i1 = hn::Add(i0, hn::IfThenElse(hn::RebindMask(du, c.lower), one_u, hn::Set(du, kBlockW)));
        const VU i2 = hn::Add(i0, hn::Set(du, kBlockW + 1));
        const auto pick = [&](VU lane) {
          const auto idx = hn::IndicesFromVec(df, hn::BitCast(di, lane));
          return Gradients::Vector{hn::TableLookupLanes(block.x, idx), hn::TableLookupLanes(block.y, idx)};
        };
        sum = hn::Add(hn::Add(SimplexCorner(x0, y0, pick(i0)), SimplexCorner(c.x1, c.y1, pick(i1))),
                      SimplexCorner(c.x2, c.y2, pick(i2)));
      } else {
        sum = SimplexHashed(x0, y0, c, hn::Mul(ci, px), hn::Mul(cj, py), vkey, g);
      }
      Put<kAccumulate>(hn::Mul(sum, vscale), out + r * stride, k);
    }
  }
}

// Inserts d into the sorted F1..F_rank kept in f[].
template <int kRank>
HWY_INLINE void Insert(VF (&f)[4], VF d) {
  if constexpr (kRank == 1) {
    f[0] = hn::Min(f[0], d);
  } else {
    VF t = d;
    for (int r = 0; r < kRank; ++r) {
      const VF lo = hn::Min(f[r], t);
      if (r + 1 < kRank) t = hn::Max(f[r], t);
      f[r] = lo;
    }
  }
}

template <WorleyMetric kMetric>
HWY_INLINE VF WorleyDistance(VF qx, VF qy) {
  if constexpr (kMetric == WorleyMetric::Euclidean) {
    return hn::MulAdd(qx, qx, hn::Mul(qy, qy));  // squared: same order, one sqrt at the end
  } else if constexpr (kMetric == WorleyMetric::Manhattan) {
    return hn::Add(hn::Abs(qx), hn::Abs(qy));
  } else {
    return hn::Max(hn::Abs(qx), hn::Abs(qy));
  }
}

template <WorleyMetric kMetric, WorleyOutput kOutput>
HWY_INLINE VF WorleyValue(VF (&f)[4]) {
  constexpr int kRank = worley_rank(kOutput);
  const DF df;
  if constexpr (kMetric == WorleyMetric::Euclidean)
    for (int r = 0; r < kRank; ++r) f[r] = hn::Sqrt(f[r]);
  if constexpr (kOutput == WorleyOutput::F1)
    return f[0];
  else if constexpr (kOutput == WorleyOutput::F2)
    return f[1];
  else if constexpr (kOutput == WorleyOutput::F2MinusF1)
    return hn::Sub(f[1], f[0]);
  else if constexpr (kOutput == WorleyOutput::F1TimesF2)
    return hn::Mul(f[0], f[1]);
  else
    return hn::Mul(hn::Add(hn::Add(f[0], f[1]), hn::Add(f[2], f[3])), hn::Set(df, 0.25f));
}

// Worley: per sample, the nearest feature points among the neighbourhood's cells (mirrored per axis, see
// worley_neighbourhood.h). With rows sharing a lattice row (kRowY), a cell's feature point depends only on
// the column and on the rows' mirror state on y (two states), so for each vector of columns the hashes and
// the x offsets are computed once per state and shared by every row of the run: per row and cell only the
// y offset, the distance and the insertion remain. The arithmetic per sample is the same in both forms.
template <WorleyMetric kMetric, WorleyOutput kOutput, bool kRowY, bool kAccumulate>
void WorleyImpl(const LatticeRun in, std::uint32_t key, const WorleyRun& search, int n, float* out,
                std::ptrdiff_t stride, float scale) {
  constexpr int kRank = worley_rank(kOutput);
  const DF df;
  const DU du;
  const int count = search.offset_count;
  // Per offset: its hash contribution and float value, for both mirror states (+d and -d).
  std::uint32_t hx[kMaxWorleyOffsets], hx_m[kMaxWorleyOffsets], hy[kMaxWorleyOffsets], hy_m[kMaxWorleyOffsets];
  float ox[kMaxWorleyOffsets], oy[kMaxWorleyOffsets];
  for (int o = 0; o < count; ++o) {
    const auto dx = static_cast<std::uint32_t>(search.offset_x[o]), dy = static_cast<std::uint32_t>(search.offset_y[o]);
    hx[o] = dx * kHashPrimeX;
    hx_m[o] = (0u - dx) * kHashPrimeX;
    hy[o] = dy * kHashPrimeY;
    hy_m[o] = (0u - dy) * kHashPrimeY;
    ox[o] = static_cast<float>(search.offset_x[o]);
    oy[o] = static_cast<float>(search.offset_y[o]);
  }
  const VU vkey = hn::Set(du, key), second = hn::Set(du, kSecondDraw);
  const float base_scalar = 0.5f - 0.5f * search.jitter;
  const VF jitter = hn::Set(df, search.jitter), half = hn::Set(df, 0.5f);
  const VF base = hn::Set(df, base_scalar);
  const VF vscale = hn::Set(df, scale);
  const VF inf = hn::Set(df, std::numeric_limits<float>::infinity());

  if constexpr (kRowY) {
    const int rows = in.rows;
    bool state_used[2] = {false, false};  // [1]: rows in the lower half of the cell (mirrored on y)
    for (int r = 0; r < rows; ++r) state_used[in.row_fy[r] < 0.5f ? 1 : 0] = true;
    // Per state and offset, for the current vector of columns: x offset qx and the draw r_y.
    constexpr std::size_t kL = HWY_MAX_BYTES / sizeof(float);
    HWY_ALIGN float qx_of[2][kMaxWorleyOffsets][kL];
    HWY_ALIGN float ry_of[2][kMaxWorleyOffsets][kL];
    // Per row and offset: dy + (base - fy), the y offset before the jittered draw.
    float qy0[kMaxRows][kMaxWorleyOffsets];
    int row_state[kMaxRows];
    for (int r = 0; r < rows; ++r) {
      row_state[r] = in.row_fy[r] < 0.5f ? 1 : 0;
      const float by = base_scalar - in.row_fy[r];
      for (int o = 0; o < count; ++o) qy0[r][o] = (row_state[r] ? -oy[o] : oy[o]) + by;
    }
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const VU xb = hn::LoadU(du, in.hx + i);
      const VF fx = hn::LoadU(df, in.fx + i);
      const auto mirror_x = fx < half;
      const auto mirror_xu = hn::RebindMask(du, mirror_x);
      const VF bx = hn::Sub(base, fx);
      for (int state = 0; state < 2; ++state) {
        if (!state_used[state]) continue;
        for (int o = 0; o < count; ++o) {
          const VU xo = hn::IfThenElse(mirror_xu, hn::Set(du, hx_m[o]), hn::Set(du, hx[o]));
          const VU y = hn::Set(du, in.row_hy + (state ? hy_m[o] : hy[o]));
          const VU h = Mix(hn::Xor(hn::Xor(hn::Add(xb, xo), y), vkey));
          const VF dxf = hn::IfThenElse(mirror_x, hn::Set(df, -ox[o]), hn::Set(df, ox[o]));
          hn::Store(hn::MulAdd(jitter, UnitFloat(h), hn::Add(dxf, bx)), df, qx_of[state][o]);
          hn::Store(UnitFloat(hn::Mul(h, second)), df, ry_of[state][o]);
        }
      }
      for (int r = 0; r < rows; ++r) {
        const int state = row_state[r];
        VF f[4] = {inf, inf, inf, inf};
        for (int o = 0; o < count; ++o) {
          const VF qx = hn::Load(df, qx_of[state][o]);
          const VF qy = hn::MulAdd(jitter, hn::Load(df, ry_of[state][o]), hn::Set(df, qy0[r][o]));
          Insert<kRank>(f, WorleyDistance<kMetric>(qx, qy));
        }
        Put<kAccumulate>(hn::Mul(WorleyValue<kMetric, kOutput>(f), vscale), out + r * stride, i);
      }
    }
  } else {
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
      const LatticeLanes c = LoadLattice<false>(in, i);
      const auto mirror_x = c.fx < half, mirror_y = c.fy < half;  // sample in the lower half: mirror offsets
      const auto mirror_xu = hn::RebindMask(du, mirror_x), mirror_yu = hn::RebindMask(du, mirror_y);
      const VU xb = c.hx, yb = c.hy;
      const VF bx = hn::Sub(base, c.fx), by = hn::Sub(base, c.fy);
      VF f[4] = {inf, inf, inf, inf};
      for (int o = 0; o < count; ++o) {
        const VU xo = hn::IfThenElse(mirror_xu, hn::Set(du, hx_m[o]), hn::Set(du, hx[o]));
        const VU yo = hn::IfThenElse(mirror_yu, hn::Set(du, hy_m[o]), hn::Set(du, hy[o]));
        const VU h = Mix(hn::Xor(hn::Xor(hn::Add(xb, xo), hn::Add(yb, yo)), vkey));
        const VF rx = UnitFloat(h), ry = UnitFloat(hn::Mul(h, second));
        const VF dxf = hn::IfThenElse(mirror_x, hn::Set(df, -ox[o]), hn::Set(df, ox[o]));
        const VF dyf = hn::IfThenElse(mirror_y, hn::Set(df, -oy[o]), hn::Set(df, oy[o]));
        const VF qx = hn::MulAdd(jitter, rx, hn::Add(dxf, bx));
        const VF qy = hn::MulAdd(jitter, ry, hn::Add(dyf, by));
        Insert<kRank>(f, WorleyDistance<kMetric>(qx, qy));
      }
      Put<kAccumulate>(hn::Mul(WorleyValue<kMetric, kOutput>(f), vscale), out, i);
    }
  }
}

// Turns the run-time choices (y per row or per sample, accumulate or store) into template arguments.
template <template <bool, bool> class Impl, class... Args>
void DispatchLattice(const LatticeRun& in, const Output& o, Args&&... args) {
  const bool row_y = in.hy == nullptr;
  if (row_y && o.accumulate)
    Impl<true, true>::run(in, args..., o.out, o.stride, o.scale);
  else if (row_y)
    Impl<true, false>::run(in, args..., o.out, o.stride, o.scale);
  else if (o.accumulate)
    Impl<false, true>::run(in, args..., o.out, o.stride, o.scale);
  else
    Impl<false, false>::run(in, args..., o.out, o.stride, o.scale);
}

template <bool A, bool B>
struct PerlinOp {
  static void run(const LatticeRun& in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
    PerlinImpl<A, B>(in, key, n, out, stride, scale);
  }
};
template <bool A, bool B>
struct ValueOp {
  static void run(const LatticeRun& in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
    ValueImpl<A, B>(in, key, n, out, stride, scale);
  }
};
template <bool A, bool B>
struct WhiteOp {
  static void run(const LatticeRun& in, std::uint32_t key, int n, float* out, std::ptrdiff_t stride, float scale) {
    WhiteImpl<A, B>(in, key, n, out, stride, scale);
  }
};

void Perlin(const LatticeRun& in, std::uint32_t key, int n, const Output& o) {
  DispatchLattice<PerlinOp>(in, o, key, n);
}
void Value(const LatticeRun& in, std::uint32_t key, int n, const Output& o) { DispatchLattice<ValueOp>(in, o, key, n); }
void White(const LatticeRun& in, std::uint32_t key, int n, const Output& o) { DispatchLattice<WhiteOp>(in, o, key, n); }
void Simplex(const SimplexRun& in, std::uint32_t key, int n, const Output& o) {
  if (o.accumulate)
    SimplexImpl<true>(in, key, n, o.out, o.scale);
  else
    SimplexImpl<false>(in, key, n, o.out, o.scale);
}
void SimplexRowsKernel(const SimplexRows& in, std::uint32_t key, int n, const Output& o) {
  if (o.accumulate)
    SimplexRowsImpl<true>(in, key, n, o.out, o.stride, o.scale);
  else
    SimplexRowsImpl<false>(in, key, n, o.out, o.stride, o.scale);
}

template <WorleyMetric M, WorleyOutput O>
struct WorleyOf {
  template <bool A, bool B>
  struct Op {
    static void run(const LatticeRun& in, std::uint32_t key, const WorleyRun& s, int n, float* out,
                    std::ptrdiff_t stride, float scale) {
      WorleyImpl<M, O, A, B>(in, key, s, n, out, stride, scale);
    }
  };
};

template <WorleyMetric M>
void WorleyMetricDispatch(const LatticeRun& in, std::uint32_t key, const WorleyRun& s, int n, const Output& o) {
  switch (s.output) {
    case WorleyOutput::F1:
      DispatchLattice<WorleyOf<M, WorleyOutput::F1>::template Op>(in, o, key, s, n);
      break;
    case WorleyOutput::F2:
      DispatchLattice<WorleyOf<M, WorleyOutput::F2>::template Op>(in, o, key, s, n);
      break;
    case WorleyOutput::F2MinusF1:
      DispatchLattice<WorleyOf<M, WorleyOutput::F2MinusF1>::template Op>(in, o, key, s, n);
      break;
    case WorleyOutput::F1TimesF2:
      DispatchLattice<WorleyOf<M, WorleyOutput::F1TimesF2>::template Op>(in, o, key, s, n);
      break;
    case WorleyOutput::MeanF1ToF4:
      DispatchLattice<WorleyOf<M, WorleyOutput::MeanF1ToF4>::template Op>(in, o, key, s, n);
      break;
  }
}

void Worley(const LatticeRun& in, std::uint32_t key, const WorleyRun& s, int n, const Output& o) {
  switch (s.metric) {
    case WorleyMetric::Euclidean:
      WorleyMetricDispatch<WorleyMetric::Euclidean>(in, key, s, n, o);
      break;
    case WorleyMetric::Manhattan:
      WorleyMetricDispatch<WorleyMetric::Manhattan>(in, key, s, n, o);
      break;
    case WorleyMetric::Chebyshev:
      WorleyMetricDispatch<WorleyMetric::Chebyshev>(in, key, s, n, o);
      break;
  }
}

// ---------------------------------------------------------------------------------------------------
// Fractal combination

void BillowStep(const float* noise, float amp, bool first, int n, float* sum) {
  const DF df;
  const VF a2 = hn::Set(df, 2.0f * amp), na = hn::Set(df, -amp);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    const VF term = hn::MulAdd(hn::Abs(hn::LoadU(df, noise + i)), a2, na);
    hn::StoreU(first ? term : hn::Add(hn::LoadU(df, sum + i), term), df, sum + i);
  }
}

void RidgedStep(const float* noise, float amp, float offset, bool first, int n, float* sum, float* prev) {
  const DF df;
  const VF vamp = hn::Set(df, amp), voff = hn::Set(df, offset), two = hn::Set(df, 2.0f);
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    const VF r = hn::Sub(voff, hn::Abs(hn::LoadU(df, noise + i)));
    VF s = hn::Mul(r, r);
    if (!first) s = hn::Mul(s, hn::Min(one, hn::Max(zero, hn::Mul(hn::LoadU(df, prev + i), two))));
    hn::StoreU(s, df, prev + i);
    hn::StoreU(first ? hn::Mul(s, vamp) : hn::MulAdd(s, vamp, hn::LoadU(df, sum + i)), df, sum + i);
  }
}

void HybridStep(const float* noise, float amp, float offset, bool first, int n, float* sum, float* weight) {
  const DF df;
  const VF vamp = hn::Set(df, amp), voff = hn::Set(df, offset), one = hn::Set(df, 1.0f);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    const VF s = hn::Mul(hn::Add(hn::LoadU(df, noise + i), voff), vamp);
    if (first) {
      hn::StoreU(s, df, sum + i);
      hn::StoreU(s, df, weight + i);
    } else {
      const VF w = hn::Min(hn::LoadU(df, weight + i), one);
      hn::StoreU(hn::MulAdd(w, s, hn::LoadU(df, sum + i)), df, sum + i);
      hn::StoreU(hn::Mul(w, s), df, weight + i);
    }
  }
}

void MultifractalStep(const float* noise, const float* q, bool first, int n, float* sum, float* w) {
  const DF df;
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    const VF nv = hn::LoadU(df, noise + i);
    if (first) {
      hn::StoreU(nv, df, sum + i);
      hn::StoreU(hn::LoadU(df, q + i), df, w + i);
    } else {
      const VF wv = hn::LoadU(df, w + i);
      hn::StoreU(hn::MulAdd(wv, nv, hn::LoadU(df, sum + i)), df, sum + i);
      hn::StoreU(hn::Mul(wv, hn::LoadU(df, q + i)), df, w + i);
    }
  }
}

void RoughnessRatio(const float* roughness, float ln_r, int n, float* q) {
  const DF df;
  const VF vln = hn::Set(df, ln_r), one = hn::Set(df, 1.0f);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df))
    hn::StoreU(hn::Exp(df, hn::Mul(vln, hn::Sub(hn::LoadU(df, roughness + i), one))), df, q + i);
}

void Finish(const float* sum, const float* amplitude, float scale, int n, float* out) {
  const DF df;
  const VF vs = hn::Set(df, scale);
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); i += hn::Lanes(df)) {
    VF v = hn::Mul(hn::LoadU(df, sum + i), vs);
    if (amplitude) v = hn::Mul(v, hn::LoadU(df, amplitude + i));
    hn::StoreU(v, df, out + i);
  }
}

}  // namespace orogen::noise::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace orogen::noise::kernels {

HWY_EXPORT(Displaced);
HWY_EXPORT(SplitLattice);
HWY_EXPORT(SimplexSkew);
HWY_EXPORT(Perlin);
HWY_EXPORT(Value);
HWY_EXPORT(White);
HWY_EXPORT(Simplex);
HWY_EXPORT(SimplexRowsKernel);
HWY_EXPORT(Worley);
HWY_EXPORT(BillowStep);
HWY_EXPORT(RidgedStep);
HWY_EXPORT(HybridStep);
HWY_EXPORT(MultifractalStep);
HWY_EXPORT(RoughnessRatio);
HWY_EXPORT(Finish);

void displaced(const double* x, double x_const, const float* warp, double frequency, double shift, int n, double* u) {
  assert(n % kBatchAlign == 0);
  HWY_DYNAMIC_DISPATCH(Displaced)(x, x_const, warp, frequency, shift, n, u);
}
void split_lattice(const double* u, std::uint32_t multiplier, int n, std::uint32_t* cell, float* frac) {
  assert(n % kBatchAlign == 0);
  HWY_DYNAMIC_DISPATCH(SplitLattice)(u, multiplier, n, cell, frac);
}
void simplex_skew(const double* u, const double* v, double v_const, int n, std::uint32_t* i, std::uint32_t* j,
                  float* x0, float* y0) {
  assert(n % kBatchAlign == 0);
  HWY_DYNAMIC_DISPATCH(SimplexSkew)(u, v, v_const, n, i, j, x0, y0);
}
void perlin(const LatticeRun& in, std::uint32_t key, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  assert(in.rows >= 1 && in.rows <= kMaxRows && (in.hy == nullptr || in.rows == 1));
  HWY_DYNAMIC_DISPATCH(Perlin)(in, key, n, out);
}
void value(const LatticeRun& in, std::uint32_t key, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  assert(in.rows >= 1 && in.rows <= kMaxRows && (in.hy == nullptr || in.rows == 1));
  HWY_DYNAMIC_DISPATCH(Value)(in, key, n, out);
}
void white(const LatticeRun& in, std::uint32_t key, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  assert(in.rows >= 1 && in.rows <= kMaxRows && (in.hy == nullptr || in.rows == 1));
  HWY_DYNAMIC_DISPATCH(White)(in, key, n, out);
}
void simplex(const SimplexRun& in, std::uint32_t key, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  HWY_DYNAMIC_DISPATCH(Simplex)(in, key, n, out);
}
void simplex_rows(const SimplexRows& in, std::uint32_t key, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  assert(in.rows >= 1 && in.rows <= kMaxRows);
  HWY_DYNAMIC_DISPATCH(SimplexRowsKernel)(in, key, n, out);
}
void worley(const LatticeRun& in, std::uint32_t key, const WorleyRun& search, int n, const Output& out) {
  assert(n % kBatchAlign == 0);
  assert(search.offset_count <= kMaxWorleyOffsets);
  assert(in.rows >= 1 && in.rows <= kMaxRows && (in.hy == nullptr || in.rows == 1));
  HWY_DYNAMIC_DISPATCH(Worley)(in, key, search, n, out);
}
void billow_step(const float* noise, float amp, bool first, int n, float* sum) {
  HWY_DYNAMIC_DISPATCH(BillowStep)(noise, amp, first, n, sum);
}
void ridged_step(const float* noise, float amp, float offset, bool first, int n, float* sum, float* prev) {
  HWY_DYNAMIC_DISPATCH(RidgedStep)(noise, amp, offset, first, n, sum, prev);
}
void hybrid_step(const float* noise, float amp, float offset, bool first, int n, float* sum, float* weight) {
  HWY_DYNAMIC_DISPATCH(HybridStep)(noise, amp, offset, first, n, sum, weight);
}
void multifractal_step(const float* noise, const float* q, bool first, int n, float* sum, float* w) {
  HWY_DYNAMIC_DISPATCH(MultifractalStep)(noise, q, first, n, sum, w);
}
void roughness_ratio(const float* roughness, float ln_r, int n, float* q) {
  HWY_DYNAMIC_DISPATCH(RoughnessRatio)(roughness, ln_r, n, q);
}
void finish(const float* sum, const float* amplitude, float scale, int n, float* out) {
  HWY_DYNAMIC_DISPATCH(Finish)(sum, amplitude, scale, n, out);
}

const char* active_target() {
  const std::int64_t available = hwy::SupportedTargets() & HWY_TARGETS;
  return hwy::TargetName(available & -available);  // lowest bit = best target
}

std::vector<std::int64_t> available_targets() {
  std::vector<std::int64_t> out;
  for (std::int64_t t = hwy::SupportedTargets() & HWY_TARGETS; t != 0; t &= t - 1) out.push_back(t & -t);
  return out;
}

const char* target_name(std::int64_t target) { return hwy::TargetName(target); }

}  // namespace orogen::noise::kernels
#endif  // HWY_ONCE
