#pragma once
// The top surface of a terrain mesh as a function of (x, y): the mesh WriteScene writes beside the instances is
// a resampled, simplified version of the heightfield they were placed on (metres off it in places), so the
// instances are grounded on this surface, the one a viewer draws.
#include <cstdint>
#include <optional>
#include <vector>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/mesh.h"
#include "graph/points.h"

namespace orogen {

class MeshSurface {
 public:
  // Polls `ctx` (may be null) for cancellation per block of triangles.
  explicit MeshSurface(const TriMesh& mesh, const ExecContext* ctx = nullptr);
  // The highest z of the mesh's triangles over (x, y) (a heightfield mesh has one; a base or skirt lies below),
  // or nothing where no triangle covers the point. Barycentric interpolation in the triangle found.
  std::optional<double> height_at(double x, double y) const;

 private:
  struct Triangle {
    double x[3], y[3], z[3];
  };
  std::vector<Triangle> triangles_;
  // A uniform grid of buckets over the mesh's xy bounds, each listing the triangles whose bounds overlap it.
  double x0_ = 0, y0_ = 0, cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> first_;  // bucket b's triangles are items_[first_[b] .. first_[b + 1])
  std::vector<std::uint32_t> items_;
};

// Moves every instance vertically onto the surface: by surface - height(x, y) when the heightfield the points
// were placed on is given (so an offset above it, such as a stem sunk by 0.1 m, survives), else so its base
// lies on the surface. Instances outside the mesh keep their z. Returns the moved points. Polls `ctx` (may be
// null) per block of instances.
Points ground_on_surface(const Points& in, const MeshSurface& surface, const Heightfield* placed_on,
                         const ExecContext* ctx = nullptr);

}  // namespace orogen
