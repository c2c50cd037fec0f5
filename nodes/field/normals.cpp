#include "nodes/field/normals.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen {

std::shared_ptr<Image> normal_map(const Heightfield& z, double height_scale, bool unsigned_encoding,
                                  const ExecContext* ctx) {
  const double scale = unsigned_encoding ? 0.5 : 1.0, bias = unsigned_encoding ? 0.5 : 0.0;
  auto out = std::make_shared<Image>(z.domain, 3);
  out->channel_names = {"X", "Y", "Z"};
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double p, q;
      gradient_at(z, i, j, p, q);
      p *= height_scale;
      q *= height_scale;
      const double inv = 1.0 / std::sqrt(p * p + q * q + 1.0);
      float* px = out->pixel(i, j);
      px[0] = static_cast<float>(-p * inv * scale + bias);
      px[1] = static_cast<float>(-q * inv * scale + bias);
      px[2] = static_cast<float>(inv * scale + bias);
    }
  });
  return out;
}

OROGEN_NODE(Normals) {
  b.reach_local(0.0, 1);  // central differences
  b.category("field").description(
      "Unit surface normals as a 3-channel image (X east, Y north, Z up), from the gradient in world units. "
      "The unsigned encoding (n * 0.5 + 0.5) is the usual normal-map texture for 8/16-bit image files.");
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Image).description("Normals, channels X, Y, Z in [-1, 1] (or 0..1 unsigned)");
  b.param_float("z_factor", 1.0)
      .unit(Unit::Factor)
      .range(0.0, 1e3)
      .soft_range(0.0, 10.0)
      .description("Relief exaggeration");
  b.param_enum("encoding", {"signed", "unsigned"}, "signed")
      .description("signed: components in -1..1; unsigned: n * 0.5 + 0.5");
  b.execute([](ExecContext& ctx) {
    ctx.set_output("out", normal_map(*ctx.require<Heightfield>("in"), ctx.param<double>("z_factor"),
                                     ctx.param<std::string>("encoding") == "unsigned", &ctx));
  });
}

}  // namespace orogen
