// WriteWeightmaps: splat weights as one 8-bit grayscale PNG per layer (Unreal Engine's landscape paint layers)
// and a JSON list of them.
#include <nlohmann/json.hpp>

#include "graph/checked_file.h"
#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/image_file.h"
#include "nodes/io/weightmaps.h"
#include "nodes/io/write_output.h"

namespace orogen {

OROGEN_NODE(WriteWeightmaps) {
  b.reach_global();
  b.category("io").writes_files().description(
      "Writes splat weights (SplatWeights' out, one channel per layer) as one 8-bit grayscale PNG per layer, the "
      "weightmaps Unreal Engine's landscape imports into its paint layers, and a JSON list of them at `path`. "
      "The weights are normalized per sample and rounded by largest remainder, so the maps sum to exactly 255 at "
      "every sample (what weight-blended layers expect) and each is within one code of its exact share; samples "
      "with no weight stay 0 in every map. Maps are linear (data, not color), north row first, and share the "
      "heightfield's samples. Files: <stem>_<layer>.png beside `path`, the layer from the channel's name.");
  b.input("in", PortType::Image).description("Weights, one channel per layer, >= 0 (any sum)");
  b.param_path("path", "weightmaps/layers.json")
      .output_file()
      .extensions({".json"})
      .description(
          "The list of weightmaps (layer name and file, in channel order), relative to the output directory; "
          "the PNGs are written beside it as <stem>_<layer>.png");
  // One layer of codes at a time besides the input (measured like WriteImage's encoder).
  b.extra_bytes([](const CostQuery& q) { return input_bytes(q, "in") + 224 * 1024; });
  b.execute([](ExecContext& ctx) {
    const auto weights = ctx.require<Image>("in");
    if (weights->channels < 1) throw NodeError("in: the image has no channel (no layer to write)");
    std::vector<Image> layers;
    try {
      layers = weightmap_layers(*weights);
    } catch (const std::invalid_argument& e) {
      throw NodeError(std::string("in: ") + e.what());
    }
    const auto names = weightmap_layer_names(*weights);
    const std::filesystem::path list = ctx.output_path("path");  // NodeError if the path rule refuses it
    nlohmann::json doc = {{"format", "orogen-weightmaps"},    {"version", 1},   {"width", weights->width()},
                          {"height", weights->height()},      {"bit_depth", 8}, {"sum", 255},
                          {"layers", nlohmann::json::array()}};
    std::vector<NodeOutputFile> files;
    for (std::size_t c = 0; c < layers.size(); ++c) {
      const std::string file = list.stem().string() + "_" + names[c] + ".png";
      doc["layers"].push_back({{"name", names[c]}, {"file", file}});
      files.push_back(
          {list.parent_path() / file, [&, c](const std::filesystem::path& temporary, const WriteProgress& progress) {
             ImageWriteOptions options;
             options.format = ImageFormat::Png8;
             options.srgb = false;  // weights are data
             options.compression_level = 6;
             options.progress = progress;
             write_image_file(layers[c], temporary, options);
           }});
    }
    // The list names the maps: renamed after them, so it never lists a missing file.
    const std::string text = doc.dump(2) + "\n";
    files.push_back({list, [&](const std::filesystem::path& temporary, const WriteProgress&) {
                       write_text_file(temporary, text);  // checked and synced: a full disk fails the node
                     }});
    write_node_files(ctx, files);
  });
}

}  // namespace orogen
