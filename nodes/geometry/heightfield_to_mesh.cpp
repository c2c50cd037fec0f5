// HeightfieldToMesh: a terrain mesh from a heightfield, the full grid or a TIN within an error bound in metres.
#include <limits>
#include <stdexcept>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/geometry/heightfield_mesh.h"

namespace orogen {

OROGEN_NODE(HeightfieldToMesh) {
  b.distribution(Distribution::Gathered);
  b.reach_global();
  b.category("geometry")
      .version(2)
      .description(
          "Turns a heightfield into a triangle mesh in world coordinates (x, y, z = height, metres, z up): one "
          "vertex per sample, two triangles per cell, vertex normals of the surface, and vertex colors from the "
          "optional image. With max_error or target_faces, a triangulated irregular network instead: greedy insertion "
          "of the worst sample into a Delaunay triangulation (Garland & Heckbert 1995, Fast polygonal approximation "
          "of terrains and height fields), then half-edge collapses (Hoppe 1996, Progressive meshes) that keep every "
          "sample within max_error metres vertically of the surface.");
  b.input("in", PortType::Heightfield).description("Heights in metres; at least 2 x 2 samples");
  b.input("colors", PortType::Image)
      .optional()
      .description(
          "Vertex colors, linear (gray, gray+alpha, RGB or RGBA), sampled at each vertex's world position; white "
          "when unconnected");
  b.output("out", PortType::Mesh).description("The terrain mesh");
  b.param_float("max_error", 0.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 10.0)
      .unit(Unit::Metre)
      .description(
          "Every sample stays within this vertical distance of the surface (exact, checked at every sample); 0 "
          "disables the error bound");
  b.param_int("target_faces", 0)
      .unit(Unit::Count)
      .range(0, 1000000000)
      .description(
          "Refine to about this many faces, never more unless max_error needs them (the tighter of the two wins); "
          "0: no target. With max_error 0 this alone decides the size");
  // Working memory beyond the outputs, 256 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 256); });
  b.execute([](ExecContext& ctx) {
    const auto height = ctx.require<Heightfield>("in");
    const auto colors = secondary_input<Image>(ctx, "colors", height->domain);
    TinOptions options;
    options.max_error = ctx.param<double>("max_error");
    options.target_faces = static_cast<std::size_t>(ctx.param<std::int64_t>("target_faces"));
    options.progress = [&ctx](double f) { ctx.progress(f); };
    options.should_stop = [&ctx] { return ctx.cancelled(); };
    auto mesh = std::make_shared<Mesh>();
    try {
      *mesh = heightfield_mesh(*height, colors.get(), options);
    } catch (const std::invalid_argument& e) {
      throw NodeError(e.what());
    }
    ctx.check_cancelled();  // a stopped refinement is a cancelled run, not a result
    ctx.set_output("out", std::move(mesh));
  });
}

}  // namespace orogen
