// ImageChannel: one channel of a multi-channel image (a month of a climate image, a splat layer), or the
// mean, sum, minimum or maximum over the channels, as a field.
#include <algorithm>
#include <cmath>
#include <limits>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen::texture {

OROGEN_NODE(ImageChannel) {
  b.reach_pointwise();
  b.category("texture").description(
      "A field from a multi-channel image: one channel chosen by name (e.g. 'jun', 'temperature_jan', "
      "'rock') or by index, or the mean, sum, minimum or maximum over all channels (e.g. the annual mean "
      "temperature or the yearly lit hours from the monthly images of the climate nodes).");
  b.input("in", PortType::Image).description("Image");
  b.output("out", PortType::Heightfield).description("The channel or the reduction, in the image's units").kind(OutputKind::Scalar);
  b.param_enum("mode", {"channel", "mean", "sum", "min", "max"}, "channel").description("One channel, or a reduction over all channels");
  b.param_string("name", "").description("Channel name (mode = channel); empty: use index");
  b.param_int("index", 0).range(0, 4096).description("Channel index 0.. (mode = channel, when name is empty)");
  b.execute([](ExecContext& ctx) {
    const auto img = ctx.require<Image>("in");
    const std::string mode = ctx.param<std::string>("mode");
    const std::string& name = ctx.param<std::string>("name");
    int channel = static_cast<int>(ctx.param<std::int64_t>("index"));
    if (mode == "channel" && !name.empty()) {
      const auto it = std::find(img->channel_names.begin(), img->channel_names.end(), name);
      if (it == img->channel_names.end()) {
        std::string known;
        for (const auto& n : img->channel_names) known += (known.empty() ? "" : ", ") + n;
        throw NodeError("no channel named '" + name + "' (channels: " + known + ")");
      }
      channel = static_cast<int>(it - img->channel_names.begin());
    }
    if (mode == "channel" && channel >= img->channels)
      throw NodeError("channel index " + std::to_string(channel) + " beyond the image's " + std::to_string(img->channels) + " channels");
    if (img->channels < 1) throw NodeError("the image has no channels");
    auto out = std::make_shared<Heightfield>(img->domain);
    const int C = img->channels;
    for_each_row(&ctx, img->height(), [&](int j) {
      for (int i = 0; i < img->width(); ++i) {
        const float* px = img->pixel(i, j);
        double v;
        if (mode == "channel") {
          v = px[channel];
        } else if (mode == "min" || mode == "max") {
          v = px[0];
          for (int c = 1; c < C; ++c) v = mode == "min" ? std::min<double>(v, px[c]) : std::max<double>(v, px[c]);
        } else {
          v = 0.0;
          for (int c = 0; c < C; ++c) v += px[c];
          if (mode == "mean") v /= C;
        }
        out->at(i, j) = static_cast<float>(v);
      }
    });
    ctx.set_output("out", out);
  });
}

}  // namespace orogen::texture
