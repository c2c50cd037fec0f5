// HeightfieldToMesh and WriteMesh: grid triangulation counts, normals, colours, the error-bounded TIN,
// and OBJ/PLY/STL round trips through OpenMesh.
// OpenMesh's IO header first: it registers the readers before the mesh kernel is instantiated.
#include <OpenMesh/Core/IO/MeshIO.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <vector>

#include <tuple>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "nodes/geometry/heightfield_mesh.h"
#include "nodes/geometry/mesh_base.h"
#include "nodes/geometry/terrain_tin.h"
#include "nodes/geometry/tin_scan.h"
#include "nodes/io/image_file.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

HeightfieldPtr field(const Domain& d, double (*f)(double, double)) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(f(d.x(i), d.y(j)));
  return h;
}

double plane(double x, double y) { return 0.3 * x - 0.2 * y + 5.0; }
double hills(double x, double y) { return 20.0 * std::sin(x / 30.0) * std::cos(y / 40.0) + 0.002 * x * y; }

// The vertical distance from (x, y, z) to the mesh surface above or below it, or NaN if no face covers
// (x, y), by an independent barycentric test over the faces whose bounding box holds the point (bucketed in a
// uniform grid so the check stays fast).
class VerticalDistance {
 public:
  VerticalDistance(const TriMesh& m, const Domain& d) : m_(m), d_(d), cells_(kCells * kCells) {
    for (auto f : m.faces()) {
      auto [lo, hi] = bbox(f);
      for (int cy = cell(lo[1], 1); cy <= cell(hi[1], 1); ++cy)
        for (int cx = cell(lo[0], 0); cx <= cell(hi[0], 0); ++cx)
          cells_[static_cast<std::size_t>(cy * kCells + cx)].push_back(f);
    }
  }
  double operator()(double x, double y, double z) const {
    double best = std::numeric_limits<double>::quiet_NaN();
    for (auto f : cells_[static_cast<std::size_t>(cell(y, 1) * kCells + cell(x, 0))]) {
      auto fv = m_.cfv_iter(f);
      const auto a = m_.point(*fv), b = m_.point(*++fv), c = m_.point(*++fv);
      const double det = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * (double(b[1]) - a[1]);
      if (det == 0.0) continue;
      const double l1 = ((x - a[0]) * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * (y - a[1])) / det;
      const double l2 = ((double(b[0]) - a[0]) * (y - a[1]) - (x - a[0]) * (double(b[1]) - a[1])) / det;
      const double l0 = 1 - l1 - l2;
      if (l0 < -1e-7 || l1 < -1e-7 || l2 < -1e-7) continue;
      const double dist = std::abs(z - (l0 * a[2] + l1 * b[2] + l2 * c[2]));
      if (std::isnan(best) || dist < best) best = dist;
    }
    return best;
  }

 private:
  static constexpr int kCells = 32;
  std::pair<OpenMesh::Vec3f, OpenMesh::Vec3f> bbox(TriMesh::FaceHandle f) const {
    auto fv = m_.cfv_iter(f);
    const auto a = m_.point(*fv), b = m_.point(*++fv), c = m_.point(*++fv);
    return {OpenMesh::Vec3f(std::min({a[0], b[0], c[0]}), std::min({a[1], b[1], c[1]}), 0),
            OpenMesh::Vec3f(std::max({a[0], b[0], c[0]}), std::max({a[1], b[1], c[1]}), 0)};
  }
  int cell(double v, int axis) const {
    const double t = (v - d_.min_corner()[axis]) / d_.size()[axis];
    return std::clamp(static_cast<int>(t * kCells), 0, kCells - 1);
  }
  const TriMesh& m_;
  Domain d_;
  std::vector<std::vector<TriMesh::FaceHandle>> cells_;
};

// Largest vertical distance of the original samples to the mesh (infinity if some sample is not covered).
double max_vertical_error(const TriMesh& m, const Heightfield& h) {
  const VerticalDistance distance(m, h.domain);
  double worst = 0.0;
  for (int j = 0; j < h.height(); ++j)
    for (int i = 0; i < h.width(); ++i) {
      const double d = distance(h.domain.x(i), h.domain.y(j), h.at(i, j));
      if (std::isnan(d)) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, d);
    }
  return worst;
}

bool all_faces_face_up(const TriMesh& m) {
  for (auto f : m.faces())
    if (!(m.calc_face_normal(f)[2] > 0.0f)) return false;
  return true;
}

TEST(HeightfieldMesh, GridCountsPositionsAndWinding) {
  const Domain d = Domain::from_extent({100, -40}, {60, 40}, {7, 5});
  const auto h = field(d, hills);
  const Mesh mesh = heightfield_grid_mesh(*h);
  EXPECT_EQ(mesh.vertex_count(), 35u);
  EXPECT_EQ(mesh.face_count(), 2u * 6u * 4u);
  const TriMesh& m = mesh.mesh;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 7; ++i) {
      const auto p = m.point(TriMesh::VertexHandle(j * 7 + i));
      EXPECT_FLOAT_EQ(p[0], static_cast<float>(d.x(i)));
      EXPECT_FLOAT_EQ(p[1], static_cast<float>(d.y(j)));
      EXPECT_EQ(p[2], h->at(i, j));
    }
  EXPECT_TRUE(all_faces_face_up(m));
  for (auto v : m.vertices()) EXPECT_GT(m.normal(v)[2], 0.0f);
  // A closed-boundary check: a grid is one disc, so V - E + F = 1.
  EXPECT_EQ(static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) + static_cast<long>(m.n_faces()), 1);
}

TEST(HeightfieldMesh, NormalsMatchTheAnalyticNormalOfATiltedPlane) {
  const Domain d = Domain::from_extent({0, 0}, {90, 50}, {10, 6});
  const Mesh mesh = heightfield_grid_mesh(*field(d, plane));
  const double len = std::sqrt(0.3 * 0.3 + 0.2 * 0.2 + 1.0);
  const OpenMesh::Vec3f expected(static_cast<float>(-0.3 / len), static_cast<float>(0.2 / len),
                                 static_cast<float>(1.0 / len));
  for (auto v : mesh.mesh.vertices())
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.mesh.normal(v)[k], expected[k], 1e-5);
  for (auto f : mesh.mesh.faces())
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.mesh.normal(f)[k], expected[k], 1e-5);
}

TEST(HeightfieldMesh, CellsSplitAlongTheShorterDiagonal) {
  const Domain d = Domain::from_extent({0, 0}, {1, 1}, {2, 2});
  auto h = std::make_shared<Heightfield>(d);
  h->at(0, 0) = 0;  // a
  h->at(1, 0) = 5;  // b
  h->at(1, 1) = 0;  // c: a-c is short (flat), b-d long
  h->at(0, 1) = 9;  // d
  Mesh mesh = heightfield_grid_mesh(*h);
  using VH = TriMesh::VertexHandle;
  EXPECT_TRUE(mesh.mesh.find_halfedge(VH(0), VH(3)).is_valid());
  EXPECT_FALSE(mesh.mesh.find_halfedge(VH(1), VH(2)).is_valid());
  h->at(1, 1) = 20;  // now b-d is the shorter one
  mesh = heightfield_grid_mesh(*h);
  EXPECT_TRUE(mesh.mesh.find_halfedge(VH(1), VH(2)).is_valid());
  EXPECT_TRUE(all_faces_face_up(mesh.mesh));
}

TEST(HeightfieldMesh, VertexColoursFromImage) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  const auto h = field(d, plane);
  // A coarser RGB image: R ramps in x, G in y, B constant; bilinear sampling reproduces the ramps.
  const Domain di = Domain::from_extent({0, 0}, {100, 100}, {5, 3});
  auto img = std::make_shared<Image>(di, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) {
      img->pixel(i, j)[0] = static_cast<float>(di.x(i) / 100);
      img->pixel(i, j)[1] = static_cast<float>(di.y(j) / 100);
      img->pixel(i, j)[2] = 0.25f;
    }
  const auto run = run_node("HeightfieldToMesh", d, {}, {{"in", h}, {"colors", ImagePtr(img)}});
  const auto mesh = run.get<Mesh>();
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) {
      const auto c = mesh->mesh.color(TriMesh::VertexHandle(j * 11 + i));
      EXPECT_NEAR(c[0], d.x(i) / 100, 1e-6);
      EXPECT_NEAR(c[1], d.y(j) / 100, 1e-6);
      EXPECT_NEAR(c[2], 0.25, 1e-6);
      EXPECT_EQ(c[3], 1.0f);
    }
  const auto plain = run_node("HeightfieldToMesh", d, {}, {{"in", h}}).get<Mesh>();
  for (auto v : plain->mesh.vertices()) EXPECT_EQ(plain->mesh.color(v), OpenMesh::Vec4f(1, 1, 1, 1));
}

TEST(HeightfieldMesh, TooSmallIsAnError) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {1, 5});
  EXPECT_THROW(run_node("HeightfieldToMesh", d, {}, {{"in", field(d, plane)}}), NodeError);
}

// A rough terrain: hills plus a hashed value noise with sharp cell edges, cliffs and a flat plateau, so the
// TIN meets ridges, steps and ties.
HeightfieldPtr rough(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const double x = d.x(i), y = d.y(j);
      std::uint32_t k = static_cast<std::uint32_t>((i / 5) * 73856093u ^ (j / 7) * 19349663u);
      k = (k ^ (k >> 13)) * 0x5bd1e995u;
      const double cell = static_cast<double>(k >> 8) / double(1u << 24);
      double z = hills(x, y) + 3.0 * cell + (x > 40.0 ? 6.0 : 0.0);
      if (x < -60.0 && y < -60.0) z = 12.0;  // plateau
      h->at(i, j) = static_cast<float>(z);
    }
  return h;
}

// Twice the signed area of a TIN triangle on the grid.
long long tin_area2(const Tin& tin, const std::array<std::int32_t, 3>& t) {
  const long long ax = tin.samples[t[0]] % tin.width, ay = tin.samples[t[0]] / tin.width;
  const long long bx = tin.samples[t[1]] % tin.width, by = tin.samples[t[1]] / tin.width;
  const long long cx = tin.samples[t[2]] % tin.width, cy = tin.samples[t[2]] / tin.width;
  return (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
}

// Every triangle counter-clockwise and not degenerate, every edge used once (on the border of the rectangle)
// or twice in opposite directions, and the areas add up to the rectangle's: the triangles tile it exactly.
void expect_exact_cover(const Tin& tin) {
  long long area = 0;
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : tin.triangles) {
    const long long a2 = tin_area2(tin, t);
    ASSERT_GT(a2, 0) << "flipped or degenerate triangle";
    area += a2;
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  }
  EXPECT_EQ(area, 2LL * (tin.width - 1) * (tin.height - 1));
  for (const auto& [e, n] : edges) {
    ASSERT_EQ(n, 1) << "edge used twice in one direction";
    if (edges.count({e.second, e.first})) continue;
    const int ax = tin.samples[e.first] % tin.width, ay = tin.samples[e.first] / tin.width;
    const int bx = tin.samples[e.second] % tin.width, by = tin.samples[e.second] / tin.width;
    const bool on_border =
        (ax == bx && (ax == 0 || ax == tin.width - 1)) || (ay == by && (ay == 0 || ay == tin.height - 1));
    EXPECT_TRUE(on_border) << "open edge inside the rectangle";
  }
  // No vertex twice.
  std::vector<std::int32_t> samples = tin.samples;
  std::sort(samples.begin(), samples.end());
  EXPECT_EQ(std::adjacent_find(samples.begin(), samples.end()), samples.end());
}

TEST(TerrainTin, PlaneNeedsTwoTriangles) {
  const Domain d = Domain::from_extent({0, 0}, {640, 480}, {33, 25});
  const auto h = field(d, plane);
  const auto mesh = run_node("HeightfieldToMesh", d, {{"max_error", 0.01}}, {{"in", h}}).get<Mesh>();
  EXPECT_EQ(mesh->face_count(), 2u);
  EXPECT_TRUE(all_faces_face_up(mesh->mesh));
  EXPECT_LE(max_vertical_error(mesh->mesh, *h), 0.01);
}

TEST(TerrainTin, BoundHoldsAtEverySampleAndTheTrianglesTileTheRectangle) {
  const Domain d = Domain::from_extent({-150, -150}, {300, 260}, {97, 81});
  // High up, the single-precision scan's rounding margin (1e-6 |z|) is too wide for the tightest bound,
  // which then runs in double precision: both paths are checked.
  for (const float altitude : {0.0f, 60000.0f}) {
    auto h = std::make_shared<Heightfield>(*rough(d));
    for (float& z : h->data) z += altitude;
    std::size_t previous = 0;
    for (double bound : {0.05, 0.5, 2.0}) {
      for (bool simplify : {false, true}) {
        TinOptions options;
        options.max_error = bound;
        options.simplify = simplify;
        const Tin tin = heightfield_tin(*h, options);
        expect_exact_cover(tin);
        // Brute force on the grid, in double precision: every sample against the one triangle that covers it.
        double worst = 0.0;
        std::vector<int> covered(static_cast<std::size_t>(tin.width) * tin.height, 0);
        for (const auto& t : tin.triangles) {
          const int ax = tin.samples[t[0]] % tin.width, ay = tin.samples[t[0]] / tin.width;
          const int bx = tin.samples[t[1]] % tin.width, by = tin.samples[t[1]] / tin.width;
          const int cx = tin.samples[t[2]] % tin.width, cy = tin.samples[t[2]] / tin.width;
          const double det = static_cast<double>(tin_area2(tin, t));
          for (int j = std::min({ay, by, cy}); j <= std::max({ay, by, cy}); ++j)
            for (int i = std::min({ax, bx, cx}); i <= std::max({ax, bx, cx}); ++i) {
              const double l1 = ((i - ax) * double(cy - ay) - (cx - ax) * double(j - ay)) / det;
              const double l2 = ((bx - ax) * double(j - ay) - (i - ax) * double(by - ay)) / det;
              const double l0 = 1.0 - l1 - l2;
              if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) continue;
              const double z = l0 * h->at(ax, ay) + l1 * h->at(bx, by) + l2 * h->at(cx, cy);
              worst = std::max(worst, std::abs(h->at(i, j) - z));
              covered[h->index(i, j)] = 1;
            }
        }
        EXPECT_EQ(std::count(covered.begin(), covered.end(), 0), 0);
        EXPECT_LE(worst, bound * (1 + 1e-9)) << bound << " simplify " << simplify << " altitude " << altitude;
        EXPECT_GT(worst, bound * 0.5) << "the bound is used, not just respected";
        EXPECT_NEAR(tin.max_error, worst, 1e-9 * (1 + worst));
        if (simplify) {
          EXPECT_LT(tin.triangles.size(), previous) << "the collapses remove triangles of the greedy TIN";
          if (bound >= 2.0) {
            EXPECT_LT(tin.triangles.size(), 2u * 96u * 80u / 4u);
          }
        }
        previous = tin.triangles.size();
      }
    }
  }
}

// The SIMD scan against brute force on random grid triangles (flat tops and bottoms, slivers, long rows):
// the same samples (edges included), the largest error within the float margin, its first sample, and the
// early stop above a limit.
TEST(TerrainTin, SimdScanMatchesBruteForceOnRandomTriangles) {
  const int w = 53, h = 47;
  std::vector<float> z(static_cast<std::size_t>(w) * h);
  std::uint64_t state = 12345;
  auto next = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(state >> 33);
  };
  for (float& v : z) v = static_cast<float>(next() % 100000) * 0.01f - 300.0f;
  const double margin = 1e-6 * 700.0;
  int tested = 0;
  while (tested < 4000) {
    int x[3], y[3];
    const int span = tested % 4 == 0 ? 52 : 6;  // mostly small triangles, as in the TIN, and some large ones
    x[0] = static_cast<int>(next() % w), y[0] = static_cast<int>(next() % h);
    for (int k = 1; k < 3; ++k) {
      x[k] = std::clamp(x[0] + static_cast<int>(next() % (2 * span + 1)) - span, 0, w - 1);
      y[k] = std::clamp(y[0] + static_cast<int>(next() % (2 * span + 1)) - span, 0, h - 1);
    }
    long long area2 =
        static_cast<long long>(x[1] - x[0]) * (y[2] - y[0]) - static_cast<long long>(y[1] - y[0]) * (x[2] - x[0]);
    if (area2 == 0) continue;
    if (area2 < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]), area2 = -area2;
    ++tested;
    const double za = z[y[0] * w + x[0]], zb = z[y[1] * w + x[1]], zc = z[y[2] * w + x[2]];
    double worst = -1.0;
    std::vector<double> error(z.size(), -1.0);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        long long e[3];
        for (int k = 0; k < 3; ++k) {
          const int a = k, b = (k + 1) % 3;
          e[k] = static_cast<long long>(x[b] - x[a]) * (j - y[a]) - static_cast<long long>(y[b] - y[a]) * (i - x[a]);
        }
        if (e[0] < 0 || e[1] < 0 || e[2] < 0) continue;
        // Barycentric weights of c and a from the exact edge functions.
        const double plane =
            (static_cast<double>(e[1]) * za + static_cast<double>(e[2]) * zb + static_cast<double>(e[0]) * zc) / area2;
        error[j * w + i] = std::abs(z[j * w + i] - plane);
        worst = std::max(worst, error[j * w + i]);
      }
    tin::ScanRequest r;
    r.z = z.data();
    r.size = z.size();
    r.width = w;
    r.ax = x[0], r.ay = y[0], r.bx = x[1], r.by = y[1], r.cx = x[2], r.cy = y[2];
    const tin::ScanResult s = tin::scan_triangle(r);
    ASSERT_NEAR(s.error, worst, margin) << x[0] << "," << y[0] << " " << x[1] << "," << y[1] << " " << x[2] << ","
                                        << y[2];
    ASSERT_GE(s.sample, 0);
    ASSERT_GE(error[s.sample], 0.0) << "the sample lies in the triangle";
    EXPECT_NEAR(error[s.sample], worst, 2 * margin);
    for (int k = 0; k < s.sample; ++k)
      ASSERT_LT(error[k], worst - 2 * margin > 0.0 ? worst - 2 * margin : error[s.sample] + 2 * margin)
          << "an earlier sample (row-major) has the largest error";
    r.stop_above = true;
    r.limit = static_cast<float>(worst + 4 * margin);
    EXPECT_LE(tin::scan_triangle(r).error, r.limit) << "nothing exceeds a limit above the largest error";
    r.limit = static_cast<float>(worst - 4 * margin);
    if (r.limit > 0.0f) {
      EXPECT_GT(tin::scan_triangle(r).error, r.limit) << "the early stop reports an error above it";
    }
  }
}

TEST(TerrainTin, TinyStripsAndFlatGrids) {
  for (const glm::ivec2 res :
       {glm::ivec2(2, 2), glm::ivec2(2, 57), glm::ivec2(61, 2), glm::ivec2(3, 3), glm::ivec2(40, 33)}) {
    const Domain d = Domain::from_extent({0, 0}, {100, 80}, res);
    for (bool flat : {true, false}) {
      auto h = std::make_shared<Heightfield>(d, 7.0f);
      if (!flat) h = std::make_shared<Heightfield>(*rough(d));
      for (std::size_t target : {std::size_t(0), std::size_t(40)}) {
        TinOptions options;
        options.max_error = target ? 0.0 : 0.1;
        options.target_faces = target;
        const Tin tin = heightfield_tin(*h, options);
        expect_exact_cover(tin);
        if (flat) {
          EXPECT_EQ(tin.triangles.size(), 2u) << res.x << "x" << res.y;
        }
        if (target) {
          EXPECT_LE(tin.triangles.size(), std::max<std::size_t>(target, 2));
        } else {
          EXPECT_LE(tin.max_error, 0.1);
        }
      }
    }
  }
}

TEST(TerrainTin, GreedyInsertionIsDelaunay) {
  const Domain d = Domain::from_extent({-150, -150}, {300, 300}, {65, 65});
  const auto h = rough(d);
  TinOptions options;
  options.max_error = 0.3;
  options.simplify = false;
  const Tin tin = heightfield_tin(*h, options);
  ASSERT_GT(tin.triangles.size(), 100u);
  auto xy = [&](int v) {
    return std::pair<long long, long long>(tin.samples[v] % tin.width, tin.samples[v] / tin.width);
  };
  for (const auto& t : tin.triangles) {
    const auto [ax, ay] = xy(t[0]);
    const auto [bx, by] = xy(t[1]);
    const auto [cx, cy] = xy(t[2]);
    for (std::size_t v = 0; v < tin.samples.size(); ++v) {
      const auto [dx, dy] = xy(static_cast<int>(v));
      const long long adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy, cdx = cx - dx, cdy = cy - dy;
      const long long det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                            (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                            (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
      ASSERT_LE(det, 0) << "vertex " << v << " inside a circumcircle";
    }
  }
}

TEST(TerrainTin, MeshBoundNormalsAndVertices) {
  const Domain d = Domain::from_extent({-150, -150}, {300, 300}, {61, 61});
  const auto h = field(d, hills);
  const std::size_t full = 2u * 60u * 60u;
  std::size_t previous_faces = 0;
  for (double bound : {0.05, 0.5, 2.0}) {
    TinOptions options;
    options.max_error = bound;
    Mesh mesh = heightfield_mesh(*h, nullptr, options);
    const double err = max_vertical_error(mesh.mesh, *h);  // independent check on the float mesh
    EXPECT_LE(err, bound + 1e-5) << "bound " << bound;
    EXPECT_GT(err, bound * 0.3) << "the bound is used, not just respected: " << bound;
    EXPECT_TRUE(all_faces_face_up(mesh.mesh));
    EXPECT_LT(mesh.face_count(), full);
    if (previous_faces) {
      EXPECT_LT(mesh.face_count(), previous_faces) << "a looser bound removes more";
    }
    previous_faces = mesh.face_count();
    // Vertices are samples with their heights and the grid mesh's normals.
    const Mesh grid = heightfield_grid_mesh(*h);
    for (auto v : mesh.mesh.vertices()) {
      const auto p = mesh.mesh.point(v);
      const auto s = d.to_sample({p[0], p[1]});
      const int i = static_cast<int>(std::lround(s.x)), j = static_cast<int>(std::lround(s.y));
      ASSERT_NEAR(s.x, i, 1e-3);
      ASSERT_NEAR(s.y, j, 1e-3);
      ASSERT_EQ(p[2], h->at(i, j));
      ASSERT_EQ(mesh.mesh.normal(v), grid.mesh.normal(TriMesh::VertexHandle(static_cast<int>(h->index(i, j)))));
      ASSERT_GT(mesh.mesh.normal(v)[2], 0.0f);
    }
  }
  EXPECT_LT(previous_faces, full / 10);  // 2 m on 40 m hills removes most of the grid
}

TEST(TerrainTin, TargetFaceCount) {
  const Domain d = Domain::from_extent({0, 0}, {300, 300}, {49, 49});
  const auto h = field(d, hills);
  const auto only_target =
      run_node("HeightfieldToMesh", d, {{"target_faces", std::int64_t(300)}}, {{"in", h}}).get<Mesh>();
  EXPECT_LE(only_target->face_count(), 300u);
  EXPECT_GE(only_target->face_count(), 290u);
  EXPECT_TRUE(all_faces_face_up(only_target->mesh));
  // With an error bound too, the tighter of the two wins.
  const auto both =
      run_node("HeightfieldToMesh", d, {{"target_faces", std::int64_t(300)}, {"max_error", 0.01}}, {{"in", h}})
          .get<Mesh>();
  EXPECT_GT(both->face_count(), 300u);
  EXPECT_LE(max_vertical_error(both->mesh, *h), 0.01 + 1e-5);
  const auto loose =
      run_node("HeightfieldToMesh", d, {{"target_faces", std::int64_t(3000)}, {"max_error", 2.0}}, {{"in", h}})
          .get<Mesh>();
  EXPECT_GE(loose->face_count(), 2900u);
  EXPECT_LE(loose->face_count(), 3000u);
}

TEST(TerrainTin, NodeMatchesFunctionAndIsDeterministic) {
  const Domain d = Domain::from_extent({0, 0}, {300, 300}, {33, 33});
  const auto h = rough(d);
  TinOptions options;
  options.max_error = 0.3;
  const Mesh direct = heightfield_mesh(*h, nullptr, options);
  const auto a = run_node("HeightfieldToMesh", d, {{"max_error", 0.3}}, {{"in", h}}).get<Mesh>();
  const auto b = run_node("HeightfieldToMesh", d, {{"max_error", 0.3}}, {{"in", h}}).get<Mesh>();
  ASSERT_EQ(a->face_count(), direct.face_count());
  ASSERT_EQ(a->face_count(), b->face_count());
  for (auto v : a->mesh.vertices()) {
    ASSERT_EQ(a->mesh.point(v), direct.mesh.point(v));
    ASSERT_EQ(a->mesh.point(v), b->mesh.point(v));
  }
  for (auto f : a->mesh.faces()) {
    auto fa = a->mesh.cfv_iter(f);
    auto fb = b->mesh.cfv_iter(TriMesh::FaceHandle(f.idx()));
    for (int k = 0; k < 3; ++k, ++fa, ++fb) ASSERT_EQ(fa->idx(), fb->idx());
  }
}

TEST(TerrainTin, CancelledRunThrows) {
  const Domain d = Domain::from_extent({0, 0}, {300, 300}, {33, 33});
  CancelToken cancel;
  cancel.cancel();
  EXPECT_THROW(run_node("HeightfieldToMesh", d, {{"max_error", 0.3}}, {{"in", field(d, hills)}}, {}, &cancel),
               Cancelled);
}

TEST(TerrainTin, NonFiniteHeightsAreAnError) {
  const Domain d = Domain::from_extent({0, 0}, {300, 300}, {9, 9});
  auto h = std::make_shared<Heightfield>(d);
  h->at(3, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(run_node("HeightfieldToMesh", d, {{"max_error", 0.3}}, {{"in", HeightfieldPtr(h)}}), NodeError);
}

// --- WriteMesh ---

class MeshFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    policy_.output_dir = test::scratch_dir("mesh") / "out";
    // Far from the origin, so text formats must keep 9 significant digits to read back the same floats.
    const Domain d = Domain::from_extent({123456.25, -98765.5}, {90, 60}, {10, 7});
    height_ = field(d, hills);
    auto img = std::make_shared<Image>(d, 3);
    for (std::size_t k = 0; k < img->data.size(); ++k) img->data[k] = static_cast<float>((k * 37 % 101) / 100.0);
    mesh_ = run_node("HeightfieldToMesh", d, {}, {{"in", height_}, {"colors", ImagePtr(img)}}).get<Mesh>();
  }
  fs::path write(const std::string& name, std::map<std::string, ParamValue> params = {}) {
    params["path"] = name;
    run_node("WriteMesh", Domain{}, params, {{"in", mesh_}}, policy_);
    return policy_.output_dir / name;
  }
  OutputPolicy policy_;
  HeightfieldPtr height_;
  MeshPtr mesh_;
};

TEST_F(MeshFileTest, ObjPlyStlRoundTripThroughOpenMesh) {
  for (const std::string name : {"t.obj", "t.ply", "t_ascii.ply", "t.stl", "t_ascii.stl"}) {
    const bool ascii = name.find("ascii") != std::string::npos;
    // Orogen's own axes (z-up) in every format, to compare positions as they are.
    const fs::path file = write("meshes/" + name, {{"binary", !ascii}, {"up_axis", std::string("Z")}});
    ASSERT_TRUE(fs::exists(file)) << name;
    TriMesh back;
    back.request_vertex_normals();
    back.request_vertex_colors();
    OpenMesh::IO::Options opt;
    if (name.find(".stl") == std::string::npos) opt += OpenMesh::IO::Options::VertexNormal;
    if (name.find(".ply") != std::string::npos) opt += OpenMesh::IO::Options::VertexColor;
    if (!ascii && name.find(".obj") == std::string::npos) opt += OpenMesh::IO::Options::Binary;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(back, file.string(), opt)) << name;
    EXPECT_EQ(back.n_vertices(), mesh_->vertex_count()) << name;
    EXPECT_EQ(back.n_faces(), mesh_->face_count()) << name;
    // The same vertices, bit for bit (STL merges vertices by position: compare as sets).
    std::vector<std::array<float, 3>> written, original;
    for (auto v : back.vertices()) written.push_back({back.point(v)[0], back.point(v)[1], back.point(v)[2]});
    for (auto v : mesh_->mesh.vertices())
      original.push_back({mesh_->mesh.point(v)[0], mesh_->mesh.point(v)[1], mesh_->mesh.point(v)[2]});
    std::sort(written.begin(), written.end());
    std::sort(original.begin(), original.end());
    EXPECT_EQ(written, original) << name;
    if (name.find(".stl") == std::string::npos) {
      EXPECT_TRUE(opt.check(OpenMesh::IO::Options::VertexNormal)) << name << " has normals";
      for (auto v : back.vertices()) {
        const auto n = back.normal(v), n0 = mesh_->mesh.normal(v);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(n[k], n0[k], 1e-4) << name;
      }
    }
    if (name.find(".ply") != std::string::npos) {
      ASSERT_TRUE(opt.check(OpenMesh::IO::Options::VertexColor)) << name << " has colours";
      for (auto v : back.vertices()) {
        const auto c = back.color(v), c0 = mesh_->mesh.color(v);
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(c[k], linear_to_srgb(static_cast<double>(c0[k])), 0.5 / 255 + 1e-6) << name;  // 8-bit sRGB
      }
    }
  }
}

// up_axis Y, and auto for OBJ (what Blender and most DCC tools import), rotate to y-up; auto leaves PLY and STL
// z-up, as Z does.
TEST_F(MeshFileTest, UpAxisYAndAutoForObjSwapToYUp) {
  const std::string Y = "Y", Z = "Z", automatic = "auto";
  for (const auto& [name, up_axis, y_up] :
       {std::tuple{"yup.obj", Y, true}, std::tuple{"auto.obj", automatic, true},
        std::tuple{"default.obj", std::string(), true}, std::tuple{"auto.ply", automatic, false},
        std::tuple{"z.obj", Z, false}, std::tuple{"yup.ply", Y, true},
        std::tuple{"default.ply", std::string(), false}}) {
    std::map<std::string, ParamValue> params;
    if (!up_axis.empty()) params["up_axis"] = up_axis;  // empty: the parameter's default
    const fs::path file = write(name, params);
    TriMesh back;
    back.request_vertex_normals();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal;
    if (std::string(name).ends_with(".ply")) opt += OpenMesh::IO::Options::Binary;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(back, file.string(), opt)) << name;
    ASSERT_EQ(back.n_vertices(), mesh_->vertex_count()) << name;
    for (auto v : back.vertices()) {
      const auto p = back.point(v), p0 = mesh_->mesh.point(v);
      const auto n = back.normal(v), n0 = mesh_->mesh.normal(v);
      ASSERT_NEAR(p[0], p0[0], 1e-4) << name;
      if (y_up) {
        ASSERT_NEAR(p[1], p0[2], 1e-4) << name;  // height is now y
        ASSERT_NEAR(p[2], -p0[1], 1e-4) << name;
        ASSERT_NEAR(n[1], n0[2], 1e-4) << name;
        ASSERT_NEAR(n[2], -n0[1], 1e-4) << name;
      } else {
        ASSERT_NEAR(p[1], p0[1], 1e-4) << name;
        ASSERT_NEAR(p[2], p0[2], 1e-4) << name;
      }
    }
    // A proper rotation: the winding still makes faces point up, along +y or +z.
    back.update_face_normals();
    for (auto f : back.faces()) ASSERT_GT(back.normal(f)[y_up ? 1 : 2], 0.0f) << name;
  }
}

TEST_F(MeshFileTest, ObjTextureCoordinatesAndMaterial) {
  const fs::path file = write("m/terrain.obj", {{"texture", std::string("colour.png")}});
  const fs::path library = policy_.output_dir / "m" / "terrain.mtl";
  ASSERT_TRUE(fs::exists(library));
  std::ifstream mtl(library);
  const std::string mtl_text((std::istreambuf_iterator<char>(mtl)), std::istreambuf_iterator<char>());
  EXPECT_NE(mtl_text.find("newmtl terrain\n"), std::string::npos);
  EXPECT_NE(mtl_text.find("map_Kd colour.png\n"), std::string::npos);
  std::ifstream obj(file);
  std::string line;
  std::size_t vt = 0;
  bool mtllib = false, usemtl = false;
  while (std::getline(obj, line)) {
    vt += line.rfind("vt ", 0) == 0;
    mtllib = mtllib || line == "mtllib terrain.mtl";
    usemtl = usemtl || line == "usemtl terrain";
  }
  EXPECT_TRUE(mtllib);
  EXPECT_TRUE(usemtl);
  EXPECT_EQ(vt, mesh_->vertex_count());
  // Read back by OpenMesh: each vertex's (u, v) is its position over the footprint.
  TriMesh back;
  back.request_vertex_texcoords2D();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexTexCoord;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(back, file.string(), opt));
  ASSERT_TRUE(opt.check(OpenMesh::IO::Options::VertexTexCoord));
  ASSERT_EQ(back.n_vertices(), mesh_->vertex_count());
  const Domain& d = height_->domain;
  for (auto v : back.vertices()) {
    const auto p = mesh_->mesh.point(v);
    const auto uv = back.texcoord2D(v);
    ASSERT_NEAR(uv[0], (p[0] - d.x(0)) / (d.x(d.width() - 1) - d.x(0)), 1e-5);
    ASSERT_NEAR(uv[1], (p[1] - d.y(0)) / (d.y(d.height() - 1) - d.y(0)), 1e-5);
  }
  // Without a texture: UVs but no material; uvs off: neither.
  const fs::path plain = write("plain.obj", {{"uvs", false}});
  std::ifstream plain_in(plain);
  const std::string plain_text((std::istreambuf_iterator<char>(plain_in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(plain_text.find("vt "), std::string::npos);
  EXPECT_EQ(plain_text.find("mtllib"), std::string::npos);
  EXPECT_FALSE(fs::exists(policy_.output_dir / "plain.mtl"));
}

// Closed: every edge has a face on both sides. The enclosed volume (divergence theorem) is positive, so the
// faces point out, and equals the prism under the surface down to the base plane.
void expect_closed_solid(const TriMesh& m, double expected_volume) {
  ASSERT_GT(m.n_faces(), 0u);
  for (auto e : m.edges()) ASSERT_FALSE(m.is_boundary(e)) << "open edge " << e.idx();
  for (auto v : m.vertices()) ASSERT_FALSE(m.is_boundary(v));
  double volume = 0.0;
  for (auto f : m.faces()) {
    auto fv = m.cfv_iter(f);
    const OpenMesh::Vec3d a = OpenMesh::vector_cast<OpenMesh::Vec3d>(m.point(*fv));
    const OpenMesh::Vec3d b = OpenMesh::vector_cast<OpenMesh::Vec3d>(m.point(*++fv));
    const OpenMesh::Vec3d c = OpenMesh::vector_cast<OpenMesh::Vec3d>(m.point(*++fv));
    volume += OpenMesh::dot(a, OpenMesh::cross(b, c)) / 6.0;
  }
  EXPECT_NEAR(volume, expected_volume, 1e-4 * std::abs(expected_volume));
  // Euler characteristic of a sphere.
  EXPECT_EQ(static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) + static_cast<long>(m.n_faces()), 2);
}

TEST(MeshBase, ClosesATerrainIntoASolid) {
  const Domain d = Domain::from_extent({-150, -150}, {300, 260}, {49, 41});
  const auto h = rough(d);
  TinOptions options;
  options.max_error = 0.5;
  const Mesh top = heightfield_mesh(*h, nullptr, options);
  const double depth = 10.0;
  const Mesh solid = mesh_with_base(top, depth);
  float zmin = std::numeric_limits<float>::infinity();
  for (auto v : top.mesh.vertices()) zmin = std::min(zmin, top.mesh.point(v)[2]);
  const double zb = static_cast<float>(zmin - depth);
  // The prism under each top triangle: its xy area times the mean height above the base.
  double expected = 0.0;
  for (auto f : top.mesh.faces()) {
    auto fv = top.mesh.cfv_iter(f);
    const auto a = top.mesh.point(*fv), b = top.mesh.point(*++fv), c = top.mesh.point(*++fv);
    const double area =
        0.5 * ((double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * (double(b[1]) - a[1]));
    expected += area * ((double(a[2]) + b[2] + c[2]) / 3.0 - zb);
  }
  expect_closed_solid(solid.mesh, expected);
  // The top is unchanged, the bottom is flat at the base and faces down.
  for (auto v : top.mesh.vertices()) ASSERT_EQ(solid.mesh.point(v), top.mesh.point(v));
  for (auto f : solid.mesh.faces()) {
    if (f.idx() < static_cast<int>(top.face_count())) continue;
    const auto n = solid.mesh.calc_face_normal(f);
    bool bottom = true;
    for (auto v : solid.mesh.fv_range(f)) bottom = bottom && solid.mesh.point(v)[2] == static_cast<float>(zb);
    if (bottom)
      ASSERT_LT(n[2], -0.999f);
    else
      ASSERT_NEAR(n[2], 0.0f, 1e-5);  // walls are vertical
  }
}

TEST_F(MeshFileTest, BaseDepthWritesAClosedStl) {
  const fs::path file = write("solid.stl", {{"base_depth", 5.0}});
  TriMesh back;
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(back, file.string(), opt));  // STL: vertices merged by position
  for (auto e : back.edges()) ASSERT_FALSE(back.is_boundary(e));
  EXPECT_GT(back.n_faces(), mesh_->face_count());
}

TEST_F(MeshFileTest, Errors) {
  EXPECT_THROW(write("../escape.obj"), NodeError);
  EXPECT_FALSE(fs::exists(policy_.output_dir.parent_path() / "escape.obj"));
  EXPECT_THROW(run_node("WriteMesh", Domain{}, {{"path", std::string("empty.ply")}},
                        {{"in", std::make_shared<const Mesh>()}}, policy_),
               NodeError);
  EXPECT_FALSE(fs::exists(policy_.output_dir / "empty.ply"));
}

}  // namespace
}  // namespace orogen
