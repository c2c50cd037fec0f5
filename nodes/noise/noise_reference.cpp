#include "nodes/noise/noise_reference.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "nodes/noise/lattice_hash.h"

namespace orogen::noise::reference {

LatticeCoord split(double u) {
  const double c = std::floor(u);
  // The cell modulo 2^32, exact for any integer-valued double, so the conversion is always defined.
  const double r = c - std::floor(c * 0x1.0p-32) * 0x1.0p32;
  if (!(r >= 0.0 && r < 0x1.0p32)) return {0, 0.0f};  // NaN or infinite coordinates
  return {static_cast<std::uint32_t>(r), static_cast<float>(u - c)};
}

float gradient_dot(std::uint32_t hash, float dx, float dy) {
  const std::uint32_t k = (hash >> 28) & 7u;
  const float d = std::fma(kGradientX[k], dx, kGradientY[k] * dy);
  return (hash & 0x80000000u) ? -d : d;
}

namespace {

float lerp(float a, float b, float t) { return a + t * (b - a); }
float signed_unit(std::uint32_t h) { return unit_float(h) * 2.0f - 1.0f; }

}  // namespace

float perlin(double u, double v, std::uint32_t key) {
  const LatticeCoord x = split(u), y = split(v);
  const float fx = x.frac, fy = y.frac;
  const float n00 = gradient_dot(lattice_hash(x.cell, y.cell, key), fx, fy);
  const float n10 = gradient_dot(lattice_hash(x.cell + 1, y.cell, key), fx - 1.0f, fy);
  const float n01 = gradient_dot(lattice_hash(x.cell, y.cell + 1, key), fx, fy - 1.0f);
  const float n11 = gradient_dot(lattice_hash(x.cell + 1, y.cell + 1, key), fx - 1.0f, fy - 1.0f);
  const float ux = fade(fx), uy = fade(fy);
  return kPerlinScale * lerp(lerp(n00, n10, ux), lerp(n01, n11, ux), uy);
}

float value(double u, double v, std::uint32_t key) {
  const LatticeCoord x = split(u), y = split(v);
  const float v00 = signed_unit(lattice_hash(x.cell, y.cell, key));
  const float v10 = signed_unit(lattice_hash(x.cell + 1, y.cell, key));
  const float v01 = signed_unit(lattice_hash(x.cell, y.cell + 1, key));
  const float v11 = signed_unit(lattice_hash(x.cell + 1, y.cell + 1, key));
  const float ux = fade(x.frac), uy = fade(y.frac);
  return lerp(lerp(v00, v10, ux), lerp(v01, v11, ux), uy);
}

float white(double u, double v, std::uint32_t key) {
  return signed_unit(lattice_hash(split(u).cell, split(v).cell, key));
}

float simplex(double u, double v, std::uint32_t key) {
  // Skew to find the simplex cell, in double so that far-away worlds keep their precision.
  const double s = (u + v) * kSimplexF2;
  const double i = std::floor(u + s), j = std::floor(v + s);
  const double t = (i + j) * kSimplexG2;
  const float x0 = static_cast<float>(u - (i - t)), y0 = static_cast<float>(v - (j - t));
  const std::uint32_t ci = split(i).cell, cj = split(j).cell;
  // The lower (x0 > y0) or upper triangle of the skewed cell.
  const std::uint32_t i1 = x0 > y0 ? 1 : 0, j1 = 1 - i1;
  constexpr float g2 = static_cast<float>(kSimplexG2);
  const float x1 = x0 - static_cast<float>(i1) + g2, y1 = y0 - static_cast<float>(j1) + g2;
  const float x2 = x0 - 1.0f + 2.0f * g2, y2 = y0 - 1.0f + 2.0f * g2;
  auto corner = [](float x, float y, std::uint32_t h) {
    const float w = std::max(0.0f, 0.5f - x * x - y * y);  // exactly 0 beyond the radius sqrt(1/2)
    const float w2 = w * w;
    return w2 * w2 * gradient_dot(h, x, y);
  };
  const float n = corner(x0, y0, lattice_hash(ci, cj, key)) + corner(x1, y1, lattice_hash(ci + i1, cj + j1, key)) +
                  corner(x2, y2, lattice_hash(ci + 1, cj + 1, key));
  return kSimplexScale * n;
}

std::array<float, 2> worley_offset(std::uint32_t cell_x, std::uint32_t cell_y, float frac_x, float frac_y, int dx,
                                   int dy, std::uint32_t key, float jitter) {
  const std::uint32_t h =
      lattice_hash(cell_x + static_cast<std::uint32_t>(dx), cell_y + static_cast<std::uint32_t>(dy), key);
  const float rx = unit_float(h), ry = unit_float(second_draw(h));
  // point = d + 1/2 + jitter * (r - 1/2); offset = point - frac, grouped as the kernels group it.
  const float base = 0.5f - 0.5f * jitter;
  return {std::fma(jitter, rx, static_cast<float>(dx) + (base - frac_x)),
          std::fma(jitter, ry, static_cast<float>(dy) + (base - frac_y))};
}

float worley_distance(WorleyMetric metric, float px, float py) {
  switch (metric) {
    case WorleyMetric::Euclidean:
      return std::sqrt(std::fma(px, px, py * py));
    case WorleyMetric::Manhattan:
      return std::fabs(px) + std::fabs(py);
    case WorleyMetric::Chebyshev:
      return std::max(std::fabs(px), std::fabs(py));
  }
  return 0.0f;
}

WorleyDistances worley_brute_force(double u, double v, std::uint32_t key, WorleyMetric metric, float jitter,
                                   int radius) {
  const LatticeCoord x = split(u), y = split(v);
  std::vector<float> d;
  d.reserve(static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1)));
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const auto p = worley_offset(x.cell, y.cell, x.frac, y.frac, dx, dy, key, jitter);
      d.push_back(worley_distance(metric, p[0], p[1]));
    }
  std::partial_sort(d.begin(), d.begin() + 4, d.end());
  return {{d[0], d[1], d[2], d[3]}};
}

float worley_select(const WorleyDistances& d, WorleyOutput output) {
  switch (output) {
    case WorleyOutput::F1:
      return d.f[0];
    case WorleyOutput::F2:
      return d.f[1];
    case WorleyOutput::F2MinusF1:
      return d.f[1] - d.f[0];
    case WorleyOutput::F1TimesF2:
      return d.f[0] * d.f[1];
    case WorleyOutput::MeanF1ToF4:
      return (d.f[0] + d.f[1] + d.f[2] + d.f[3]) * 0.25f;
  }
  return 0.0f;
}

float basis(Basis b, double u, double v, std::uint32_t key) {
  switch (b) {
    case Basis::Perlin:
      return perlin(u, v, key);
    case Basis::Simplex:
      return simplex(u, v, key);
    case Basis::Value:
      return value(u, v, key);
    case Basis::White:
      return white(u, v, key);
    case Basis::Worley:
      return worley_select(worley_brute_force(u, v, key, WorleyMetric::Euclidean, 1.0f), WorleyOutput::F1);
  }
  return 0.0f;
}

}  // namespace orogen::noise::reference
