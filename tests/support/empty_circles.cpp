#include "support/empty_circles.h"

#include <algorithm>
#include <cmath>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace orogen::testing {

double float_tolerance(double x, double y) {
  const float m = static_cast<float>(std::max(std::abs(x), std::abs(y)));
  return 2.0 * (static_cast<double>(std::nextafter(m, INFINITY)) - m);
}

EmptyCircles empty_circles(const std::vector<glm::dvec2>& samples, double r, glm::dvec2 lo, glm::dvec2 hi,
                           const std::function<double(double, double)>& tolerance) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Delaunay = CGAL::Delaunay_triangulation_2<K>;
  using Point = K::Point_2;
  std::vector<Point> pts;
  pts.reserve(samples.size());
  for (const auto& s : samples) pts.emplace_back(s.x, s.y);
  Delaunay dt(pts.begin(), pts.end());
  EmptyCircles out;
  out.worst_interior = -r;
  out.worst_border = -r;
  auto inside = [&](double x, double y) { return x >= lo.x && x <= hi.x && y >= lo.y && y <= hi.y; };
  // Distance from (x, y) to its nearest sample.
  auto nearest = [&](double x, double y) {
    if (dt.number_of_vertices() == 0) return static_cast<double>(INFINITY);
    const Point p(x, y);
    return std::sqrt(CGAL::to_double(CGAL::squared_distance(dt.nearest_vertex(p)->point(), p)));
  };
  auto border_spot = [&](double x, double y) {
    const double d = nearest(x, y);
    out.worst_border = std::max(out.worst_border, d - r);
    if (d >= r + tolerance(x, y)) ++out.border;
  };
  if (dt.dimension() == 2)
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
      const Point c = dt.circumcenter(f);
      if (!inside(c.x(), c.y())) continue;
      const double R = std::sqrt(CGAL::to_double(CGAL::squared_distance(c, f->vertex(0)->point())));
      out.worst_interior = std::max(out.worst_interior, R - r);
      if (R >= r + tolerance(c.x(), c.y())) ++out.interior;
    }
  // The boundary: where a Voronoi edge (dual of a Delaunay edge: a segment between two circumcentres, a ray, or
  // a line) crosses one of the four sides; its two samples are the nearest there. And the corners.
  out.shortest = INFINITY;
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    const Point& a = e->first->vertex(Delaunay::cw(e->second))->point();
    const Point& b = e->first->vertex(Delaunay::ccw(e->second))->point();
    out.shortest = std::min(out.shortest, std::sqrt(CGAL::to_double(CGAL::squared_distance(a, b))));
    // The Voronoi edge as p0 + t d, t in [t0, t1].
    double p0x, p0y, dx, dy, t0 = 0.0, t1 = 1.0;
    const CGAL::Object dual = dt.dual(e);
    if (const auto* s = CGAL::object_cast<K::Segment_2>(&dual)) {
      p0x = s->source().x(), p0y = s->source().y();
      dx = s->target().x() - p0x, dy = s->target().y() - p0y;
    } else if (const auto* ray = CGAL::object_cast<K::Ray_2>(&dual)) {
      p0x = ray->source().x(), p0y = ray->source().y();
      dx = ray->direction().dx(), dy = ray->direction().dy();
      t1 = INFINITY;
    } else if (const auto* line = CGAL::object_cast<K::Line_2>(&dual)) {
      const Point q = line->point(0);
      p0x = q.x(), p0y = q.y();
      dx = line->direction().dx(), dy = line->direction().dy();
      t0 = -INFINITY, t1 = INFINITY;
    } else {
      continue;
    }
    for (int side = 0; side < 4; ++side) {
      const bool vertical = side < 2;  // the sides x = const
      const double v = side == 0 ? lo.x : side == 1 ? hi.x : side == 2 ? lo.y : hi.y;
      const double dv = vertical ? dx : dy;
      if (dv == 0.0) continue;
      const double t = (v - (vertical ? p0x : p0y)) / dv;
      if (!(t >= t0 && t <= t1)) continue;
      const double x = vertical ? v : p0x + t * dx, y = vertical ? p0y + t * dy : v;
      if (!inside(x, y)) continue;
      const double d = std::sqrt((x - a.x()) * (x - a.x()) + (y - a.y()) * (y - a.y()));
      out.worst_border = std::max(out.worst_border, d - r);
      if (d >= r + tolerance(x, y)) ++out.border;
    }
  }
  border_spot(lo.x, lo.y);
  border_spot(hi.x, lo.y);
  border_spot(lo.x, hi.y);
  border_spot(hi.x, hi.y);
  return out;
}

}  // namespace orogen::testing
