#include "nodes/scatter/mesh_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/common/work_poll.h"

namespace orogen {

MeshSurface::MeshSurface(const TriMesh& mesh, const ExecContext* ctx) {
  WorkPoll poll(ctx);
  triangles_.reserve(mesh.n_faces());
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  for (auto f : mesh.faces()) {
    poll();
    Triangle t{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      if (k == 3) break;
      const auto p = mesh.point(v);
      t.x[k] = p[0], t.y[k] = p[1], t.z[k] = p[2];
      ++k;
    }
    if (k != 3) continue;
    // A vertical triangle (a skirt) covers no area in xy: it cannot hold an instance.
    const double area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
    if (!(std::abs(area) > 0.0)) continue;
    triangles_.push_back(t);
    for (int c = 0; c < 3; ++c) {
      xmin = std::min(xmin, t.x[c]), xmax = std::max(xmax, t.x[c]);
      ymin = std::min(ymin, t.y[c]), ymax = std::max(ymax, t.y[c]);
    }
  }
  if (triangles_.empty()) return;
  // About two triangles per bucket on average.
  const double area = std::max((xmax - xmin) * (ymax - ymin), 1e-12);
  cell_ = std::max(std::sqrt(2.0 * area / static_cast<double>(triangles_.size())), 1e-9);
  x0_ = xmin, y0_ = ymin;
  nx_ = std::clamp(static_cast<int>((xmax - xmin) / cell_) + 1, 1, 1 << 14);
  ny_ = std::clamp(static_cast<int>((ymax - ymin) / cell_) + 1, 1, 1 << 14);
  cell_ = std::max((xmax - xmin) / nx_, (ymax - ymin) / ny_) * (1.0 + 1e-9) + 1e-12;
  auto bucket_range = [&](const Triangle& t, int& i0, int& i1, int& j0, int& j1) {
    const auto [xa, xb] = std::minmax({t.x[0], t.x[1], t.x[2]});
    const auto [ya, yb] = std::minmax({t.y[0], t.y[1], t.y[2]});
    i0 = std::clamp(static_cast<int>((xa - x0_) / cell_), 0, nx_ - 1);
    i1 = std::clamp(static_cast<int>((xb - x0_) / cell_), 0, nx_ - 1);
    j0 = std::clamp(static_cast<int>((ya - y0_) / cell_), 0, ny_ - 1);
    j1 = std::clamp(static_cast<int>((yb - y0_) / cell_), 0, ny_ - 1);
  };
  // Counting sort of (bucket, triangle) pairs into a compact list.
  first_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  for (const auto& t : triangles_) {
    int i0, i1, j0, j1;
    bucket_range(t, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) ++first_[static_cast<std::size_t>(j) * nx_ + i + 1];
    poll();
  }
  for (std::size_t b = 1; b < first_.size(); ++b) first_[b] += first_[b - 1];
  items_.resize(first_.back());
  std::vector<std::uint32_t> fill(first_.begin(), first_.end() - 1);
  for (std::uint32_t n = 0; n < triangles_.size(); ++n) {
    int i0, i1, j0, j1;
    bucket_range(triangles_[n], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) items_[fill[static_cast<std::size_t>(j) * nx_ + i]++] = n;
    poll();
  }
}

std::optional<double> MeshSurface::height_at(double x, double y) const {
  if (triangles_.empty() || !std::isfinite(x) || !std::isfinite(y)) return std::nullopt;
  const int i = static_cast<int>(std::floor((x - x0_) / cell_));
  const int j = static_cast<int>(std::floor((y - y0_) / cell_));
  // A point on the mesh's outer edge may round just outside the last bucket.
  std::optional<double> best;
  for (int jj = std::max(j - 1, 0); jj <= std::min(j + 1, ny_ - 1); ++jj)
    for (int ii = std::max(i - 1, 0); ii <= std::min(i + 1, nx_ - 1); ++ii) {
      const std::size_t b = static_cast<std::size_t>(jj) * nx_ + ii;
      for (std::uint32_t k = first_[b]; k < first_[b + 1]; ++k) {
        const Triangle& t = triangles_[items_[k]];
        const double d = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
        const double l1 = ((x - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (y - t.y[0])) / d;
        const double l2 = ((t.x[1] - t.x[0]) * (y - t.y[0]) - (x - t.x[0]) * (t.y[1] - t.y[0])) / d;
        const double l0 = 1.0 - l1 - l2;
        constexpr double eps = -1e-9;  // points on a shared edge belong to both triangles
        if (l0 < eps || l1 < eps || l2 < eps) continue;
        const double z = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
        if (!best || z > *best) best = z;
      }
    }
  return best;
}

Points ground_on_surface(const Points& in, const MeshSurface& surface, const Heightfield* placed_on,
                         const ExecContext* ctx) {
  WorkPoll poll(ctx, WorkPoll::kUnitsPerCheck / 8);  // a lookup scans a few buckets of triangles
  Points out = in;
  for (auto& p : out.position) {
    poll();
    const auto z = surface.height_at(p.x, p.y);
    if (!z) continue;
    if (placed_on) {
      const double h = placed_on->sample_world(p.x, p.y);
      if (std::isfinite(h)) p.z = static_cast<float>(p.z + (*z - h));
    } else {
      p.z = static_cast<float>(*z);
    }
  }
  return out;
}

}  // namespace orogen
