#pragma once
// Batch kernels of the noise generators: SIMD loops over a run of samples (part of a row), compiled for
// every x86-64 level by Highway and chosen at run time (SSE4, AVX2, AVX-512, or plain scalar code on
// older machines). No virtual call and no branch per sample: choices (basis, metric, output, mode) are
// made once per batch.
//
// Conventions:
//  - `n` is a multiple of kBatchAlign; every input array holds valid numbers for all n entries and every
//    output array has room for n. Callers pad a row's tail with real (outside-the-domain) coordinates, so
//    every sample goes through the same vector code whatever its position in a row: a sample's value
//    depends only on its coordinates, never on which domain or tile computed it.
//  - Lattice coordinates are an integer cell taken modulo 2^32 plus a float fraction in [0, 1], split in
//    double precision so that worlds far from the origin keep full float precision in the fraction.
//  - The scalar reference (noise_reference.h) implements the same mathematics independently; tests check
//    that both agree to 1e-5.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/noise/noise_types.h"

namespace orogen::noise::kernels {

// Row runs are padded to a multiple of the widest float vector on x86 (AVX-512: 16 lanes).
inline constexpr int kBatchAlign = 16;
constexpr int padded(int n) { return (n + kBatchAlign - 1) / kBatchAlign * kBatchAlign; }

// Lattice coordinates of a run of samples. The integer cells come pre-multiplied by the hash primes
// (hx = cell_x * kHashPrimeX, hy = cell_y * kHashPrimeY, modulo 2^32): every kernel starts the lattice
// hash with these products, and the next cell is one addition away (hx + kHashPrimeX).
//
// Two forms:
//  - per-sample y (hy, fy set; rows == 1): warped evaluation.
//  - shared lattice row (hy null): `rows` sample rows with the same x coordinates that all lie in lattice
//    row row_hy, with fractions row_fy[0..rows). This is the unwarped case, where neighbouring sample rows
//    usually fall in the same lattice row: the Perlin, Value, White and Worley kernels then hash each
//    lattice cell once for all those rows. Simplex (not a square lattice) has its own row form (SimplexRun).
//    The result of a row does not depend on which other rows share its batch.
inline constexpr int kMaxRows = 8;
struct LatticeRun {
  const std::uint32_t* hx = nullptr;
  const float* fx = nullptr;
  const std::uint32_t* hy = nullptr;
  const float* fy = nullptr;
  std::uint32_t row_hy = 0;
  const float* row_fy = nullptr;
  int rows = 1;
};

// Simplex coordinates of warped samples: skewed cell (i, j), pre-multiplied like LatticeRun
// (hi = i * kHashPrimeX, hj = j * kHashPrimeY), and the unskewed offset (x0, y0) from its origin.
struct SimplexRun {
  const std::uint32_t* hi = nullptr;
  const std::uint32_t* hj = nullptr;
  const float* x0 = nullptr;
  const float* y0 = nullptr;
};

// Unwarped simplex rows sharing their columns. The skewed coordinates are sums of a column term and a row
// term, (u + s, v + s) = (A + B, D + C) with A = u (1 + F2), D = u F2 per column and B = v F2, C = v (1 + F2)
// per row. Each term is split once, in double, into a wrapped lattice cell (not pre-multiplied here) and a
// fraction; a sample then only adds the fractions (a carry when they pass 1) and the cells, in float and
// integer lanes. The columns' split is shared by every row, so no per-sample double arithmetic is left, and
// the result depends only on the world coordinates of the sample's column and row (tile-invariant).
//
// Rows of a run lie close together, so a vector of columns over all of them touches few lattice vertices:
// the kernel hashes a small block of vertices once per vector of columns (one hash per lane) and each
// sample picks its three corners' gradients from it by lane permutation; a row whose vertices fall outside
// the block (sparse sampling) hashes its corners itself. Both give the same bits. Row r goes to
// out + r * stride.
struct SimplexRows {
  const std::uint32_t* ci = nullptr;  // cells of A
  const std::uint32_t* cj = nullptr;  // cells of D
  const float* fi = nullptr;          // fractions of A
  const float* fj = nullptr;          // fractions of D
  int rows = 1;
  std::uint32_t row_ci[kMaxRows] = {}, row_cj[kMaxRows] = {};  // cells of B and C
  float row_fi[kMaxRows] = {}, row_fj[kMaxRows] = {};          // fractions of B and C
};

// Where a basis kernel puts its result: out = scale * noise, or out += scale * noise when accumulating.
// Row r of a multi-row run goes to out + r * stride.
struct Output {
  float* out = nullptr;
  float scale = 1.0f;
  bool accumulate = false;
  std::ptrdiff_t stride = 0;
};

// Worley search: cell offsets (in the frame where the sample lies in the upper half of its cell on
// both axes; the kernel mirrors them per sample) from worley_neighbourhood.h.
inline constexpr int kMaxWorleyOffsets = 128;  // the largest neighbourhood (Manhattan, jitter 1, F4) has < 50
struct WorleyRun {
  WorleyMetric metric = WorleyMetric::Euclidean;
  WorleyOutput output = WorleyOutput::F1;
  float jitter = 1.0f;
  const std::int32_t* offset_x = nullptr;
  const std::int32_t* offset_y = nullptr;
  int offset_count = 0;
};

// ---- coordinate stages (double precision) ----

// u[k] = (x[k] + warp[k]) * frequency + shift; x may be null (then x_const for every sample), warp may be
// null (no displacement).
void displaced(const double* x, double x_const, const float* warp, double frequency, double shift, int n, double* u);

// hashed_cell[k] = (floor(u[k]) mod 2^32) * multiplier, frac[k] = u[k] - floor(u[k]) rounded to float.
void split_lattice(const double* u, std::uint32_t multiplier, int n, std::uint32_t* hashed_cell, float* frac);

// Skews (u, v) onto the simplex lattice (F2 = (sqrt3 - 1) / 2, G2 = (3 - sqrt3) / 6), giving the hashed
// cells of SimplexRun. v may be null (then v_const for every sample).
void simplex_skew(const double* u, const double* v, double v_const, int n, std::uint32_t* hi, std::uint32_t* hj,
                  float* x0, float* y0);

// ---- bases ----
void perlin(const LatticeRun& in, std::uint32_t key, int n, const Output& out);
void value(const LatticeRun& in, std::uint32_t key, int n, const Output& out);
void white(const LatticeRun& in, std::uint32_t key, int n, const Output& out);
void simplex(const SimplexRun& in, std::uint32_t key, int n, const Output& out);
void simplex_rows(const SimplexRows& in, std::uint32_t key, int n, const Output& out);
void worley(const LatticeRun& in, std::uint32_t key, const WorleyRun& search, int n, const Output& out);

// ---- fractal combination (one octave at a time; `first` marks octave 0) ----
// billow: sum += amp * (2|noise| - 1)
void billow_step(const float* noise, float amp, bool first, int n, float* sum);
// ridged (Musgrave): s = (offset - |noise|)^2 * w, w = clamp(2 * s_prev, 0, 1) (1 at octave 0);
// sum += amp * s; prev = s.
void ridged_step(const float* noise, float amp, float offset, bool first, int n, float* sum, float* prev);
// hybrid multifractal (Musgrave): s = (noise + offset) * amp; octave 0: sum = w = s; then
// w = min(w, 1), sum += w * s, w *= s.
void hybrid_step(const float* noise, float amp, float offset, bool first, int n, float* sum, float* weight);
// Weiss 2015 Eq 4: sum += w * noise, then w *= q (per sample).
void multifractal_step(const float* noise, const float* q, bool first, int n, float* sum, float* w);
// q = exp(ln_r * (roughness - 1)) = r^-(1 - R), per sample.
void roughness_ratio(const float* roughness, float ln_r, int n, float* q);
// out = scale * sum * (amplitude ? amplitude : 1)
void finish(const float* sum, const float* amplitude, float scale, int n, float* out);

// The instruction set the kernels run with on this machine (e.g. "AVX3", "AVX2", "SSE4", "SCALAR").
const char* active_target();
// Every instruction set the kernels were compiled for that this CPU supports (Highway target bits). Tests
// run each through hwy::SetSupportedTargetsForTest to check every code path against the reference.
std::vector<std::int64_t> available_targets();
const char* target_name(std::int64_t target);

}  // namespace orogen::noise::kernels
