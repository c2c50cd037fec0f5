#pragma once
// A triangulated irregular network (TIN) of a heightfield within a vertical error bound.
//
// Two stages, both on the sample grid with exact integer predicates:
//  1. Greedy insertion (Garland & Heckbert 1995, "Fast polygonal approximation of terrains and height
//     fields", CMU-CS-95-181, algorithm III): start from the two triangles of the rectangle, keep each
//     triangle's worst sample (largest vertical distance to the triangle's plane) in a priority queue, and
//     insert the worst sample of all into a Delaunay triangulation (Lawson flips) until every sample is
//     within the bound.
//  2. Decimation of that TIN by half-edge collapses (Hoppe 1996, "Progressive meshes", restricted to vertex
//     positions that are samples): a vertex is merged into the neighbour that leaves the smallest maximum
//     vertical error, as long as every sample under the changed triangles stays within the bound and no
//     triangle folds over. Greedy insertion over-refines (each insertion is chosen before the ones that make
//     it redundant), so this removes about a third of its triangles; the result is no longer Delaunay. The
//     priorities are re-evaluated lazily (when a disturbed vertex comes out of the queue).
//
// The bound is exact: after both stages every sample (i, j) lies within max_error metres, vertically, of the
// linear interpolation over the triangle that covers it (evaluated in double precision on the grid). The
// scans run in single precision with SIMD (tin_scan.h) against the bound minus their rounding margin.
// The triangles cover the rectangle of samples exactly, all counter-clockwise seen from +z, none degenerate.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "graph/heightfield.h"

namespace orogen {

struct TinOptions {
  // Largest vertical distance, in metres, between any sample and the surface; 0 or less: no bound (then
  // target_faces alone decides the size).
  double max_error = 0.0;
  // Refine until the mesh has about this many triangles (never more), even when the bound is already met;
  // with max_error 0 this alone decides the size; 0: no target.
  std::size_t target_faces = 0;
  // Stage 2 (collapses after the greedy insertion); off gives the plain greedy-insertion (Delaunay) TIN.
  bool simplify = true;
  std::function<void(double)> progress;  // optional, fraction done (approximate)
  std::function<bool()> should_stop;     // optional; true stops early (cancellation), leaving a valid TIN
};

struct Tin {
  int width = 0, height = 0;                           // the sample grid
  std::vector<std::int32_t> samples;                   // vertex k is sample samples[k] = j * width + i
  std::vector<std::array<std::int32_t, 3>> triangles;  // vertex indices, counter-clockwise seen from +z
  double max_error = 0.0;                              // the largest vertical distance of any sample, metres
};

// The TIN of a heightfield of at least 2 x 2 samples (std::invalid_argument otherwise). Deterministic.
Tin heightfield_tin(const Heightfield& height, const TinOptions& options);

}  // namespace orogen
