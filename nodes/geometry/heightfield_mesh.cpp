#include "nodes/geometry/heightfield_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "nodes/common/resample.h"

namespace orogen {
namespace {

OpenMesh::Vec4f color_at(const Image& img, double x, double y) {
  const auto s = img.domain.to_sample({x, y});
  float c[4];
  const int n = std::min(img.channels, 4);
  for (int k = 0; k < n; ++k) c[k] = image_bilinear(img, k, s.x, s.y);
  switch (n) {
    case 1:
      return {c[0], c[0], c[0], 1.0f};
    case 2:
      return {c[0], c[0], c[0], c[1]};
    case 3:
      return {c[0], c[1], c[2], 1.0f};
    default:
      return {c[0], c[1], c[2], c[3]};
  }
}

// Surface normal of the heightfield at sample (i, j): central differences inside, one-sided at the border.
OpenMesh::Vec3f surface_normal(const Heightfield& h, int i, int j) {
  const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, h.width() - 1);
  const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, h.height() - 1);
  const double dzdx = (double(h.at(i1, j)) - h.at(i0, j)) / (h.domain.x(i1) - h.domain.x(i0));
  const double dzdy = (double(h.at(i, j1)) - h.at(i, j0)) / (h.domain.y(j1) - h.domain.y(j0));
  const double len = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
  return {static_cast<float>(-dzdx / len), static_cast<float>(-dzdy / len), static_cast<float>(1.0 / len)};
}

}  // namespace

Mesh heightfield_grid_mesh(const Heightfield& height, const Image* colors) {
  const int w = height.width(), h = height.height();
  if (w < 2 || h < 2) throw std::invalid_argument("a heightfield mesh needs at least 2 x 2 samples");
  if (static_cast<double>(w - 1) * (h - 1) * 2 > static_cast<double>(std::numeric_limits<int>::max() / 2))
    throw std::invalid_argument("the heightfield is too large for one mesh (" + height.domain.describe() + ")");
  if (colors && (colors->channels < 1 || colors->width() < 1 || colors->height() < 1))
    throw std::invalid_argument("the color image is empty");

  Mesh result;
  TriMesh& m = result.mesh;
  m.reserve(static_cast<std::size_t>(w) * h, static_cast<std::size_t>(w) * h * 3,
            static_cast<std::size_t>(w - 1) * (h - 1) * 2);
  std::vector<TriMesh::VertexHandle> v(static_cast<std::size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double x = height.domain.x(i), y = height.domain.y(j);
      const auto vh = m.add_vertex({static_cast<float>(x), static_cast<float>(y), height.at(i, j)});
      m.set_normal(vh, surface_normal(height, i, j));
      m.set_color(vh, colors ? color_at(*colors, x, y) : OpenMesh::Vec4f(1, 1, 1, 1));
      v[height.index(i, j)] = vh;
    }
  for (int j = 0; j + 1 < h; ++j)
    for (int i = 0; i + 1 < w; ++i) {
      // Corners counter-clockwise seen from +z: a (i, j), b (i+1, j), c (i+1, j+1), d (i, j+1).
      const auto a = v[height.index(i, j)], b = v[height.index(i + 1, j)];
      const auto c = v[height.index(i + 1, j + 1)], d = v[height.index(i, j + 1)];
      const double ac = (m.point(c) - m.point(a)).sqrnorm(), bd = (m.point(d) - m.point(b)).sqrnorm();
      if (ac <= bd) {
        m.add_face(a, b, c);
        m.add_face(a, c, d);
      } else {
        m.add_face(a, b, d);
        m.add_face(b, c, d);
      }
    }
  m.update_face_normals();
  return result;
}

Mesh heightfield_mesh(const Heightfield& height, const Image* colors, const TinOptions& options) {
  if (!(options.max_error > 0.0) && options.target_faces == 0) return heightfield_grid_mesh(height, colors);
  if (colors && (colors->channels < 1 || colors->width() < 1 || colors->height() < 1))
    throw std::invalid_argument("the color image is empty");
  const Tin tin = heightfield_tin(height, options);
  Mesh result;
  TriMesh& m = result.mesh;
  m.reserve(tin.samples.size(), tin.samples.size() + tin.triangles.size(), tin.triangles.size());
  std::vector<TriMesh::VertexHandle> v(tin.samples.size());
  for (std::size_t k = 0; k < tin.samples.size(); ++k) {
    const int i = tin.samples[k] % tin.width, j = tin.samples[k] / tin.width;
    const double x = height.domain.x(i), y = height.domain.y(j);
    v[k] = m.add_vertex({static_cast<float>(x), static_cast<float>(y), height.at(i, j)});
    m.set_normal(v[k], surface_normal(height, i, j));
    m.set_color(v[k], colors ? color_at(*colors, x, y) : OpenMesh::Vec4f(1, 1, 1, 1));
  }
  for (const auto& t : tin.triangles) m.add_face(v[t[0]], v[t[1]], v[t[2]]);
  m.update_face_normals();
  return result;
}

}  // namespace orogen
