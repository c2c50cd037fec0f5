#include "nodes/common/resample.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orogen {
namespace {

// Sample coordinates within this distance of an integer are treated as exactly on the lattice.
constexpr double kSnap = 1e-7;

double snap(double u) {
  const double r = std::round(u);
  return std::abs(u - r) < kSnap ? r : u;
}

}  // namespace

void resample_bilinear_row(const Heightfield& source, const Domain& target, int j, std::span<float> out) {
  const double v = snap(source.domain.to_sample({0.0, target.y(j)}).y);
  for (int i = 0; i < target.width(); ++i) {
    const double u = snap(source.domain.to_sample({target.x(i), 0.0}).x);
    out[static_cast<std::size_t>(i)] = source.bilinear(u, v);
  }
}

Heightfield resample_bilinear(const Heightfield& source, const Domain& target) {
  Heightfield out(target);
  for (int j = 0; j < target.height(); ++j) resample_bilinear_row(source, target, j, out.row(j));
  return out;
}

BilinearRows bilinear_rows(const Domain& source, const Domain& target, int j) {
  const int h = source.height();
  double v = snap(source.to_sample({0.0, target.y(j)}).y);
  if (std::isnan(v)) return {};
  v = std::clamp(v, 0.0, static_cast<double>(h - 1));
  const int lower = std::min(static_cast<int>(v), std::max(h - 2, 0));
  return {lower, std::min(lower + 1, h - 1), v};
}

BilinearColumns bilinear_columns(const Domain& source, const Domain& target) {
  const int w = source.width();
  BilinearColumns columns;
  columns.left.resize(static_cast<std::size_t>(target.width()));
  columns.weight.resize(columns.left.size());
  for (int k = 0; k < target.width(); ++k) {
    double u = snap(source.to_sample({target.x(k), 0.0}).x);
    if (std::isnan(u)) {
      columns.left[static_cast<std::size_t>(k)] = -1;
      continue;
    }
    u = std::clamp(u, 0.0, static_cast<double>(w - 1));
    const int i = std::min(static_cast<int>(u), std::max(w - 2, 0));
    columns.left[static_cast<std::size_t>(k)] = i;
    columns.weight[static_cast<std::size_t>(k)] = u - i;
  }
  return columns;
}

void resample_bilinear_row(const Domain& source, std::span<const float> lower, std::span<const float> upper,
                           const BilinearRows& rows, const Domain& target, std::span<float> out) {
  resample_bilinear_row(bilinear_columns(source, target), lower, upper, rows, out);
}

// The arithmetic of Heightfield::bilinear, on two rows.
void resample_bilinear_row(const BilinearColumns& columns, std::span<const float> lower, std::span<const float> upper,
                           const BilinearRows& rows, std::span<float> out) {
  if (rows.lower < 0) {
    std::fill(out.begin(), out.end(), std::numeric_limits<float>::quiet_NaN());
    return;
  }
  const std::size_t last = lower.size() - 1;  // the right column of a one-column source is its only one
  const double fv = rows.v - rows.lower;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const int left = columns.left[k];
    if (left < 0) {
      out[k] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(left), right = std::min(i + 1, last);
    const double fu = columns.weight[k];
    const double a = lower[i], b = lower[right], c = upper[i], d = upper[right];
    out[k] = static_cast<float>((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv);
  }
}

float image_bilinear(const Image& image, int channel, double u, double v) {
  const int w = image.width(), h = image.height();
  if (std::isnan(u) || std::isnan(v)) return std::numeric_limits<float>::quiet_NaN();  // no position, no index
  u = std::clamp(u, 0.0, static_cast<double>(w - 1));
  v = std::clamp(v, 0.0, static_cast<double>(h - 1));
  const int i = std::min(static_cast<int>(u), std::max(w - 2, 0));
  const int j = std::min(static_cast<int>(v), std::max(h - 2, 0));
  const int i1 = std::min(i + 1, w - 1), j1 = std::min(j + 1, h - 1);
  const double fu = u - i, fv = v - j;
  const double a = image.pixel(i, j)[channel], b = image.pixel(i1, j)[channel];
  const double c = image.pixel(i, j1)[channel], d = image.pixel(i1, j1)[channel];
  return static_cast<float>((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv);
}

void resample_bilinear_row(const Image& source, const Domain& target, int j, std::span<float> out) {
  const double v = snap(source.domain.to_sample({0.0, target.y(j)}).y);
  const auto channels = static_cast<std::size_t>(source.channels);
  for (int i = 0; i < target.width(); ++i) {
    const double u = snap(source.domain.to_sample({target.x(i), 0.0}).x);
    for (int c = 0; c < source.channels; ++c)
      out[static_cast<std::size_t>(i) * channels + static_cast<std::size_t>(c)] = image_bilinear(source, c, u, v);
  }
}

Image resample_bilinear(const Image& source, const Domain& target) {
  Image out(target, source.channels);
  out.channel_names = source.channel_names;
  out.color = source.color;
  const std::size_t row = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(source.channels);
  for (int j = 0; j < target.height(); ++j) {
    float* first = out.data.data() + row * static_cast<std::size_t>(j);
    resample_bilinear_row(source, target, j, std::span<float>(first, row));
  }
  return out;
}

}  // namespace orogen
