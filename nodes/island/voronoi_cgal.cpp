// The only file of the project that includes CGAL: clipped Voronoi diagrams as the dual of a Delaunay
// triangulation (see voronoi.h for the construction).
#include "nodes/island/voronoi.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "graph/exec_context.h"

namespace orogen::island {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Delaunay = CGAL::Delaunay_triangulation_2<K, Tds>;
using Point = K::Point_2;

// Sites live on an integer lattice of 2^30 steps along the rectangle's longer side: mirrors (-k, 2w - k)
// are then exact in double precision.
constexpr double kLattice = 1073741824.0;
constexpr int kMaxSites = 1 << 28;  // vertex info packs site * 4 + side into an int

// Vertex info: a site index >= 0, or -1 - (site * 4 + side) for the mirror of `site` across `side`
// (0 left, 1 right, 2 bottom, 3 top).
int mirror_info(int site, int side) { return -1 - (site * 4 + side); }
int mirror_side(int info) { return (-1 - info) & 3; }

struct Lattice {
  std::vector<double> kx, ky;  // integer-valued lattice coordinates of the sites
  double w = 0.0, h = 0.0;     // integer-valued lattice size of the rectangle
  double scale = 1.0;          // metres per lattice step
};

Lattice snap(std::span<const glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi) {
  Lattice L;
  const glm::dvec2 size = hi - lo;
  if (!(size.x > 0.0) || !(size.y > 0.0) || !std::isfinite(size.x) || !std::isfinite(size.y))
    throw std::runtime_error("Voronoi diagram: the rectangle must have a positive, finite size");
  const double side = std::max(size.x, size.y);
  L.scale = side / kLattice;
  L.w = std::max(2.0, std::round(size.x / L.scale));
  L.h = std::max(2.0, std::round(size.y / L.scale));
  L.kx.resize(sites.size());
  L.ky.resize(sites.size());
  for (std::size_t i = 0; i < sites.size(); ++i) {
    const glm::dvec2 p = sites[i];
    if (!(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y))
      throw std::runtime_error("Voronoi diagram: site " + std::to_string(i) + " lies outside the rectangle");
    // Strictly inside, so no site coincides with its own mirror.
    L.kx[i] = std::clamp(std::round((p.x - lo.x) / L.scale), 1.0, L.w - 1.0);
    L.ky[i] = std::clamp(std::round((p.y - lo.y) / L.scale), 1.0, L.h - 1.0);
  }
  return L;
}

int find_root(std::vector<int>& parent, int k) {
  while (parent[static_cast<std::size_t>(k)] != k) {
    parent[static_cast<std::size_t>(k)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(k)])];
    k = parent[static_cast<std::size_t>(k)];
  }
  return k;
}

// Builds the diagram with mirrors of the sites within `margin` lattice steps of a side. Returns false if
// some cell is not closed by them (then the caller mirrors every site).
void triangulate(const Lattice& L, double margin, Delaunay& dt) {
  const int n = static_cast<int>(L.kx.size());
  std::vector<std::pair<Point, int>> points;
  points.reserve(static_cast<std::size_t>(n) + 64);
  for (int i = 0; i < n; ++i) points.emplace_back(Point(L.kx[static_cast<std::size_t>(i)], L.ky[static_cast<std::size_t>(i)]), i);
  for (int i = 0; i < n; ++i) {
    const double x = L.kx[static_cast<std::size_t>(i)], y = L.ky[static_cast<std::size_t>(i)];
    if (x < margin) points.emplace_back(Point(-x, y), mirror_info(i, 0));
    if (x > L.w - margin) points.emplace_back(Point(2.0 * L.w - x, y), mirror_info(i, 1));
    if (y < margin) points.emplace_back(Point(x, -y), mirror_info(i, 2));
    if (y > L.h - margin) points.emplace_back(Point(x, 2.0 * L.h - y), mirror_info(i, 3));
  }
  dt.insert(points.begin(), points.end());
  if (dt.number_of_vertices() != points.size())
    throw std::runtime_error("Voronoi diagram: two sites coincide (closer than 2^-30 of the map size)");
}

Point lattice_point(const Lattice& L, int info) {
  if (info >= 0) return Point(L.kx[static_cast<std::size_t>(info)], L.ky[static_cast<std::size_t>(info)]);
  const int code = -1 - info, site = code >> 2, side = code & 3;
  const double x = L.kx[static_cast<std::size_t>(site)], y = L.ky[static_cast<std::size_t>(site)];
  switch (side) {
    case 0: return Point(-x, y);
    case 1: return Point(2.0 * L.w - x, y);
    case 2: return Point(x, -y);
    default: return Point(x, 2.0 * L.h - y);
  }
}

// The circumcentre of a face from its vertices in a canonical order (sorted infos), so it does not depend on
// how the face's vertices happen to be rotated.
Point face_circumcentre(const Lattice& L, int a, int b, int c) {
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
  return CGAL::circumcenter(lattice_point(L, a), lattice_point(L, b), lattice_point(L, c));
}

// Area centroids of the clipped cells straight from the triangulation (Lloyd passes need nothing else).
// Returns false if a cell is not closed by the mirrors.
bool centroids(const Lattice& L, glm::dvec2 lo, glm::dvec2 hi, double margin, std::vector<glm::dvec2>& out,
               double* energy) {
  Delaunay dt;
  triangulate(L, margin, dt);
  if (dt.dimension() < 2) return false;  // too few mirrors to surround the sites
  const std::size_t n = L.kx.size();
  std::vector<Point> centre;
  for (auto f : dt.all_face_handles()) f->info() = -1;
  for (auto f : dt.finite_face_handles()) {
    f->info() = static_cast<int>(centre.size());
    centre.push_back(face_circumcentre(L, f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()));
  }
  out.assign(n, glm::dvec2(0.0));
  double e = 0.0;
  const double tol = 1.0;
  std::vector<glm::dvec2> poly;
  for (auto v : dt.finite_vertex_handles()) {
    const int i = v->info();
    if (i < 0) continue;
    const glm::dvec2 s(v->point().x(), v->point().y());
    double area2 = 0.0;
    glm::dvec2 acc(0.0);
    auto fc = dt.incident_faces(v);
    const auto done = fc;
    poly.clear();
    do {
      if (dt.is_infinite(fc)) return false;
      const Point& c = centre[static_cast<std::size_t>(fc->info())];
      if (c.x() < -tol || c.x() > L.w + tol || c.y() < -tol || c.y() > L.h + tol) return false;
      poly.emplace_back(std::clamp(c.x(), 0.0, L.w), std::clamp(c.y(), 0.0, L.h));
    } while (++fc != done);
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const glm::dvec2 a = poly[k] - s, b = poly[(k + 1) % poly.size()] - s;
      const double cr = a.x * b.y - b.x * a.y;
      area2 += cr;
      acc += cr * (a + b);
      e += cr / 12.0 * (glm::dot(a, a) + glm::dot(a, b) + glm::dot(b, b));
    }
    const glm::dvec2 centroid = area2 != 0.0 ? s + acc / (3.0 * area2) : s;
    out[static_cast<std::size_t>(i)] = glm::clamp(lo + centroid * L.scale, lo, hi);
  }
  if (energy) *energy = e * L.scale * L.scale * L.scale * L.scale;
  return true;
}

bool build(const Lattice& L, glm::dvec2 lo, glm::dvec2 hi, double margin, PolygonMap& out, const ExecContext* ctx) {
  const int n = static_cast<int>(L.kx.size());
  Delaunay dt;
  triangulate(L, margin, dt);
  if (dt.dimension() < 2) return false;  // too few mirrors to surround the sites
  if (ctx) ctx->check_cancelled();

  std::vector<Delaunay::Vertex_handle> vertex_of(static_cast<std::size_t>(n));
  for (auto v : dt.finite_vertex_handles())
    if (v->info() >= 0) vertex_of[static_cast<std::size_t>(v->info())] = v;

  // Faces touching a site become (parts of) corners.
  for (auto f : dt.all_face_handles()) f->info() = -1;
  std::vector<Delaunay::Face_handle> faces;
  for (auto f : dt.finite_face_handles())
    if (f->vertex(0)->info() >= 0 || f->vertex(1)->info() >= 0 || f->vertex(2)->info() >= 0) {
      f->info() = static_cast<int>(faces.size());
      faces.push_back(f);
    }
  // Neighbouring faces on one circle (exact predicate) share their circumcentre: one corner.
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const auto f = faces[k];
    for (int i = 0; i < 3; ++i) {
      const auto g = f->neighbor(i);
      if (dt.is_infinite(g) || g->info() < static_cast<int>(k)) continue;
      const Point& opposite = g->vertex(g->index(f))->point();
      if (dt.side_of_oriented_circle(f, opposite) == CGAL::ON_ORIENTED_BOUNDARY) {
        const int a = find_root(parent, static_cast<int>(k)), b = find_root(parent, g->info());
        parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
      }
    }
  }
  // Corners: one per circle. A corner's key is the sorted set of the (mirrored) sites on its circle; corners
  // are numbered in key order and placed at the circumcentre of the key's first three points, so the result
  // does not depend on how CGAL happened to triangulate a circle of four or more sites (its point location
  // draws from a global random generator).
  std::vector<int> class_of(faces.size(), -1);
  // Keys as one sorted list of (class, info) pairs: class c owns the range [key_start[c], key_start[c + 1]).
  std::vector<std::pair<int, int>> members;
  members.reserve(3 * faces.size());
  int classes = 0;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int root = find_root(parent, static_cast<int>(k));
    if (class_of[static_cast<std::size_t>(root)] < 0) class_of[static_cast<std::size_t>(root)] = classes++;
    const int c = class_of[static_cast<std::size_t>(root)];
    class_of[k] = c;
    for (int i = 0; i < 3; ++i) members.emplace_back(c, faces[k]->vertex(i)->info());
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  std::vector<int> key_start(static_cast<std::size_t>(classes) + 1, 0);
  for (const auto& m : members) ++key_start[static_cast<std::size_t>(m.first) + 1];
  for (std::size_t c = 1; c < key_start.size(); ++c) key_start[c] += key_start[c - 1];
  const auto key_info = [&](int c, int k) { return members[static_cast<std::size_t>(key_start[static_cast<std::size_t>(c)] + k)].second; };
  const auto key_size = [&](int c) { return key_start[static_cast<std::size_t>(c) + 1] - key_start[static_cast<std::size_t>(c)]; };
  std::vector<int> order(static_cast<std::size_t>(classes));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const int na = key_size(a), nb = key_size(b);
    for (int k = 0; k < std::min(na, nb); ++k)
      if (key_info(a, k) != key_info(b, k)) return key_info(a, k) < key_info(b, k);
    return na < nb;
  });
  std::vector<int> rank(static_cast<std::size_t>(classes));
  for (std::size_t r = 0; r < order.size(); ++r) rank[static_cast<std::size_t>(order[r])] = static_cast<int>(r);
  std::vector<int> corner_of(faces.size(), -1);
  for (std::size_t k = 0; k < faces.size(); ++k) corner_of[k] = rank[static_cast<std::size_t>(class_of[k])];
  out = PolygonMap{};
  out.min_corner = lo;
  out.max_corner = hi;
  out.corners.resize(static_cast<std::size_t>(classes));
  std::vector<int> flags(static_cast<std::size_t>(classes), 0);  // per corner: 1 left, 2 right, 4 bottom, 8 top
  for (std::size_t r = 0; r < order.size(); ++r) {
    const int c = order[r];
    const Point centre = face_circumcentre(L, key_info(c, 0), key_info(c, 1), key_info(c, 2));
    auto& q = out.corners[r];
    q.position = {centre.x(), centre.y()};  // lattice units for now
    q.cells.reserve(3);
    q.adjacent.reserve(3);
    q.edges.reserve(3);
    for (int k = 0; k < key_size(c); ++k)
      if (key_info(c, k) < 0) flags[r] |= 1 << mirror_side(key_info(c, k));
  }
  // Corners to world coordinates; corners on a side are placed exactly on it. A corner outside the
  // rectangle means a cell was not closed by the mirrors.
  const double tol = 1.0;  // lattice steps
  for (std::size_t c = 0; c < out.corners.size(); ++c) {
    auto& q = out.corners[c];
    const int fl = flags[c];
    if (fl == 0 && (q.position.x < -tol || q.position.x > L.w + tol || q.position.y < -tol || q.position.y > L.h + tol))
      return false;
    glm::dvec2 w = lo + q.position * L.scale;
    w = glm::clamp(w, lo, hi);
    if (fl & 1) w.x = lo.x;
    if (fl & 2) w.x = hi.x;
    if (fl & 4) w.y = lo.y;
    if (fl & 8) w.y = hi.y;
    q.position = w;
    q.border = fl != 0;
  }

  out.cells.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    auto& cell = out.cells[static_cast<std::size_t>(i)];
    cell.corners.reserve(8);
    cell.edges.reserve(8);
    cell.neighbours.reserve(8);
    cell.centre = lo + glm::dvec2(L.kx[static_cast<std::size_t>(i)], L.ky[static_cast<std::size_t>(i)]) * L.scale;
    auto fc = dt.incident_faces(vertex_of[static_cast<std::size_t>(i)]);
    const auto done = fc;
    do {
      if (dt.is_infinite(fc)) return false;
      const int c = corner_of[static_cast<std::size_t>(fc->info())];
      if (cell.corners.empty() || cell.corners.back() != c) cell.corners.push_back(c);
    } while (++fc != done);
    if (cell.corners.size() > 1 && cell.corners.front() == cell.corners.back()) cell.corners.pop_back();
    std::rotate(cell.corners.begin(), std::min_element(cell.corners.begin(), cell.corners.end()), cell.corners.end());
    for (int c : cell.corners) {
      auto& q = out.corners[static_cast<std::size_t>(c)];
      q.cells.push_back(i);
      cell.border = cell.border || q.border;
    }
  }

  for (auto e : dt.finite_edges()) {
    const auto f = e.first;
    const int i = e.second;
    const int ia = f->vertex(f->cw(i))->info(), ib = f->vertex(f->ccw(i))->info();
    if (ia < 0 && ib < 0) continue;
    const auto g = f->neighbor(i);
    if (dt.is_infinite(g)) return false;
    const int cf = corner_of[static_cast<std::size_t>(f->info())], cg = corner_of[static_cast<std::size_t>(g->info())];
    if (cf == cg) continue;  // four sites on one circle: no edge
    PolygonMap::Edge edge;
    edge.cells = {std::max(ia, ib), std::min(ia, ib) >= 0 ? std::min(ia, ib) : -1};
    edge.corners = {std::min(cf, cg), std::max(cf, cg)};
    out.edges.push_back(edge);
  }
  std::sort(out.edges.begin(), out.edges.end(), [](const PolygonMap::Edge& a, const PolygonMap::Edge& b) {
    return a.corners < b.corners || (a.corners == b.corners && a.cells < b.cells);
  });
  for (std::size_t k = 0; k < out.edges.size(); ++k) {
    const auto& edge = out.edges[k];
    for (int c : edge.cells)
      if (c >= 0) out.cells[static_cast<std::size_t>(c)].edges.push_back(static_cast<int>(k));
    if (edge.cells[1] >= 0) {
      out.cells[static_cast<std::size_t>(edge.cells[0])].neighbours.push_back(edge.cells[1]);
      out.cells[static_cast<std::size_t>(edge.cells[1])].neighbours.push_back(edge.cells[0]);
    }
    auto& qa = out.corners[static_cast<std::size_t>(edge.corners[0])];
    auto& qb = out.corners[static_cast<std::size_t>(edge.corners[1])];
    qa.edges.push_back(static_cast<int>(k));
    qb.edges.push_back(static_cast<int>(k));
    qa.adjacent.push_back(edge.corners[1]);
    qb.adjacent.push_back(edge.corners[0]);
  }
  for (auto& cell : out.cells) std::sort(cell.neighbours.begin(), cell.neighbours.end());
  for (auto& q : out.corners) {
    std::sort(q.adjacent.begin(), q.adjacent.end());
    std::sort(q.cells.begin(), q.cells.end());
  }
  return true;
}

}  // namespace

PolygonMap voronoi_diagram(std::span<const glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, const ExecContext* ctx) {
  if (sites.size() > static_cast<std::size_t>(kMaxSites)) throw std::runtime_error("Voronoi diagram: too many sites");
  const Lattice L = snap(sites, lo, hi);
  PolygonMap map;
  map.min_corner = lo;
  map.max_corner = hi;
  if (sites.empty()) return map;
  // Mirror the sites within a few mean spacings of a side; if that leaves a cell open, mirror all.
  const double spacing = std::sqrt(L.w * L.h / static_cast<double>(sites.size()));
  if (!build(L, lo, hi, 4.0 * spacing, map, ctx)) {
    if (!build(L, lo, hi, 2.0 * std::max(L.w, L.h) + 1.0, map, ctx))
      throw std::logic_error("Voronoi diagram: a cell stayed open with every site mirrored");
  }
  return map;
}

double polygon_area(std::span<const glm::dvec2> poly) {
  double a = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const glm::dvec2 p = poly[k], q = poly[(k + 1) % poly.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return 0.5 * a;
}

glm::dvec2 polygon_centroid(std::span<const glm::dvec2> poly) {
  if (poly.empty()) return {0.0, 0.0};
  // Relative to the first vertex, for precision far from the origin.
  const glm::dvec2 o = poly[0];
  double a = 0.0;
  glm::dvec2 c{0.0, 0.0};
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    const glm::dvec2 p = poly[k] - o, q = poly[k + 1] - o;
    const double cross = p.x * q.y - q.x * p.y;
    a += cross;
    c += cross * (p + q);
  }
  if (a == 0.0) return o;
  return o + c / (3.0 * a);
}

std::vector<glm::dvec2> cell_polygon(const PolygonMap& map, int c) {
  std::vector<glm::dvec2> poly;
  for (int q : map.cells[static_cast<std::size_t>(c)].corners) poly.push_back(map.corners[static_cast<std::size_t>(q)].position);
  return poly;
}

double centroidal_energy(const PolygonMap& map) {
  double e = 0.0;
  for (const auto& cell : map.cells) {
    const std::size_t n = cell.corners.size();
    for (std::size_t k = 0; k < n; ++k) {
      const glm::dvec2 a = map.corners[static_cast<std::size_t>(cell.corners[k])].position - cell.centre;
      const glm::dvec2 b = map.corners[static_cast<std::size_t>(cell.corners[(k + 1) % n])].position - cell.centre;
      const double area = 0.5 * (a.x * b.y - b.x * a.y);
      e += area / 6.0 * (glm::dot(a, a) + glm::dot(a, b) + glm::dot(b, b));
    }
  }
  return e;
}

std::vector<glm::dvec2> lloyd_relax(std::vector<glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, int passes,
                                    std::vector<double>* energy, const ExecContext* ctx) {
  if (energy) energy->clear();
  if (sites.empty()) return sites;
  if (sites.size() > static_cast<std::size_t>(kMaxSites)) throw std::runtime_error("Voronoi diagram: too many sites");
  std::vector<glm::dvec2> next;
  for (int pass = 0; pass <= passes; ++pass) {
    if (pass == passes && !energy) break;
    if (ctx) ctx->check_cancelled();
    const Lattice L = snap(sites, lo, hi);
    const double spacing = std::sqrt(L.w * L.h / static_cast<double>(sites.size()));
    double e = 0.0;
    if (!centroids(L, lo, hi, 4.0 * spacing, next, &e) && !centroids(L, lo, hi, 2.0 * std::max(L.w, L.h) + 1.0, next, &e))
      throw std::logic_error("Voronoi diagram: a cell stayed open with every site mirrored");
    if (energy) energy->push_back(e);
    if (pass < passes) sites.swap(next);
  }
  return sites;
}

}  // namespace orogen::island
