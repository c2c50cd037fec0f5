#pragma once
// Tile-invariant, maximal Poisson-disk sampling with variable radius and several classes.
//
// Algorithm: Bridson (2007), "Fast Poisson disk sampling in arbitrary dimensions" (k candidates in the
// annulus [r, 2r] around an active point, a background grid of cell r/sqrt 2), run chunk by chunk in the
// phase order of Wei (2008), "Parallel Poisson disk sampling", followed by the gap filling of Ebeida et al.
// (2011), "Efficient maximal Poisson-disk sampling" (darts into the still-uncovered cells of a quadtree), so
// no point can be added when it finishes.
//
// Tile invariance: classes are placed one after the other, largest radius first. Each class cuts the world
// plane into square chunks anchored at world (0, 0), of side C_k = max(2 r_max, 8 r) (at least twice its own
// exclusion distance), processed in four phases by the parity of their chunk indices: chunks of one phase are
// at least C_k apart and never interact, so they run in parallel, and a chunk's points depend only on the
// seed, its indices, the points of its neighbours placed in earlier phases and the (final) points of the
// earlier classes. A class's points are final three chunks inside what was computed, and each class is
// computed far enough beyond the request for the later classes' reads, so the points inside any rectangle are
// the same whichever rectangle asks, at any raster resolution and for any thread count. (Fields that modulate
// the density must cover the halo for this to hold exactly near the edges; outside its domain a field is
// extended by its edge values.)
//
// Precision: candidates are computed in double, rounded to the float positions Points store, and tested in
// double against the stored (float) positions of their neighbours, so the minimum distance holds exactly for
// the positions that are output, at any coordinate magnitude the request accepts.
//
// Maximality (one class of constant radius r, the fast path): every spot of the sampled region (the plane,
// or the bounded rectangle with its edges) is closer than r + 2 u to a point, u the float step at the spot's
// coordinates (a spot free by less may hold no free float position). The gap filling ends each grid cell it
// cannot prove covered with the cell's farthest spot from the points (a circumcentre of three, a crossing of
// a bisector and an edge, or a corner, found exactly in double) and places a point there when it is free.
// Checked on the output's Delaunay triangulation (tests/support/empty_circles.h). The general sampler
// (variable radius, several classes: a spot is free for class k when every point is at least the conflict
// distance for the local radius there away) fills gaps by darts on a quadtree and is maximal only up to gaps
// narrower than its finest cells: a cell that two exclusion disks do not cover refines down to a 1024th of
// the class's grid cell, where a dart at its centre ends the search; along the borders of a density's support
// (masks) cells stop at a 32nd when their corners and centre are blocked. Measured with one class of constant
// radius routed through it (a density field of 1; r = 5 m, 2 km square, bounded): 21 interior spots free by
// up to 1.3 mm among 112,270 points (before the finer quadtree: 837 by up to 4.1 cm), none on the edges.

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/heightfield.h"
#include "graph/points.h"

namespace orogen {

class ExecContext;

struct PoissonClass {
  double radius = 5.0;                   // m: minimum distance between two points of this class at density 1
  std::int32_t class_id = 0;             // written to Points::class_id
  const Heightfield* density = nullptr;  // optional per-class density in [0, 1], multiplies the common one
};

struct PoissonParams {
  std::vector<PoissonClass> classes;  // placed largest radius first (ties: in the given order)
  // Pairs of different classes keep cross_separation * (r_i + r_j) / 2 apart (1: the disks of radius r/2
  // around points never overlap; 0: classes ignore each other).
  double cross_separation = 1.0;
  // Density d in [0, 1] (common field times per-class field, mask): the local radius is r / sqrt(d), so the
  // number of points per area is proportional to d; where d < min_density there are no points.
  double min_density = 0.1;
  const Heightfield* density = nullptr;  // optional common density, [0, 1]
  const Heightfield* mask = nullptr;     // optional: points only where mask >= 0.5
  // Bridson's k. With fill_gaps the result is maximal whatever k: Bridson is a fast first pass and k = 30
  // spends most of its time retiring active points; 8 gives the same density at about half the cost.
  int attempts = 8;
  bool fill_gaps = true;  // Ebeida's gap filling (maximal sampling)
  // The region sampled. Unbounded (the default): the whole plane, of which each request gets the points inside
  // it (tile invariant, but a spot within r of a request's edge may be free: the point that covers it lies
  // beyond the edge). Bounded: points only inside the closed rectangle [bounds_lo, bounds_hi], which is filled
  // up to its edges; requests inside it get its points (tile invariant among requests with the same bounds).
  bool bounded = false;
  glm::dvec2 bounds_lo{0.0}, bounds_hi{0.0};
  std::uint64_t seed = 0;
  std::size_t max_points = 50'000'000;  // refuse requests that would place more
};

// Interaction distance, chunk side and halo (metres) of a parameter set.
struct PoissonLayout {
  double interaction = 0.0;  // largest distance at which two points can conflict
  double chunk = 0.0;        // largest chunk side
  double halo = 0.0;         // metres around a request within which points are computed
};
PoissonLayout poisson_layout(const PoissonParams& p);

// The points inside [lo, hi] (both inclusive), in a fixed order (chunk rows, then chunks, then classes,
// then placement order). Attributes: "radius" (the local minimum distance, m). Rotation is a yaw about z
// hashed from the seed and the position; scale 1; z 0. Throws std::invalid_argument for bad parameters and
// std::runtime_error when the request is too large or its coordinates too big for float positions.
Points poisson_disk(glm::dvec2 lo, glm::dvec2 hi, const PoissonParams& p, const ExecContext* ctx = nullptr);

// The minimum distance the sampler keeps between a point of class index a with local radius ra and one of
// class index b with radius rb (for tests and callers that add points later).
double poisson_conflict_distance(const PoissonParams& p, int a, double ra, int b, double rb);

// The local radius of class index k at (x, y), or 0 where no point of that class may be placed.
double poisson_local_radius(const PoissonParams& p, int k, double x, double y);

}  // namespace orogen
