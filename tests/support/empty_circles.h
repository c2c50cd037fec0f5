#pragma once
// An exact check of maximal Poisson-disk sampling with one radius r: the largest circles centred in a closed
// rectangle that hold no sample, from the Delaunay triangulation of the samples (CGAL, exact predicates).
// The function "distance to the nearest sample" over the rectangle peaks at a Voronoi vertex inside it (a
// Delaunay circumcentre), where a Voronoi edge crosses its boundary, or at a corner: the sampling is maximal
// in the rectangle iff each of those is closer than r to a sample.
#include <cstddef>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::testing {

struct EmptyCircles {
  std::size_t interior = 0;     // Delaunay circumcentres inside the rectangle with circumradius >= r + tolerance
  std::size_t border = 0;       // boundary points (Voronoi edge crossings, corners) that far from every sample
  double worst_interior = 0.0;  // largest circumradius (centre inside) minus r, metres (negative: all below)
  double worst_border = 0.0;    // largest empty circle centred on the boundary minus r, metres (at least -r)
  double shortest = 0.0;        // the shortest Delaunay edge: the distance between the closest two samples
};

// `tolerance(x, y)`: the excess over r still accepted at a spot (0: none).
EmptyCircles empty_circles(const std::vector<glm::dvec2>& samples, double r, glm::dvec2 lo, glm::dvec2 hi,
                           const std::function<double(double, double)>& tolerance);

// Two float steps at the spot's magnitude: what a sampler storing float positions cannot resolve (a spot free
// by less may hold no float position that is free).
double float_tolerance(double x, double y);

}  // namespace orogen::testing
