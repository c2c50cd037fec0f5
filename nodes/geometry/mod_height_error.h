#pragma once
// An OpenMesh decimation module that keeps a heightfield mesh within a vertical error bound.
//
// Every original sample removed by a collapse is remembered in the face whose ground-plane (xy) projection
// contains it. A collapse is legal only if
//  - every new face keeps a positive xy orientation (the mesh stays a heightfield: no fold-over, no vertical
//    sliver), and
//  - every remembered sample of the affected faces, and the removed vertex itself, lies over some new face
//    with |z - z_face(x, y)| <= tolerance.
// So the decimated surface is within `tolerance` metres of every original sample, measured vertically, and
// its footprint stays the original rectangle (a corner or a kink of the border cannot be cut off, as its
// sample would lie over no face). Binary module: it never sets the priority, only forbids collapses.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

namespace orogen {

template <class MeshT>
class ModHeightErrorT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModHeightErrorT, MeshT, HeightError);
  using Point = typename Mesh::Point;
  using FaceHandle = typename Mesh::FaceHandle;

  explicit ModHeightErrorT(MeshT& mesh) : Base(mesh, true), mesh_(Base::mesh()) { mesh_.add_property(samples_); }
  ~ModHeightErrorT() override { mesh_.remove_property(samples_); }

  // Largest allowed vertical distance, metres (infinity: only the heightfield property is kept).
  void set_tolerance(double metres) { tolerance_ = metres; }
  double tolerance() const { return tolerance_; }

  void initialize() override {
    for (auto f : mesh_.faces()) mesh_.property(samples_, f).clear();
  }

  float collapse_priority(const CollapseInfo& ci) override {
    ring_.clear();
    faces_.clear();
    for (auto vf = mesh_.cvf_iter(ci.v0); vf.is_valid(); ++vf) {
      ring_.push_back(*vf);
      if (*vf != ci.fl && *vf != ci.fr) faces_.push_back(*vf);
    }
    mesh_.set_point(ci.v0, ci.p1);  // simulate the collapse
    bool ok = true;
    for (auto f : faces_)
      if (!(oriented_area(f) > 0.0)) ok = false;
    for (std::size_t r = 0; ok && r < ring_.size(); ++r)
      for (const Point& p : mesh_.property(samples_, ring_[r]))
        if (!(ok = covered(p))) break;
    ok = ok && covered(ci.p0);
    mesh_.set_point(ci.v0, ci.p0);
    return ok ? float(Base::LEGAL_COLLAPSE) : float(Base::ILLEGAL_COLLAPSE);
  }

  // The faces that survive the collapse around v0; after it they surround v1 in v0's place.
  void preprocess_collapse(const CollapseInfo& ci) override {
    changed_.clear();
    for (auto vf = mesh_.cvf_iter(ci.v0); vf.is_valid(); ++vf)
      if (*vf != ci.fl && *vf != ci.fr) changed_.push_back(*vf);
  }

  // After the collapse, hand the samples of the changed and removed faces, and the removed vertex, to the
  // changed face each lies over: exactly the samples and faces collapse_priority checked, so faces that did
  // not change keep their samples and the priorities of their vertices stay valid.
  void postprocess_collapse(const CollapseInfo& ci) override {
    gathered_.clear();
    for (auto f : changed_) take_samples(f);
    for (FaceHandle f : {ci.fl, ci.fr})
      if (f.is_valid()) take_samples(f);
    gathered_.push_back(ci.p0);
    if (changed_.empty()) return;
    for (const Point& p : gathered_) {
      // The containing face; round-off at shared edges can leave a sample just outside all of them, so keep
      // the face it is least outside of.
      FaceHandle best = changed_.front();
      double best_slack = -std::numeric_limits<double>::infinity();
      for (auto f : changed_) {
        double dz = 0.0, slack = 0.0;
        if (offset_over(f, p, dz, slack)) {
          best = f;
          break;
        }
        if (slack > best_slack) best_slack = slack, best = f;
      }
      mesh_.property(samples_, best).push_back(p);
    }
  }

 private:
  // Whether p lies over one of faces_ within the tolerance.
  bool covered(const Point& p) const {
    for (auto f : faces_) {
      double dz = 0.0, slack = 0.0;
      if (offset_over(f, p, dz, slack) && std::abs(dz) <= tolerance_) return true;
    }
    return false;
  }

  void take_samples(FaceHandle f) {
    auto& s = mesh_.property(samples_, f);
    gathered_.insert(gathered_.end(), s.begin(), s.end());
    s.clear();
  }

  // Twice the signed xy area of face f (positive: counter-clockwise seen from +z).
  double oriented_area(FaceHandle f) const {
    auto fv = mesh_.cfv_iter(f);
    const Point& a = mesh_.point(*fv);
    const Point& b = mesh_.point(*++fv);
    const Point& c = mesh_.point(*++fv);
    return (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * (double(b[1]) - a[1]);
  }

  // Whether p lies over face f in xy (within round-off); if so dz = p.z - the face's height at p.
  // `slack` is the smallest barycentric coordinate (negative when outside).
  bool offset_over(FaceHandle f, const Point& p, double& dz, double& slack) const {
    auto fv = mesh_.cfv_iter(f);
    const Point& a = mesh_.point(*fv);
    const Point& b = mesh_.point(*++fv);
    const Point& c = mesh_.point(*++fv);
    const double d = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * (double(b[1]) - a[1]);
    if (!(d > 0.0)) {
      slack = -std::numeric_limits<double>::infinity();
      return false;
    }
    const double px = double(p[0]) - a[0], py = double(p[1]) - a[1];
    const double l1 = (px * (double(c[1]) - a[1]) - (double(c[0]) - a[0]) * py) / d;
    const double l2 = ((double(b[0]) - a[0]) * py - px * (double(b[1]) - a[1])) / d;
    const double l0 = 1.0 - l1 - l2;
    slack = std::min({l0, l1, l2});
    if (slack < -kInside) return false;
    dz = double(p[2]) - (l0 * a[2] + l1 * b[2] + l2 * c[2]);
    return true;
  }

  static constexpr double kInside = 1e-9;  // barycentric tolerance for samples on shared edges

  Mesh& mesh_;
  double tolerance_ = std::numeric_limits<double>::infinity();
  OpenMesh::FPropHandleT<std::vector<Point>> samples_;
  std::vector<Point> gathered_;
  std::vector<FaceHandle> ring_;     // faces around v0 (collapse_priority)
  std::vector<FaceHandle> faces_;    // the ones that survive the collapse
  std::vector<FaceHandle> changed_;  // the same, kept from preprocess_collapse to postprocess_collapse
};

}  // namespace orogen
