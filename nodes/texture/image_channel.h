#pragma once
// One channel of a multi-channel image as a field, or a reduction (mean, sum, minimum, maximum) over all
// its channels at each sample.
#include <memory>
#include <string>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::texture {

enum class ChannelMode { Channel, Mean, Sum, Min, Max };

struct ImageChannelParams {
  ChannelMode mode = ChannelMode::Channel;
  std::string name;  // mode Channel: the channel's name; empty: use `index`
  int index = 0;     // mode Channel with no name: channel index, 0 .. channels - 1
};

// The field on the image's domain, in the image's units. Reductions are computed in double precision and
// rounded to float once. Throws NodeError for an unknown channel name, an index beyond the channels, or an
// image without channels.
std::shared_ptr<Heightfield> image_channel(const Image& img, const ImageChannelParams& p,
                                           const ExecContext* ctx = nullptr);

}  // namespace orogen::texture
