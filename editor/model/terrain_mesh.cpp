#include "editor/model/terrain_mesh.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace orogen::editor {

namespace {
float linear_to_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}
}  // namespace

TerrainMesh build_terrain_mesh(const Heightfield& field, const TerrainMeshOptions& options) {
  TerrainMesh mesh;
  const int w = field.width(), h = field.height();
  if (w < 2 || h < 2) return mesh;
  const int stride = std::max(1, (std::max(w, h) + options.max_side - 2) / std::max(2, options.max_side - 1));
  // Sample indices along each axis: every stride-th, always including the last.
  auto samples = [stride](int n) {
    std::vector<int> s;
    for (int k = 0; k < n - 1; k += stride) s.push_back(k);
    s.push_back(n - 1);
    return s;
  };
  const auto cols = samples(w), rows = samples(h);
  mesh.columns = static_cast<int>(cols.size());
  mesh.rows = static_cast<int>(rows.size());
  const float vs = options.vertical_scale;
  const ValueRange range = value_range(field);
  const double sx = field.domain.spacing.x, sy = field.domain.spacing.y;

  mesh.positions.reserve(cols.size() * rows.size());
  mesh.normals.reserve(cols.size() * rows.size());
  mesh.colors.reserve(cols.size() * rows.size());
  mesh.min = glm::vec3(std::numeric_limits<float>::max());
  mesh.max = glm::vec3(-std::numeric_limits<float>::max());
  for (int j : rows)
    for (int i : cols) {
      float z = field.at(i, j);
      if (!std::isfinite(z)) z = range.lo;
      const glm::vec3 p(static_cast<float>(field.domain.x(i)), static_cast<float>(field.domain.y(j)), z * vs);
      mesh.positions.push_back(p);
      mesh.min = glm::min(mesh.min, p);
      mesh.max = glm::max(mesh.max, p);
      // Normal of the (scaled) surface from central differences on the full-resolution samples.
      const int i0 = std::max(i - stride, 0), i1 = std::min(i + stride, w - 1);
      const int j0 = std::max(j - stride, 0), j1 = std::min(j + stride, h - 1);
      const float dzdx = vs * (field.at(i1, j) - field.at(i0, j)) / static_cast<float>((i1 - i0) * sx);
      const float dzdy = vs * (field.at(i, j1) - field.at(i, j0)) / static_cast<float>((j1 - j0) * sy);
      glm::vec3 n = glm::normalize(glm::vec3(-dzdx, -dzdy, 1.0f));
      if (!std::isfinite(n.x + n.y + n.z)) n = {0.0f, 0.0f, 1.0f};
      mesh.normals.push_back(n);

      glm::vec4 c(colormap(options.map, (z - range.lo) / (range.hi - range.lo)), 1.0f);
      if (const Image* img = options.drape; img && img->channels > 0) {
        const glm::dvec2 s = img->domain.to_sample({p.x, p.y});
        const int u = std::clamp(static_cast<int>(std::lround(s.x)), 0, img->width() - 1);
        const int v = std::clamp(static_cast<int>(std::lround(s.y)), 0, img->height() - 1);
        const float* px = img->pixel(u, v);
        if (img->channels >= 3) c = {linear_to_srgb(px[0]), linear_to_srgb(px[1]), linear_to_srgb(px[2]), 1.0f};
        else c = glm::vec4(glm::vec3(linear_to_srgb(px[0])), 1.0f);
      }
      mesh.colors.push_back(c);
    }

  const auto nc = static_cast<std::uint32_t>(cols.size());
  mesh.indices.reserve((cols.size() - 1) * (rows.size() - 1) * 6);
  for (std::uint32_t r = 0; r + 1 < rows.size(); ++r)
    for (std::uint32_t c = 0; c + 1 < nc; ++c) {
      const std::uint32_t a = r * nc + c, b = a + 1, d = a + nc, e = d + 1;
      // Counter-clockwise seen from above (+z): x right, y up.
      mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, d});
    }
  return mesh;
}

}  // namespace orogen::editor
