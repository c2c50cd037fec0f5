#include "nodes/geometry/heightfield_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Decimater/Observer.hh>

#include "nodes/geometry/mod_height_error.h"

namespace orogen {
namespace {

// One channel of an image at continuous sample coordinates (u, v), bilinear, clamped at the borders.
float image_bilinear(const Image& img, int channel, double u, double v) {
  const int w = img.width(), h = img.height();
  u = std::clamp(u, 0.0, static_cast<double>(w - 1));
  v = std::clamp(v, 0.0, static_cast<double>(h - 1));
  const int i = std::min(static_cast<int>(u), std::max(w - 2, 0));
  const int j = std::min(static_cast<int>(v), std::max(h - 2, 0));
  const int i1 = std::min(i + 1, w - 1), j1 = std::min(j + 1, h - 1);
  const double fu = u - i, fv = v - j;
  const double a = img.pixel(i, j)[channel], b = img.pixel(i1, j)[channel];
  const double c = img.pixel(i, j1)[channel], d = img.pixel(i1, j1)[channel];
  return static_cast<float>((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv);
}

OpenMesh::Vec4f color_at(const Image& img, double x, double y) {
  const auto s = img.domain.to_sample({x, y});
  float c[4];
  const int n = std::min(img.channels, 4);
  for (int k = 0; k < n; ++k) c[k] = image_bilinear(img, k, s.x, s.y);
  switch (n) {
    case 1: return {c[0], c[0], c[0], 1.0f};
    case 2: return {c[0], c[0], c[0], c[1]};
    case 3: return {c[0], c[1], c[2], 1.0f};
    default: return {c[0], c[1], c[2], c[3]};
  }
}

// Surface normal of the heightfield at sample (i, j): central differences inside, one-sided at the border.
OpenMesh::Vec3f surface_normal(const Heightfield& h, int i, int j) {
  const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, h.width() - 1);
  const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, h.height() - 1);
  const double dzdx = (double(h.at(i1, j)) - h.at(i0, j)) / (h.domain.x(i1) - h.domain.x(i0));
  const double dzdy = (double(h.at(i, j1)) - h.at(i, j0)) / (h.domain.y(j1) - h.domain.y(j0));
  const double len = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
  return {static_cast<float>(-dzdx / len), static_cast<float>(-dzdy / len), static_cast<float>(1.0 / len)};
}

// ModQuadricT without an error bound, its priority clamped at 0. On flat or planar regions the quadric error
// is zero up to round-off, and DecimaterT treats a negative priority (say -1e-12) as an illegal collapse,
// which stalls the decimation of planes at hundreds of faces. Only the round-off is clamped: an actual
// ILLEGAL_COLLAPSE (not returned without an error bound, but kept meaningful) passes through.
template <class MeshT>
class ModQuadricClampedT : public OpenMesh::Decimater::ModQuadricT<MeshT> {
 public:
  using Quadric = OpenMesh::Decimater::ModQuadricT<MeshT>;
  using Handle = OpenMesh::Decimater::ModHandleT<ModQuadricClampedT>;
  explicit ModQuadricClampedT(MeshT& mesh) : Quadric(mesh) {}
  const std::string& name() const override {
    static const std::string n("QuadricClamped");
    return n;
  }
  float collapse_priority(const typename Quadric::CollapseInfo& ci) override {
    const float p = Quadric::collapse_priority(ci);
    return p == float(Quadric::ILLEGAL_COLLAPSE) ? p : std::max(0.0f, p);
  }
};

class Progress : public OpenMesh::Decimater::Observer {
 public:
  Progress(const DecimationOptions& options, std::size_t total)
      : Observer(std::max<std::size_t>(1, total / 100)), options_(options), total_(std::max<std::size_t>(1, total)) {}
  void notify(std::size_t step) override {
    if (options_.progress) options_.progress(std::min(1.0, static_cast<double>(step) / static_cast<double>(total_)));
  }
  bool abort() const override { return options_.should_stop && options_.should_stop(); }

 private:
  const DecimationOptions& options_;
  std::size_t total_;
};

}  // namespace

Mesh heightfield_grid_mesh(const Heightfield& height, const Image* colors) {
  const int w = height.width(), h = height.height();
  if (w < 2 || h < 2) throw std::invalid_argument("a heightfield mesh needs at least 2 x 2 samples");
  if (static_cast<double>(w - 1) * (h - 1) * 2 > static_cast<double>(std::numeric_limits<int>::max() / 2))
    throw std::invalid_argument("the heightfield is too large for one mesh (" + height.domain.describe() + ")");
  if (colors && (colors->channels < 1 || colors->width() < 1 || colors->height() < 1))
    throw std::invalid_argument("the color image is empty");

  Mesh result;
  TriMesh& m = result.mesh;
  m.reserve(static_cast<std::size_t>(w) * h, static_cast<std::size_t>(w) * h * 3, static_cast<std::size_t>(w - 1) * (h - 1) * 2);
  std::vector<TriMesh::VertexHandle> v(static_cast<std::size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double x = height.domain.x(i), y = height.domain.y(j);
      const auto vh = m.add_vertex({static_cast<float>(x), static_cast<float>(y), height.at(i, j)});
      m.set_normal(vh, surface_normal(height, i, j));
      m.set_color(vh, colors ? color_at(*colors, x, y) : OpenMesh::Vec4f(1, 1, 1, 1));
      v[height.index(i, j)] = vh;
    }
  for (int j = 0; j + 1 < h; ++j)
    for (int i = 0; i + 1 < w; ++i) {
      // Corners counter-clockwise seen from +z: a (i, j), b (i+1, j), c (i+1, j+1), d (i, j+1).
      const auto a = v[height.index(i, j)], b = v[height.index(i + 1, j)];
      const auto c = v[height.index(i + 1, j + 1)], d = v[height.index(i, j + 1)];
      const double ac = (m.point(c) - m.point(a)).sqrnorm(), bd = (m.point(d) - m.point(b)).sqrnorm();
      if (ac <= bd) {
        m.add_face(a, b, c);
        m.add_face(a, c, d);
      } else {
        m.add_face(a, b, d);
        m.add_face(b, c, d);
      }
    }
  m.update_face_normals();
  return result;
}

std::size_t decimate_heightfield_mesh(Mesh& mesh, const DecimationOptions& options) {
  const bool bounded = options.max_error > 0.0;
  if (!bounded && options.target_faces == 0) return 0;
  TriMesh& m = mesh.mesh;
  m.update_face_normals();  // ModNormalFlippingT compares against the current face normals

  using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
  Decimater decimater(m);
  ModQuadricClampedT<TriMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle flipping;
  ModHeightErrorT<TriMesh>::Handle height_error;
  decimater.add(quadric);
  decimater.add(flipping);
  decimater.add(height_error);
  // The quadric only orders the collapses: its error is area-weighted (m^4), not a distance, so the bound in
  // metres is enforced exactly by the height-error module instead.
  decimater.module(quadric).unset_max_err();
  decimater.module(height_error).set_tolerance(bounded ? options.max_error : std::numeric_limits<double>::infinity());
  if (!decimater.initialize()) throw std::logic_error("OpenMesh decimater failed to initialise");

  Progress observer(options, m.n_vertices());
  decimater.set_observer(&observer);
  const std::size_t collapses =
      options.target_faces > 0 ? decimater.decimate_to_faces(0, options.target_faces) : decimater.decimate();
  decimater.set_observer(nullptr);
  m.garbage_collection();
  m.update_face_normals();
  return collapses;
}

}  // namespace orogen
