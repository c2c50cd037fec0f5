#include "nodes/rocks/hull_rock.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "nodes/common/hash.h"

namespace orogen::rocks {
namespace {

// Counter-based uniform numbers in [0, 1) keyed by (seed, variant, stream).
struct Stream {
  std::uint64_t key;
  std::uint64_t counter = 0;
  Stream(std::uint64_t seed, std::uint64_t variant, std::uint64_t stream)
      : key(mix64(mix64(seed ^ 0x6A09E667F3BCC909ull) ^ (variant * kGoldenGamma)) ^ (stream << 56)) {}
  double next() { return unit_double(mix64(key + 0xD1B54A32D192ED03ull * ++counter)); }
  double gauss() {
    const double u = 1.0 - next(), v = next();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * v);
  }
};

// 3D value noise in [-1, 1] with smooth (quintic) interpolation, hashed lattice.
double lattice(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t seed) {
  const std::uint64_t h = mix64(seed ^ mix64(static_cast<std::uint64_t>(x) * kGoldenGamma ^
                                             mix64(static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                                                   static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull)));
  return static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0;
}
double value_noise(const glm::dvec3& p, std::uint64_t seed) {
  const glm::dvec3 f = glm::floor(p);
  const glm::dvec3 t = p - f;
  const glm::dvec3 s = t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
  const auto ix = static_cast<std::int64_t>(f.x), iy = static_cast<std::int64_t>(f.y),
             iz = static_cast<std::int64_t>(f.z);
  double c[2][2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) c[dz][dy][dx] = lattice(ix + dx, iy + dy, iz + dz, seed);
  auto lerp = [](double a, double b, double u) { return a + (b - a) * u; };
  const double x00 = lerp(c[0][0][0], c[0][0][1], s.x), x10 = lerp(c[0][1][0], c[0][1][1], s.x);
  const double x01 = lerp(c[1][0][0], c[1][0][1], s.x), x11 = lerp(c[1][1][0], c[1][1][1], s.x);
  return lerp(lerp(x00, x10, s.y), lerp(x01, x11, s.y), s.z);
}

// Every kPollEvery elements of a long loop, a cancelled build stops (ExecContext::check_cancelled throws).
constexpr std::size_t kPollEvery = 1u << 14;
void poll(const ExecContext* ctx, std::size_t k) {
  if (ctx && k % kPollEvery == 0) ctx->check_cancelled();
}

void subdivide(Hull& h, const ExecContext* ctx) {
  std::map<std::pair<int, int>, int> mid;
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const int v = static_cast<int>(h.vertices.size());
    h.vertices.push_back(0.5 * (h.vertices[static_cast<std::size_t>(a)] + h.vertices[static_cast<std::size_t>(b)]));
    mid.emplace(key, v);
    return v;
  };
  std::vector<std::array<int, 3>> faces;
  faces.reserve(h.faces.size() * 4);
  for (std::size_t k = 0; k < h.faces.size(); ++k) {
    poll(ctx, k);
    const auto& f = h.faces[k];
    const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    faces.push_back({f[0], ab, ca});
    faces.push_back({ab, f[1], bc});
    faces.push_back({ca, bc, f[2]});
    faces.push_back({ab, bc, ca});
  }
  h.faces = std::move(faces);
}

std::vector<glm::dvec3> vertex_normals(const Hull& h) {
  std::vector<glm::dvec3> n(h.vertices.size(), glm::dvec3(0.0));
  for (const auto& f : h.faces) {
    const auto& a = h.vertices[static_cast<std::size_t>(f[0])];
    const glm::dvec3 fn =
        glm::cross(h.vertices[static_cast<std::size_t>(f[1])] - a, h.vertices[static_cast<std::size_t>(f[2])] - a);
    for (int v : f) n[static_cast<std::size_t>(v)] += fn;  // area-weighted
  }
  for (auto& v : n) {
    const double l = glm::length(v);
    v = l > 0.0 ? v / l : glm::dvec3(0.0, 0.0, 1.0);
  }
  return n;
}

}  // namespace

double variant_uniform(std::uint64_t seed, std::uint64_t variant, int index) {
  Stream s(seed, variant, 3 + static_cast<std::uint64_t>(index));
  return s.next();
}

std::vector<glm::dvec3> rock_points(const HullRockOptions& o) {
  const glm::dvec3 r = glm::max(o.radii, glm::dvec3(0.0));
  // Area-uniform on the ellipsoid: a uniform direction on the sphere mapped by the radii, accepted with
  // probability proportional to the surface element |(bc u_x, ac u_y, ab u_z)|.
  const double gmax = std::max({r.y * r.z, r.x * r.z, r.x * r.y});
  Stream uni(o.seed, o.variant, 1), noise(o.seed, o.variant, 2);
  std::vector<glm::dvec3> out;
  out.reserve(static_cast<std::size_t>(std::max(0, o.points)));
  for (int k = 0; k < o.points; ++k) {
    glm::dvec3 u;
    for (int attempt = 0;; ++attempt) {
      const double z = 2.0 * uni.next() - 1.0, phi = 2.0 * std::numbers::pi * uni.next();
      const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
      u = {s * std::cos(phi), s * std::sin(phi), z};
      const double g = glm::length(glm::dvec3(r.y * r.z * u.x, r.x * r.z * u.y, r.x * r.y * u.z));
      if (gmax <= 0.0 || attempt >= 64 || uni.next() * gmax <= g) break;
    }
    out.push_back(r * u + o.sigma * glm::dvec3(noise.gauss(), noise.gauss(), noise.gauss()));
  }
  return out;
}

Hull hull_rock(const HullRockOptions& o, const ExecContext* ctx) {
  Hull h = convex_hull(rock_points(o));
  if (o.subdivisions > 0) {
    for (int s = 0; s < o.subdivisions; ++s) subdivide(h, ctx);
  }
  if (o.displacement != 0.0 && o.wavelength > 0.0) {
    const auto n = vertex_normals(h);
    const std::uint64_t key = mix64(o.seed ^ mix64(o.variant + 0x51ED27u));
    for (std::size_t v = 0; v < h.vertices.size(); ++v) {
      poll(ctx, v);
      h.vertices[v] += n[v] * (o.displacement * value_noise(h.vertices[v] / o.wavelength, key));
    }
  }
  return h;
}

void append_hull(TriMesh& m, const Hull& h, const glm::dvec3& offset, const glm::dquat& rotation,
                 const TriMesh::Color& color, const ExecContext* ctx) {
  const auto normals = vertex_normals(h);
  std::vector<TriMesh::VertexHandle> vh(h.vertices.size());
  for (std::size_t v = 0; v < h.vertices.size(); ++v) {
    poll(ctx, v);
    const glm::dvec3 p = offset + rotation * h.vertices[v];
    const glm::dvec3 n = rotation * normals[v];
    vh[v] = m.add_vertex({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    m.set_normal(vh[v], {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
    m.set_color(vh[v], color);
    if (m.has_vertex_texcoords2D()) {
      // Spherical projection of the local position.
      const glm::dvec3 d = glm::normalize(h.vertices[v]);
      m.set_texcoord2D(vh[v], {static_cast<float>(0.5 + std::atan2(d.y, d.x) / (2.0 * std::numbers::pi)),
                               static_cast<float>(0.5 + std::asin(std::clamp(d.z, -1.0, 1.0)) / std::numbers::pi)});
    }
  }
  for (std::size_t k = 0; k < h.faces.size(); ++k) {
    poll(ctx, k);
    const auto& f = h.faces[k];
    m.add_face(vh[static_cast<std::size_t>(f[0])], vh[static_cast<std::size_t>(f[1])],
               vh[static_cast<std::size_t>(f[2])]);
  }
}

void append_hull_rock(TriMesh& m, const HullRockOptions& o, const glm::dvec3& offset, const glm::dquat& rotation,
                      const TriMesh::Color& color, const ExecContext* ctx) {
  append_hull(m, hull_rock(o, ctx), offset, rotation, color, ctx);
}

}  // namespace orogen::rocks
