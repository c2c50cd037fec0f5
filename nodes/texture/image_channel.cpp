// ImageChannel: one channel of a multi-channel image (a month of a climate image, a splat layer), or the
// mean, sum, minimum or maximum over the channels, as a field.
#include "nodes/texture/image_channel.h"

#include <algorithm>
#include <string>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen::texture {

std::shared_ptr<Heightfield> image_channel(const Image& img, const ImageChannelParams& p, const ExecContext* ctx) {
  int channel = p.index;
  if (p.mode == ChannelMode::Channel && !p.name.empty()) {
    const auto it = std::find(img.channel_names.begin(), img.channel_names.end(), p.name);
    if (it == img.channel_names.end()) {
      std::string known;
      for (const auto& n : img.channel_names) known += (known.empty() ? "" : ", ") + n;
      throw NodeError("no channel named '" + p.name + "' (channels: " + known + ")");
    }
    channel = static_cast<int>(it - img.channel_names.begin());
  }
  if (p.mode == ChannelMode::Channel && (channel < 0 || channel >= img.channels))
    throw NodeError("channel index " + std::to_string(channel) + " beyond the image's " + std::to_string(img.channels) +
                    " channels");
  if (img.channels < 1) throw NodeError("the image has no channels");
  auto out = std::make_shared<Heightfield>(img.domain);
  const int C = img.channels;
  for_each_row(ctx, img.height(), [&](int j) {
    for (int i = 0; i < img.width(); ++i) {
      const float* px = img.pixel(i, j);
      double v = 0.0;
      switch (p.mode) {
        case ChannelMode::Channel:
          v = px[channel];
          break;
        case ChannelMode::Min:
          v = px[0];
          for (int c = 1; c < C; ++c) v = std::min<double>(v, px[c]);
          break;
        case ChannelMode::Max:
          v = px[0];
          for (int c = 1; c < C; ++c) v = std::max<double>(v, px[c]);
          break;
        case ChannelMode::Sum:
        case ChannelMode::Mean:
          for (int c = 0; c < C; ++c) v += px[c];
          if (p.mode == ChannelMode::Mean) v /= C;
          break;
      }
      out->at(i, j) = static_cast<float>(v);
    }
  });
  return out;
}

OROGEN_NODE(ImageChannel) {
  b.reach_pointwise();
  b.category("texture").description(
      "A field from a multi-channel image: one channel chosen by name (e.g. 'jun', 'temperature_jan', "
      "'rock') or by index, or the mean, sum, minimum or maximum over all channels (e.g. the annual mean "
      "temperature or the yearly lit hours from the monthly images of the climate nodes).");
  b.input("in", PortType::Image).description("Image");
  b.output("out", PortType::Heightfield)
      .description("The channel or the reduction, in the image's units")
      .kind(OutputKind::Scalar);
  b.param_enum("mode", {"channel", "mean", "sum", "min", "max"}, "channel")
      .description("One channel, or a reduction over all channels");
  b.param_string("name", "").description("Channel name (mode = channel); empty: use index");
  b.param_int("index", 0)
      .unit(Unit::Count)
      .range(0, 4096)
      .description("Channel index 0.. (mode = channel, when name is empty)");
  b.execute([](ExecContext& ctx) {
    static constexpr ChannelMode kModes[] = {ChannelMode::Channel, ChannelMode::Mean, ChannelMode::Sum,
                                             ChannelMode::Min, ChannelMode::Max};
    ImageChannelParams p;
    p.mode = kModes[ctx.enum_index("mode")];
    p.name = ctx.param<std::string>("name");
    p.index = static_cast<int>(ctx.param<std::int64_t>("index"));
    ctx.set_output("out", image_channel(*ctx.require<Image>("in"), p, &ctx));
  });
}

}  // namespace orogen::texture
