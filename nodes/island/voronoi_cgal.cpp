// The only file of the project that includes CGAL: clipped Voronoi diagrams as the dual of a Delaunay
// triangulation (see voronoi.h for the construction).
#include "nodes/island/voronoi.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "graph/exec_context.h"
#include "nodes/common/work_poll.h"

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

// The order in which sites are inserted: along a Hilbert curve (CGAL::hilbert_sort, middle policy, which
// draws no random numbers), so each point is located by a short walk from the previous one. Lloyd passes
// keep the order of their first diagram: the sites move by less than a cell per pass.
std::vector<int> hilbert_order(std::span<const Point> points) {
  using Entry = std::pair<Point, int>;
  std::vector<Entry> pts;
  pts.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) pts.emplace_back(points[i], static_cast<int>(i));
  using Traits = CGAL::Spatial_sort_traits_adapter_2<K, CGAL::First_of_pair_property_map<Entry>>;
  CGAL::hilbert_sort(pts.begin(), pts.end(), Traits(), CGAL::Hilbert_sort_middle_policy());
  std::vector<int> order(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) order[k] = pts[k].second;
  return order;
}

std::vector<int> insertion_order(const Lattice& L) {
  std::vector<Point> pts;
  pts.reserve(L.kx.size());
  for (std::size_t i = 0; i < L.kx.size(); ++i) pts.emplace_back(L.kx[i], L.ky[i]);
  return hilbert_order(pts);
}

// Triangulates the sites (in `order`) and the mirrors of those within `margin` lattice steps of a side,
// each point located from the previous one.
void triangulate(const Lattice& L, std::span<const int> order, double margin, Delaunay& dt, const ExecContext* ctx) {
  std::size_t count = 0;
  Delaunay::Face_handle hint;
  WorkPoll poll(ctx, 256);  // one unit: an insertion (a walk and a few flips, about a microsecond)
  const auto add = [&](double x, double y, int info) {
    poll();
    const auto v = dt.insert(Point(x, y), hint);
    v->info() = info;
    hint = v->face();
    ++count;
  };
  for (int i : order) add(L.kx[static_cast<std::size_t>(i)], L.ky[static_cast<std::size_t>(i)], i);
  // Mirrors side by side, so consecutive ones are near each other.
  for (int side = 0; side < 4; ++side)
    for (int i : order) {
      const double x = L.kx[static_cast<std::size_t>(i)], y = L.ky[static_cast<std::size_t>(i)];
      switch (side) {
        case 0:
          if (x < margin) add(-x, y, mirror_info(i, 0));
          break;
        case 1:
          if (x > L.w - margin) add(2.0 * L.w - x, y, mirror_info(i, 1));
          break;
        case 2:
          if (y < margin) add(x, -y, mirror_info(i, 2));
          break;
        default:
          if (y > L.h - margin) add(x, 2.0 * L.h - y, mirror_info(i, 3));
          break;
      }
    }
  if (dt.number_of_vertices() != count)
    throw std::runtime_error("Voronoi diagram: two sites coincide (closer than 2^-30 of the map size)");
}

// Mirror margins tried in turn, in mean site spacings (a cell left open by the mirrors of one margin is
// retried with the next; the last mirrors every site). Mirrors of sites whose cells do not reach a side
// change nothing, so the result does not depend on which margin closed every cell.
constexpr double kMargins[] = {2.0, 4.0};

Point lattice_point(const Lattice& L, int info) {
  if (info >= 0) return Point(L.kx[static_cast<std::size_t>(info)], L.ky[static_cast<std::size_t>(info)]);
  const int code = -1 - info, site = code >> 2, side = code & 3;
  const double x = L.kx[static_cast<std::size_t>(site)], y = L.ky[static_cast<std::size_t>(site)];
  switch (side) {
    case 0:
      return Point(-x, y);
    case 1:
      return Point(2.0 * L.w - x, y);
    case 2:
      return Point(x, -y);
    default:
      return Point(x, 2.0 * L.h - y);
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

// The same from a face of the triangulation (its vertices hold exactly the lattice points of their infos).
Point face_circumcentre(Delaunay::Face_handle f) {
  const Delaunay::Vertex_handle v0 = f->vertex(0), v1 = f->vertex(1), v2 = f->vertex(2);
  const Point* p[3] = {&v0->point(), &v1->point(), &v2->point()};
  int k[3] = {v0->info(), v1->info(), v2->info()};
  const auto order = [&](int i, int j) {
    if (k[i] > k[j]) {
      std::swap(k[i], k[j]);
      std::swap(p[i], p[j]);
    }
  };
  order(0, 1);
  order(1, 2);
  order(0, 1);
  return CGAL::circumcenter(*p[0], *p[1], *p[2]);
}

// Area centroids of the clipped cells straight from the triangulation (Lloyd passes need nothing else).
// Returns false if a cell is not closed by the mirrors.
bool centroids(const Lattice& L, std::span<const int> order, glm::dvec2 lo, glm::dvec2 hi, double margin,
               std::vector<glm::dvec2>& out, double* energy, double tol, const ExecContext* ctx) {
  Delaunay dt;
  triangulate(L, order, margin, dt, ctx);
  if (dt.dimension() < 2) return false;  // too few mirrors to surround the sites
  const std::size_t n = L.kx.size();
  std::vector<Point> centre;
  centre.reserve(dt.number_of_faces());
  for (auto f : dt.all_face_handles()) f->info() = -1;
  for (auto f : dt.finite_face_handles()) {
    const int a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
    if (a < 0 && b < 0 && c < 0) continue;  // mirrors only
    f->info() = static_cast<int>(centre.size());
    centre.push_back(face_circumcentre(f));
  }
  out.assign(n, glm::dvec2(0.0));
  double e = 0.0;
  std::vector<glm::dvec2> poly;
  std::vector<int> next_info;
  for (auto v : dt.finite_vertex_handles()) {
    const int i = v->info();
    if (i < 0) continue;
    const glm::dvec2 s(v->point().x(), v->point().y());
    auto fc = dt.incident_faces(v);
    const auto done = fc;
    poly.clear();
    next_info.clear();
    do {
      if (dt.is_infinite(fc)) return false;
      const Point& c = centre[static_cast<std::size_t>(fc->info())];
      if (c.x() < -tol || c.x() > L.w + tol || c.y() < -tol || c.y() > L.h + tol) return false;
      poly.emplace_back(std::clamp(c.x(), 0.0, L.w), std::clamp(c.y(), 0.0, L.h));
      next_info.push_back(fc->vertex(fc->ccw(fc->index(v)))->info());
    } while (++fc != done);
    // Sum from a canonical face (the one after the neighbour with the least index), so the rounding does not
    // depend on the triangulation's history.
    const std::size_t m = poly.size();
    const std::size_t k0 =
        static_cast<std::size_t>(std::min_element(next_info.begin(), next_info.end()) - next_info.begin());
    double area2 = 0.0, ei = 0.0;
    glm::dvec2 acc(0.0);
    for (std::size_t t = 0; t < m; ++t) {
      const std::size_t k = (k0 + t) % m;
      const glm::dvec2 a = poly[k] - s, b = poly[(k + 1) % m] - s;
      const double cr = a.x * b.y - b.x * a.y;
      area2 += cr;
      acc += cr * (a + b);
      ei += cr / 12.0 * (glm::dot(a, a) + glm::dot(a, b) + glm::dot(b, b));
    }
    e += ei;
    const glm::dvec2 centroid = area2 != 0.0 ? s + acc / (3.0 * area2) : s;
    out[static_cast<std::size_t>(i)] = glm::clamp(lo + centroid * L.scale, lo, hi);
  }
  if (energy) *energy = e * L.scale * L.scale * L.scale * L.scale;
  return true;
}

bool build(const Lattice& L, std::span<const int> order_in, glm::dvec2 lo, glm::dvec2 hi, double margin,
           PolygonMap& out, const ExecContext* ctx, double tol) {
  const int n = static_cast<int>(L.kx.size());
  Delaunay dt;
  triangulate(L, order_in, margin, dt, ctx);
  if (dt.dimension() < 2) return false;  // too few mirrors to surround the sites
  if (ctx) ctx->check_cancelled();

  std::vector<Delaunay::Vertex_handle> vertex_of(static_cast<std::size_t>(n));
  for (auto v : dt.finite_vertex_handles())
    if (v->info() >= 0) vertex_of[static_cast<std::size_t>(v->info())] = v;

  // Faces touching a site become (parts of) corners.
  for (auto f : dt.all_face_handles()) f->info() = -1;
  std::vector<Delaunay::Face_handle> faces;
  faces.reserve(dt.number_of_faces());
  for (auto f : dt.finite_face_handles())
    if (f->vertex(0)->info() >= 0 || f->vertex(1)->info() >= 0 || f->vertex(2)->info() >= 0) {
      f->info() = static_cast<int>(faces.size());
      faces.push_back(f);
    }
  if (ctx) ctx->check_cancelled();
  // Neighbouring faces on one circle (exact predicate) share their circumcentre: one corner.
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  bool merged = false;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const auto f = faces[k];
    for (int i = 0; i < 3; ++i) {
      const auto g = f->neighbor(i);
      if (dt.is_infinite(g) || g->info() < static_cast<int>(k)) continue;
      const Point& opposite = g->vertex(g->index(f))->point();
      if (dt.side_of_oriented_circle(f, opposite) == CGAL::ON_ORIENTED_BOUNDARY) {
        const int a = find_root(parent, static_cast<int>(k)), b = find_root(parent, g->info());
        parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
        merged = merged || a != b;
      }
    }
  }
  // Corners: one per circle. A corner's key is the sorted set of the (mirrored) sites on its circle; corners
  // are numbered in key order and placed at the circumcentre of the key's first three points, so the result
  // does not depend on how CGAL happened to triangulate a circle of four or more sites. Three points fix a
  // circle, so the first three of a key tell it apart from every other key: they alone order the corners.
  // (A class's root is its least face, so roots come first.)
  const std::size_t nf = faces.size();
  std::vector<int> class_of(nf, -1);
  std::vector<int> class_size;
  int classes = 0;
  for (std::size_t k = 0; k < nf; ++k) {
    const int root = merged ? find_root(parent, static_cast<int>(k)) : static_cast<int>(k);
    if (root == static_cast<int>(k)) {
      class_of[k] = classes++;
      class_size.push_back(0);
    } else {
      class_of[k] = class_of[static_cast<std::size_t>(root)];
    }
    ++class_size[static_cast<std::size_t>(class_of[k])];
  }
  struct Key {
    std::array<int, 3> info;  // the first three sites of the key
    int cls = 0;
    int begin = 0, size = 3;       // the whole key in `members` (circles of four or more sites)
    unsigned __int128 packed = 0;  // info as one number in the same order
  };
  std::vector<Key> keys(static_cast<std::size_t>(classes));
  std::vector<int> flags_of(static_cast<std::size_t>(classes), 0);  // 1 left, 2 right, 4 bottom, 8 top
  std::vector<std::pair<int, int>> members;                         // (class, info) of circles of 4+ sites
  for (std::size_t k = 0; k < nf; ++k) {
    const int c = class_of[k];
    const int a = faces[k]->vertex(0)->info(), b = faces[k]->vertex(1)->info(), d = faces[k]->vertex(2)->info();
    if (class_size[static_cast<std::size_t>(c)] > 1) {
      members.emplace_back(c, a);
      members.emplace_back(c, b);
      members.emplace_back(c, d);
      continue;
    }
    std::array<int, 3> t{a, b, d};
    if (t[0] > t[1]) std::swap(t[0], t[1]);
    if (t[1] > t[2]) std::swap(t[1], t[2]);
    if (t[0] > t[1]) std::swap(t[0], t[1]);
    keys[static_cast<std::size_t>(c)] = {t, c};
    for (int x : t)
      if (x < 0) flags_of[static_cast<std::size_t>(c)] |= 1 << mirror_side(x);
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  for (std::size_t m = 0; m < members.size();) {
    const int c = members[m].first;
    auto& key = keys[static_cast<std::size_t>(c)];
    key.cls = c;
    key.begin = static_cast<int>(m);
    int j = 0;
    for (; m < members.size() && members[m].first == c; ++m, ++j) {
      if (j < 3) key.info[static_cast<std::size_t>(j)] = members[m].second;
      if (members[m].second < 0) flags_of[static_cast<std::size_t>(c)] |= 1 << mirror_side(members[m].second);
    }
    key.size = j;
  }
  for (auto& k : keys) {
    const auto u = [&](int j) {
      return static_cast<unsigned __int128>(static_cast<std::uint32_t>(k.info[static_cast<std::size_t>(j)]) ^
                                            0x80000000u);
    };
    k.packed = (u(0) << 64) | (u(1) << 32) | u(2);
  }
  // Whole keys compared only if the first three agree (two corners on one circle, split by faces of mirrors).
  const auto key_at = [&](const Key& k, int j) {
    return j < 3 ? k.info[static_cast<std::size_t>(j)] : members[static_cast<std::size_t>(k.begin + j)].second;
  };
  std::sort(keys.begin(), keys.end(), [&](const Key& a, const Key& b) {
    if (a.packed != b.packed) return a.packed < b.packed;
    for (int j = 3; j < std::min(a.size, b.size); ++j)
      if (key_at(a, j) != key_at(b, j)) return key_at(a, j) < key_at(b, j);
    return a.size < b.size;
  });
  std::vector<int> rank(static_cast<std::size_t>(classes));
  for (std::size_t r = 0; r < keys.size(); ++r) rank[static_cast<std::size_t>(keys[r].cls)] = static_cast<int>(r);
  std::vector<int> corner_of(nf, -1);
  for (std::size_t k = 0; k < nf; ++k) corner_of[k] = rank[static_cast<std::size_t>(class_of[k])];
  out = PolygonMap{};
  out.min_corner = lo;
  out.max_corner = hi;
  out.corners.resize(static_cast<std::size_t>(classes));
  // Corners to world coordinates; corners on a side are placed exactly on it. A corner outside the
  // rectangle means a cell was not closed by the mirrors (tol: lattice steps).
  for (std::size_t r = 0; r < keys.size(); ++r) {
    const auto& key = keys[r];
    const Point centre = face_circumcentre(L, key.info[0], key.info[1], key.info[2]);
    const int fl = flags_of[static_cast<std::size_t>(key.cls)];
    const glm::dvec2 pos(centre.x(), centre.y());  // lattice units
    if (fl == 0 && (pos.x < -tol || pos.x > L.w + tol || pos.y < -tol || pos.y > L.h + tol)) return false;
    glm::dvec2 w = glm::clamp(lo + pos * L.scale, lo, hi);
    if (fl & 1) w.x = lo.x;
    if (fl & 2) w.x = hi.x;
    if (fl & 4) w.y = lo.y;
    if (fl & 8) w.y = hi.y;
    auto& q = out.corners[r];
    q.position = w;
    q.border = fl != 0;
    q.cells.reserve(3);
    q.adjacent.reserve(3);
    q.edges.reserve(3);
  }

  if (ctx) ctx->check_cancelled();
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

  // Edges, ordered by (corners, cells): a counting sort on the first corner, then each (short) run sorted.
  std::vector<PolygonMap::Edge> raw;
  raw.reserve(3 * static_cast<std::size_t>(n) + 16);
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
    raw.push_back(edge);
  }
  {
    std::vector<int> start(out.corners.size() + 1, 0);
    for (const auto& e : raw) ++start[static_cast<std::size_t>(e.corners[0]) + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    out.edges.resize(raw.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& e : raw) out.edges[static_cast<std::size_t>(fill[static_cast<std::size_t>(e.corners[0])]++)] = e;
    const auto less = [](const PolygonMap::Edge& a, const PolygonMap::Edge& b) {
      return a.corners < b.corners || (a.corners == b.corners && a.cells < b.cells);
    };
    for (std::size_t c = 0; c + 1 < start.size(); ++c)
      if (start[c + 1] - start[c] > 1) std::sort(out.edges.begin() + start[c], out.edges.begin() + start[c + 1], less);
  }
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

// A corner (circumcentre) more than this many lattice steps outside the rectangle means a cell is not closed
// by the mirrors of the margin tried. With every site mirrored every cell is closed, and a corner outside can
// only be the rounding of a circumcentre of a nearly flat triangle (sites almost in a line, as on a map
// thousands of times longer than wide): the last attempt allows that rounding, up to 2^-20 of the long side.
constexpr double kTolerance = 1.0;
double full_mirror_tolerance(const Lattice& L) { return std::max(kTolerance, std::max(L.w, L.h) * 0x1p-20); }

[[noreturn]] void open_cell_error(const Lattice& L) {
  char ratio[32];
  std::snprintf(ratio, sizeof ratio, "%.3g", std::max(L.w, L.h) / std::min(L.w, L.h));
  throw NodeError(std::string("Voronoi diagram: a cell stayed open with every site mirrored (the map is ") + ratio +
                  " times longer than wide, beyond what the diagram resolves for this many cells); change `size` "
                  "to a less elongated rectangle or lower `cells`");
}

// The diagram of the snapped sites, trying the mirror margins in turn.
void build_diagram(const Lattice& L, std::span<const int> order, glm::dvec2 lo, glm::dvec2 hi, PolygonMap& map,
                   const ExecContext* ctx) {
  const double spacing = std::sqrt(L.w * L.h / static_cast<double>(L.kx.size()));
  for (double m : kMargins)
    if (build(L, order, lo, hi, m * spacing, map, ctx, kTolerance)) return;
  if (!build(L, order, lo, hi, 2.0 * std::max(L.w, L.h) + 1.0, map, ctx, full_mirror_tolerance(L))) open_cell_error(L);
}

// One Lloyd pass: the centroids of the snapped sites' cells.
void lloyd_pass(const Lattice& L, std::span<const int> order, glm::dvec2 lo, glm::dvec2 hi,
                std::vector<glm::dvec2>& out, double* energy, const ExecContext* ctx) {
  const double spacing = std::sqrt(L.w * L.h / static_cast<double>(L.kx.size()));
  for (double m : kMargins)
    if (centroids(L, order, lo, hi, m * spacing, out, energy, kTolerance, ctx)) return;
  if (!centroids(L, order, lo, hi, 2.0 * std::max(L.w, L.h) + 1.0, out, energy, full_mirror_tolerance(L), ctx))
    open_cell_error(L);
}

std::vector<glm::dvec2> relax(std::vector<glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, int passes,
                              std::vector<double>* energy, const ExecContext* ctx, std::vector<int>& order) {
  std::vector<glm::dvec2> next;
  for (int pass = 0; pass <= passes; ++pass) {
    if (pass == passes && !energy) break;
    if (ctx) ctx->check_cancelled();
    const Lattice L = snap(sites, lo, hi);
    if (order.empty()) order = insertion_order(L);
    double e = 0.0;
    lloyd_pass(L, order, lo, hi, next, &e, ctx);
    if (energy) energy->push_back(e);
    if (pass < passes) sites.swap(next);
  }
  return sites;
}

}  // namespace

PolygonMap voronoi_diagram(std::span<const glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, const ExecContext* ctx) {
  if (sites.size() > static_cast<std::size_t>(kMaxSites)) throw std::runtime_error("Voronoi diagram: too many sites");
  const Lattice L = snap(sites, lo, hi);
  PolygonMap map;
  map.min_corner = lo;
  map.max_corner = hi;
  if (sites.empty()) return map;
  build_diagram(L, insertion_order(L), lo, hi, map, ctx);
  return map;
}

PolygonMap relaxed_voronoi_diagram(std::vector<glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, int passes,
                                   std::vector<double>* energy, const ExecContext* ctx) {
  if (energy) energy->clear();
  if (sites.size() > static_cast<std::size_t>(kMaxSites)) throw std::runtime_error("Voronoi diagram: too many sites");
  PolygonMap map;
  map.min_corner = lo;
  map.max_corner = hi;
  if (sites.empty()) return map;
  std::vector<int> order;
  sites = relax(std::move(sites), lo, hi, passes, energy, ctx, order);
  const Lattice L = snap(sites, lo, hi);
  if (order.empty()) order = insertion_order(L);
  build_diagram(L, order, lo, hi, map, ctx);
  return map;
}

void hilbert_sort(std::vector<glm::dvec2>& points) {
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const auto& p : points) pts.emplace_back(p.x, p.y);
  const std::vector<int> order = hilbert_order(pts);
  std::vector<glm::dvec2> sorted(points.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = points[static_cast<std::size_t>(order[k])];
  points.swap(sorted);
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
  for (int q : map.cells[static_cast<std::size_t>(c)].corners)
    poly.push_back(map.corners[static_cast<std::size_t>(q)].position);
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
  std::vector<int> order;
  return relax(std::move(sites), lo, hi, passes, energy, ctx, order);
}

}  // namespace orogen::island
