#pragma once
// Convex-hull rocks (S. Ekman et al. 2016, SeamScape §3.8): points sampled uniformly on an ellipsoid, perturbed
// by spherical Gaussian noise, their 3D convex hull (incremental insertion for small sets; CGAL's
// convex_hull_3, the quickhull of Barber, Dobkin & Huhdanpaa 1996, above 512 points or as a fallback) with
// outward faces; optionally subdivided and displaced along the normals by 3D value noise in world
// units for a less faceted look (still closed).
#include <array>
#include <cstdint>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "graph/exec_context.h"
#include "graph/mesh.h"

namespace orogen::rocks {

struct HullRockOptions {
  int points = 20;                  // N, 4..10000
  glm::dvec3 radii{1.0, 0.7, 0.5};  // ellipsoid semi-axes a, b, c (m)
  double sigma = 0.05;              // Gaussian noise per coordinate (m)
  std::uint64_t seed = 0;
  std::uint64_t variant = 0;  // a second key (rock index in a set)
  int subdivisions = 0;       // refinement: each level splits every triangle in four
  double displacement = 0.0;  // amplitude of the noise displacement along the normal (m)
  double wavelength = 0.5;    // of the displacement noise (m)
};

// A closed triangle mesh as indexed faces, counter-clockwise seen from outside.
struct Hull {
  std::vector<glm::dvec3> vertices;
  std::vector<std::array<int, 3>> faces;
};

// A uniform number in [0, 1) keyed by (seed, variant, index), for per-variant choices.
double variant_uniform(std::uint64_t seed, std::uint64_t variant, int index);
// The N sampled points (deterministic in seed and variant).
std::vector<glm::dvec3> rock_points(const HullRockOptions& options);
// The convex hull of `points` with CGAL (convex_hull_3); vertices are a subset of the inputs. Throws
// std::invalid_argument when the points span less than three dimensions.
Hull convex_hull_cgal(const std::vector<glm::dvec3>& points);
// The convex hull by incremental insertion with a floating-point tolerance of 1e-11 of the set's extent
// (points within it of a face count as inside); a result that fails the closed-surface check is recomputed
// with CGAL. Vertices are a subset of the inputs; throws like convex_hull_cgal.
Hull convex_hull_small(const std::vector<glm::dvec3>& points);
// convex_hull_small up to 512 points, CGAL above.
Hull convex_hull(const std::vector<glm::dvec3>& points);
// The rock of `options` (hull, then refinement). With `ctx`, the refinement polls for cancellation (4 levels of
// 10000 points make a million triangles).
Hull hull_rock(const HullRockOptions& options, const ExecContext* ctx = nullptr);
// Appends the rock transformed by `rotation` then moved to `offset`, with a color and per-vertex normals.
void append_hull_rock(TriMesh& mesh, const HullRockOptions& options, const glm::dvec3& offset,
                      const glm::dquat& rotation, const TriMesh::Color& color, const ExecContext* ctx = nullptr);
void append_hull(TriMesh& mesh, const Hull& hull, const glm::dvec3& offset, const glm::dquat& rotation,
                 const TriMesh::Color& color, const ExecContext* ctx = nullptr);

}  // namespace orogen::rocks
