#include "editor/model/terrain_mesh.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "nodes/common/color_space.h"

namespace orogen::editor {

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
  const ValueRange crange = options.color_range ? *options.color_range : range;
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

      glm::vec4 c(colormap(options.map, (z - crange.lo) / (crange.hi - crange.lo)), 1.0f);
      if (const Image* img = options.drape; img && img->channels > 0) {
        const glm::dvec2 s = img->domain.to_sample({p.x, p.y});
        const int u = std::clamp(static_cast<int>(std::lround(s.x)), 0, img->width() - 1);
        const int v = std::clamp(static_cast<int>(std::lround(s.y)), 0, img->height() - 1);
        const float* px = img->pixel(u, v);
        if (img->channels >= 3)
          c = {linear_to_srgb(px[0]), linear_to_srgb(px[1]), linear_to_srgb(px[2]), 1.0f};
        else
          c = glm::vec4(glm::vec3(linear_to_srgb(px[0])), 1.0f);
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

namespace {

std::vector<int> strided_samples(int n, int stride) {
  std::vector<int> s;
  for (int k = 0; k < n - 1; k += stride) s.push_back(k);
  s.push_back(n - 1);
  return s;
}

}  // namespace

TerrainMesh build_water_mesh(const Heightfield& terrain, const Heightfield& depth, const TerrainMeshOptions& options) {
  TerrainMesh mesh;
  const int w = terrain.width(), h = terrain.height();
  if (w < 2 || h < 2) return mesh;
  const int stride = std::max(1, (std::max(w, h) + options.max_side - 2) / std::max(2, options.max_side - 1));
  const auto cols = strided_samples(w, stride), rows = strided_samples(h, stride);
  const int nc = static_cast<int>(cols.size()), nr = static_cast<int>(rows.size());
  const bool same = depth.domain.width() == w && depth.domain.height() == h &&
                    depth.domain.min_corner() == terrain.domain.min_corner() &&
                    depth.domain.max_corner() == terrain.domain.max_corner();
  // Depth and water level at each vertex of the strided grid.
  std::vector<float> d(static_cast<std::size_t>(nc) * nr), level(d.size());
  float max_depth = 0.0f;
  for (int r = 0; r < nr; ++r)
    for (int c = 0; c < nc; ++c) {
      const int i = cols[static_cast<std::size_t>(c)], j = rows[static_cast<std::size_t>(r)];
      float v =
          same ? depth.at(i, j) : static_cast<float>(depth.sample_world(terrain.domain.x(i), terrain.domain.y(j)));
      if (!std::isfinite(v) || v < 0.0f) v = 0.0f;
      const std::size_t k = static_cast<std::size_t>(r) * nc + c;
      d[k] = v;
      level[k] = terrain.at(i, j) + v;
      max_depth = std::max(max_depth, v);
    }
  if (max_depth <= 0.0f) return mesh;
  // Dry vertices next to water take the mean level of their wet 8-neighbours.
  std::vector<float> shown = level;
  std::vector<char> near_water(d.size(), 0);
  for (int r = 0; r < nr; ++r)
    for (int c = 0; c < nc; ++c) {
      const std::size_t k = static_cast<std::size_t>(r) * nc + c;
      if (d[k] > 0.0f) {
        near_water[k] = 1;
        continue;
      }
      double sum = 0.0;
      int n = 0;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= nr || cc >= nc) continue;
          const std::size_t q = static_cast<std::size_t>(rr) * nc + cc;
          if (d[q] > 0.0f) {
            sum += level[q];
            ++n;
          }
        }
      if (n > 0) {
        shown[k] = static_cast<float>(sum / n);
        near_water[k] = 1;
      }
    }
  const float vs = options.vertical_scale;
  std::vector<std::uint32_t> vertex_of(d.size(), ~0u);
  auto vertex = [&](int r, int c) {
    const std::size_t k = static_cast<std::size_t>(r) * nc + c;
    if (vertex_of[k] == ~0u) {
      vertex_of[k] = static_cast<std::uint32_t>(mesh.positions.size());
      const glm::vec3 p(static_cast<float>(terrain.domain.x(cols[static_cast<std::size_t>(c)])),
                        static_cast<float>(terrain.domain.y(rows[static_cast<std::size_t>(r)])), shown[k] * vs);
      mesh.positions.push_back(p);
      mesh.normals.push_back({0.0f, 0.0f, 1.0f});
      const float t = std::clamp(d[k] / max_depth, 0.0f, 1.0f);
      // sRGB: pale turquoise in the shallows to deep blue; more opaque where deeper.
      mesh.colors.push_back({0.25f - 0.17f * t, 0.55f - 0.25f * t, 0.78f - 0.18f * t, 0.55f + 0.3f * t});
      if (mesh.positions.size() == 1) mesh.min = mesh.max = p;
      mesh.min = glm::min(mesh.min, p);
      mesh.max = glm::max(mesh.max, p);
    }
    return vertex_of[k];
  };
  for (int r = 0; r + 1 < nr; ++r)
    for (int c = 0; c + 1 < nc; ++c) {
      const std::size_t k = static_cast<std::size_t>(r) * nc + c;
      const bool wet = d[k] > 0.0f || d[k + 1] > 0.0f || d[k + nc] > 0.0f || d[k + nc + 1] > 0.0f;
      if (!wet || !(near_water[k] && near_water[k + 1] && near_water[k + nc] && near_water[k + nc + 1])) continue;
      const std::uint32_t a = vertex(r, c), b = vertex(r, c + 1), e = vertex(r + 1, c + 1), f = vertex(r + 1, c);
      mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, f});
    }
  mesh.columns = nc;
  mesh.rows = nr;
  return mesh;
}

TerrainMesh build_curve_ribbons(const Curves& curves, const Heightfield* terrain, const CurveRibbonOptions& options) {
  TerrainMesh mesh;
  float max_width = options.min_width;
  for (const auto& curve : curves.curves)
    for (float wv : curve.width) max_width = std::max(max_width, wv);
  const float vs = options.vertical_scale;
  for (const auto& curve : curves.curves) {
    const std::size_t n = curve.points.size();
    if (n < 2) continue;
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (std::size_t k = 0; k < n; ++k) {
      const glm::vec3 p = curve.points[k];
      // Direction: the mean of the adjacent segments' (mitre), in the horizontal plane.
      glm::vec2 dir(0.0f);
      if (k > 0) {
        const glm::vec2 s(p.x - curve.points[k - 1].x, p.y - curve.points[k - 1].y);
        if (glm::length(s) > 0.0f) dir += glm::normalize(s);
      }
      if (k + 1 < n) {
        const glm::vec2 s(curve.points[k + 1].x - p.x, curve.points[k + 1].y - p.y);
        if (glm::length(s) > 0.0f) dir += glm::normalize(s);
      }
      if (glm::length(dir) == 0.0f) dir = {1.0f, 0.0f};
      dir = glm::normalize(dir);
      const glm::vec2 side(-dir.y, dir.x);
      const float width = std::max(k < curve.width.size() ? curve.width[k] : 0.0f, options.min_width);
      const float t = max_width > 0.0f ? std::clamp(width / max_width, 0.0f, 1.0f) : 0.0f;
      const glm::vec4 color(0.55f - 0.45f * t, 0.85f - 0.4f * t, 1.0f - 0.1f * t, 1.0f);
      for (float sgn : {-1.0f, 1.0f}) {
        const glm::vec2 q = glm::vec2(p.x, p.y) + side * (0.5f * width * sgn);
        float z = std::isfinite(p.z) ? p.z : -std::numeric_limits<float>::max();
        if (terrain) {
          const double ground = terrain->sample_world(q.x, q.y);
          if (std::isfinite(ground)) z = std::max(z, static_cast<float>(ground));
        }
        if (z == -std::numeric_limits<float>::max()) z = 0.0f;
        const glm::vec3 v(q.x, q.y, (z + options.lift) * vs);
        mesh.positions.push_back(v);
        mesh.normals.push_back({0.0f, 0.0f, 1.0f});
        mesh.colors.push_back(color);
        if (mesh.positions.size() == 1) mesh.min = mesh.max = v;
        mesh.min = glm::min(mesh.min, v);
        mesh.max = glm::max(mesh.max, v);
      }
    }
    for (std::uint32_t k = 0; k + 1 < n; ++k) {
      const std::uint32_t a = first + 2 * k, b = a + 1, c = a + 2, d = a + 3;
      mesh.indices.insert(mesh.indices.end(), {a, c, d, a, d, b});
    }
  }
  return mesh;
}

}  // namespace orogen::editor
