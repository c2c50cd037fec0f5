#pragma once
// One float32 channel sampled on a Domain: heights in metres, masks in 0..1, moisture, flow, ...
// Row-major, row j holds the samples at world y = domain.y(j).
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "graph/domain.h"

namespace orogen {

struct Heightfield {
  Domain domain;
  std::vector<float> data;

  Heightfield() = default;
  explicit Heightfield(const Domain& d, float fill = 0.0f) : domain(d), data(d.sample_count(), fill) {}

  int width() const { return domain.width(); }
  int height() const { return domain.height(); }
  float& at(int i, int j) { return data[index(i, j)]; }
  float at(int i, int j) const { return data[index(i, j)]; }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(domain.width()) + static_cast<std::size_t>(i);
  }
  std::span<float> row(int j) { return {data.data() + index(0, j), static_cast<std::size_t>(width())}; }
  std::span<const float> row(int j) const { return {data.data() + index(0, j), static_cast<std::size_t>(width())}; }

  // Sample value at the nearest edge sample for indices outside the grid.
  float clamped(int i, int j) const;
  // Bilinear interpolation at continuous sample coordinates (column, row), clamped at the borders.
  float bilinear(double u, double v) const;
  // Bilinear interpolation at a world position.
  float sample_world(double x, double y) const;

  std::size_t byte_size() const { return data.size() * sizeof(float) + sizeof(*this); }
};

using HeightfieldPtr = std::shared_ptr<const Heightfield>;

}  // namespace orogen
