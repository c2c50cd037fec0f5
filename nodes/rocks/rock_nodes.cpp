// Rock nodes: HullRock (one convex-hull rock) and RockSet (K variants for scattering). Thin adapters over
// hull_rock.h.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/rocks/hull_rock.h"
#include "nodes/rocks/rock_set.h"

namespace orogen {
namespace {

const char* kRockSource =
    "S. Ekman et al. (2016), SeamScape (Chalmers bachelor thesis) §3.8: N points uniformly on an ellipsoid (semi-axes "
    "a, b, c), each "
    "moved by spherical Gaussian noise of standard deviation sigma, and their 3D convex hull (incremental "
    "insertion, Clarkson & Shor 1989, checked, with CGAL's exact convex_hull_3 for near-degenerate sets and "
    "above 512 points; hull vertices are input points) with outward faces and smooth normals";

void declare_rock_params(NodeBuilder& b) {
  b.param_int("points", 20)
      .unit(Unit::Count)
      .range(4, 10000)
      .soft_range(8, 200)
      .description("Points sampled on the ellipsoid (N)");
  b.param_vec3("radii", {1.0, 0.7, 0.5})
      .range(0.001, 1000.0)
      .unit(Unit::Metre)
      .description("Ellipsoid semi-axes a, b, c along x, y, z");
  b.param_float("sigma", 0.05)
      .range(0.0, 1000.0)
      .soft_range(0.0, 0.5)
      .unit(Unit::Metre)
      .description("Standard deviation of the Gaussian noise added to each point per axis");
  b.param_int("subdivisions", 0)
      .unit(Unit::Count)
      .range(0, 5)
      .description("Refinement levels: each splits every triangle in four (x4 faces) before the displacement");
  b.param_float("displacement", 0.0)
      .range(0.0, 1000.0)
      .soft_range(0.0, 0.3)
      .unit(Unit::Metre)
      .description("Amplitude of the 3D value-noise displacement along the normals (0: the faceted hull)");
  b.param_float("wavelength", 0.5)
      .range(0.001, 1000.0)
      .soft_range(0.05, 5.0)
      .unit(Unit::Metre)
      .description("Feature size of the displacement noise");
  b.param_color("color", {0.35f, 0.33f, 0.3f, 1.0f}).description("Vertex color (linear RGB)");
  b.param_seed("seed", 0).description("Key of the random points (and of each variant's radii)");
}

// Bytes of one rock's mesh at most: a hull of N points has at most 2N - 4 triangles (all points on it, sigma 0), each
// refinement level 4 times as many, and the mesh with its normals, colors and texture coordinates, the refined hull
// and its edge map hold about 160 bytes a triangle (measured: 794 MB peak for one rock of 5 million triangles); at
// least 8 KB a rock (tests/test_peak_memory.cpp).
double rock_bytes(const ParamView& p) {
  const double triangles = (2.0 * static_cast<double>(p.get<std::int64_t>("points")) - 4.0) *
                           std::pow(4.0, static_cast<double>(p.get<std::int64_t>("subdivisions")));
  return std::max(8192.0, 160.0 * triangles);
}

rocks::HullRockOptions rock_options(const ExecContext& ctx) {
  rocks::HullRockOptions o;
  o.points = static_cast<int>(ctx.param<std::int64_t>("points"));
  o.radii = ctx.param<glm::dvec3>("radii");
  o.sigma = ctx.param<double>("sigma");
  o.subdivisions = static_cast<int>(ctx.param<std::int64_t>("subdivisions"));
  o.displacement = ctx.param<double>("displacement");
  o.wavelength = ctx.param<double>("wavelength");
  o.seed = ctx.param<std::uint64_t>("seed");
  return o;
}

TriMesh::Color color_of(const ExecContext& ctx) {
  const glm::vec4 c = ctx.param<glm::vec4>("color");
  return {c.r, c.g, c.b, 1.0f};
}

}  // namespace

OROGEN_NODE(HullRock) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("rocks").description(std::string("A low-polygon rock centered on the origin. ") + kRockSource +
                                  ". Optionally subdivided and displaced by 3D noise in world units for a less "
                                  "faceted look; the surface stays closed.");
  b.output("out", PortType::Mesh).description("The rock, metres, z up");
  declare_rock_params(b);
  b.extra_bytes([](const CostQuery& q) { return per_item_bytes(1.0, rock_bytes(q.params)); });
  b.execute([](ExecContext& ctx) {
    auto mesh = std::make_shared<Mesh>();
    mesh->mesh.request_vertex_texcoords2D();
    try {
      rocks::append_hull_rock(mesh->mesh, rock_options(ctx), glm::dvec3(0.0), glm::dquat(1, 0, 0, 0), color_of(ctx),
                              &ctx);
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("no rock: ") + e.what() + " (raise sigma or the radii)");
    }
    mesh->mesh.update_face_normals();
    ctx.set_output("out", std::move(mesh));
  });
}

OROGEN_NODE(RockSet) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("rocks").description(std::string("K rock variants at once, for scattering: each a hull rock (") +
                                  kRockSource +
                                  ") with its own random points and radii scaled by up to +-variation, laid out "
                                  "in a row along x; the placements output marks each variant's center with "
                                  "class_id = its index.");
  b.output("out", PortType::Mesh).description("All variants in one mesh, side by side along x (m)");
  b.output("placements", PortType::Points)
      .description("Center of each variant, class_id = variant index, scale = its radii (m)");
  b.param_int("count", 8).unit(Unit::Count).range(1, 1000).soft_range(1, 32).description("Number of variants (K)");
  b.param_float("variation", 0.3)
      .range(0.0, 0.95)
      .unit(Unit::Factor)
      .description("Each variant's radii are multiplied by independent factors in 1 +- variation");
  b.param_float("spacing", 0.5)
      .range(0.0, 1e4)
      .soft_range(0.0, 5.0)
      .unit(Unit::Metre)
      .description("Gap between neighboring variants in the row");
  declare_rock_params(b);
  b.extra_bytes([](const CostQuery& q) {
    return per_item_bytes(static_cast<double>(q.params.get<std::int64_t>("count")), rock_bytes(q.params));
  });
  b.execute([](ExecContext& ctx) {
    rocks::RockSetParams p;
    p.rock = rock_options(ctx);
    p.count = static_cast<int>(ctx.param<std::int64_t>("count"));
    p.variation = ctx.param<double>("variation");
    p.spacing = ctx.param<double>("spacing");
    p.color = color_of(ctx);
    auto mesh = std::make_shared<Mesh>();
    mesh->mesh.request_vertex_texcoords2D();
    auto placements = std::make_shared<Points>();
    try {
      rocks::append_rock_set(mesh->mesh, *placements, p, &ctx);
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("no ") + e.what() + " (raise sigma or the radii)");
    }
    mesh->mesh.update_face_normals();
    ctx.set_output("out", std::move(mesh));
    ctx.set_output("placements", std::move(placements));
  });
}

}  // namespace orogen
