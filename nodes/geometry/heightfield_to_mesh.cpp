// HeightfieldToMesh: a terrain mesh from a heightfield, optionally decimated to an error bound in metres.
#include <limits>
#include <stdexcept>

#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "nodes/geometry/heightfield_mesh.h"

namespace orogen {

OROGEN_NODE(HeightfieldToMesh) {
  b.reach_global();
  b.category("geometry").description(
      "Turns a heightfield into a triangle mesh in world coordinates (x, y, z = height, metres, z up): one "
      "vertex per sample, two triangles per cell, vertex normals of the surface, and vertex colors from the "
      "optional image. Optionally decimated (OpenMesh decimater, quadric-ordered) so that every original "
      "sample stays within max_error metres vertically of the surface, and/or down to a target face count.");
  b.input("in", PortType::Heightfield).description("Heights in metres; at least 2 x 2 samples");
  b.input("colors", PortType::Image).optional().description(
      "Vertex colors, linear (gray, gray+alpha, RGB or RGBA), sampled at each vertex's world position; white "
      "when unconnected");
  b.output("out", PortType::Mesh).description("The terrain mesh");
  b.param_float("max_error", 0.0).range(0.0, 1e5).soft_range(0.0, 10.0).unit("m").description(
      "Decimate as long as every original sample stays within this vertical distance of the surface; 0 "
      "disables the error-bounded decimation");
  b.param_int("target_faces", 0).range(0, 1000000000).description(
      "Stop decimating at this many faces (still within max_error when that is set); 0: no target. With "
      "max_error 0 this alone drives the decimation");
  b.execute([](ExecContext& ctx) {
    const auto height = ctx.require<Heightfield>("in");
    const auto colors = ctx.input<Image>("colors");
    auto mesh = std::make_shared<Mesh>();
    try {
      *mesh = heightfield_grid_mesh(*height, colors.get());
    } catch (const std::invalid_argument& e) {
      throw NodeError(e.what());
    }
    ctx.check_cancelled();
    DecimationOptions options;
    options.max_error = ctx.param<double>("max_error");
    options.target_faces = static_cast<std::size_t>(ctx.param<std::int64_t>("target_faces"));
    if (options.max_error > 0.0 || options.target_faces > 0) {
      ctx.progress(0.2);
      options.progress = [&ctx](double f) { ctx.progress(0.2 + 0.8 * f); };
      options.should_stop = [&ctx] { return ctx.cancelled(); };
      decimate_heightfield_mesh(*mesh, options);
      ctx.check_cancelled();  // a stopped decimation is a cancelled run, not a result
    }
    ctx.set_output("out", std::move(mesh));
  });
}

}  // namespace orogen
