#pragma once
// Scalar reference implementations of the noise bases: one sample at a time, written for clarity. They
// define the noise; the SIMD kernels (noise_kernels.h) must agree with them to 1e-5 (tests check it), and
// the brute-force Worley search here is the oracle for the exactness of the kernels' neighbourhood.
//
// Coordinates (u, v) are in lattice cells (world metres times frequency, plus the octave's shift).
#include <array>
#include <cstdint>

#include "nodes/noise/noise_types.h"

namespace orogen::noise::reference {

// 2D Perlin noise with unit gradients has range [-sqrt(2)/2, sqrt(2)/2] (reached at cell centres when all
// four gradients point at them); scaling by sqrt(2) gives [-1, 1].
inline constexpr float kPerlinScale = 1.41421356237309505f;
// Simplex: the largest value of sum over the 3 corners of (1/2 - r^2)^4 * r (gradients aligned with the
// offsets) is 2 * (1/3)^4 * sqrt(1/6) = 0.0100802 at the midpoint of a simplex edge; its inverse maps
// the noise to [-1, 1]. The diagonal gradients along those edges are in the set, so the bound is reached.
inline constexpr float kSimplexScale = 99.2043345827f;
inline constexpr double kSimplexF2 = 0.36602540378443864676;  // (sqrt(3) - 1) / 2: skew
inline constexpr double kSimplexG2 = 0.21132486540518711775;  // (3 - sqrt(3)) / 6: unskew

struct LatticeCoord {
  std::uint32_t cell = 0;  // floor(u) modulo 2^32
  float frac = 0.0f;       // u - floor(u), in [0, 1]
};
LatticeCoord split(double u);

// Quintic fade 6t^5 - 15t^4 + 10t^3: zero first and second derivatives at 0 and 1.
constexpr float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

// Gradients: the 16 unit vectors at angles k * 22.5 degrees, k = the top 4 bits of the lattice hash. A
// proper 2D set: evenly spread directions, not Zaiz 2022's 3D edge vectors with z dropped (which collapse
// onto the axes); and more than the 8 axis-and-diagonal directions, whose lattice bias shows as a maze of
// horizontal and vertical streaks. Vector k + 8 is the negation of vector k, so the kernels look up the
// first half (kGradientX/Y) and flip the sign of the dot product with bit 31.
inline constexpr float kGradientX[8] = {1.0f, 0.923879532511f,  0.707106781187f,  0.382683432365f,
                                        0.0f, -0.382683432365f, -0.707106781187f, -0.923879532511f};
inline constexpr float kGradientY[8] = {0.0f, 0.382683432365f, 0.707106781187f, 0.923879532511f,
                                        1.0f, 0.923879532511f, 0.707106781187f, 0.382683432365f};
// g_k . (dx, dy) for k = hash >> 28, computed as fma(gx, dx, gy * dy) then negated for k >= 8.
float gradient_dot(std::uint32_t hash, float dx, float dy);

float perlin(double u, double v, std::uint32_t key);   // [-1, 1], 0 at lattice points
float value(double u, double v, std::uint32_t key);    // [-1, 1], random values at lattice points
float white(double u, double v, std::uint32_t key);    // [-1, 1], constant per cell
float simplex(double u, double v, std::uint32_t key);  // [-1, 1]

// Worley: the feature point of a lattice cell, relative to the sample's cell origin plus the sample's
// fraction as the kernels compute it: returns (point - sample) for the cell at integer offset (dx, dy)
// from the sample's cell.
std::array<float, 2> worley_offset(std::uint32_t cell_x, std::uint32_t cell_y, float frac_x, float frac_y, int dx,
                                   int dy, std::uint32_t key, float jitter);
// The metric as the kernels evaluate it in float.
float worley_distance(WorleyMetric metric, float px, float py);

struct WorleyDistances {
  std::array<float, 4> f{};  // F1 <= F2 <= F3 <= F4, in lattice cells
};
// Brute force: every feature point of the (2 * radius + 1)^2 cells around the sample, sorted. With
// radius >= 5 this is every point that can matter: worley_neighbourhood.h bounds F4 by 3 cells (Manhattan,
// jitter 1), and every point of a cell 5 or more cells away is farther than that.
WorleyDistances worley_brute_force(double u, double v, std::uint32_t key, WorleyMetric metric, float jitter,
                                   int radius = 6);
float worley_select(const WorleyDistances& d, WorleyOutput output);

float basis(Basis b, double u, double v, std::uint32_t key);  // Worley: F1, Euclidean, jitter 1

}  // namespace orogen::noise::reference
