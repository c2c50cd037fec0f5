// WriteControlMap: splat weights as a Terrain3D (Godot 4) control map, a bit-packed 32-bit EXR.
#include "graph/checked_file.h"
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/control_map.h"
#include "nodes/io/image_file.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteControlMap) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes splat weights (SplatWeights' out, one channel per layer) as the control map of Terrain3D, the main "
      "terrain system of Godot 4 (its format since 0.9): a one-channel 32-bit EXR whose every sample holds, bit "
      "for bit, a 32-bit word with a base texture id (the layer of largest weight), an overlay texture id (the "
      "second largest) and the overlay's blend over the base (its share of the two, 0..255), plus the navigation "
      "and autoshader flags. Layer c is Terrain3D's texture c, so list the textures in the layers' order; at most "
      "32 layers. Rows north first, on the heightfield's samples, like the EXR heights Terrain3D imports beside "
      "it.");
  b.input("in", PortType::Image).description("Weights, one channel per layer, >= 0 (any sum)");
  b.param_path("path", "godot/control.exr")
      .output_file()
      .extensions({".exr"})
      .description("Output file, relative to the output directory (EXR: the words must keep their bits)");
  b.param_bool("navigation", false)
      .description("Mark every sample navigable (Terrain3D's navigation bit, used when it bakes a navigation mesh)");
  b.param_bool("autoshader", false)
      .description("Let Terrain3D's autoshader texture every sample by slope instead of the painted ids");
  // The words and their float image (4 bytes a sample each) besides the input, and the EXR encoder's buffers
  // (measured like WriteImage's).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 8.0) + 224 * 1024; });
  b.execute([](ExecContext& ctx) {
    const auto weights = ctx.require<Image>("in");
    if (weights->channels < 1) throw NodeError("in: the image has no channel (no layer to write)");
    ControlMapFlags flags;
    flags.navigation = ctx.param<bool>("navigation");
    flags.autoshader = ctx.param<bool>("autoshader");
    std::vector<std::uint32_t> words;
    try {
      words = control_words(*weights, flags);
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("in: ") + e.what());
    }
    const Image image = control_map_image(weights->domain, words);
    words = {};
    const std::filesystem::path target = ctx.output_path("path");  // NodeError if the path rule refuses it
    write_node_files(ctx, {{target, [&](const std::filesystem::path& temporary, const WriteProgress& progress) {
                              ImageWriteOptions options;
                              options.format = ImageFormat::Exr;
                              options.progress = progress;
                              write_image_file(image, temporary, options);
                            }}});
  });
}

}  // namespace orogen
