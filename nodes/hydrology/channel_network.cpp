#include "nodes/hydrology/channel_network.h"

#include <stdexcept>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

ChannelNetwork channel_network(const std::vector<std::int64_t>& samples, const std::vector<std::uint8_t>& directions,
                               glm::ivec2 size, const std::string& who) {
  const std::int64_t domain_samples = static_cast<std::int64_t>(size.x) * size.y;
  auto id_of = [&](std::int64_t sample) {
    const auto it = std::lower_bound(samples.begin(), samples.end(), sample);
    return it != samples.end() && *it == sample ? static_cast<std::int32_t>(it - samples.begin()) : -1;
  };
  const auto n = static_cast<std::int32_t>(samples.size());
  ChannelNetwork net;
  auto& receiver = net.receiver;
  auto& donors = net.donors;
  receiver.resize(samples.size());
  donors.resize(samples.size());
  for (std::int32_t c = 0; c < n; ++c) {
    const std::int64_t sample = samples[static_cast<std::size_t>(c)];
    const std::uint8_t direction = directions[static_cast<std::size_t>(c)];
    if (sample < 0 || sample >= domain_samples || (c > 0 && samples[static_cast<std::size_t>(c - 1)] == sample))
      throw std::invalid_argument(who + ": a channel cell outside the domain or sent twice");
    receiver[static_cast<std::size_t>(c)] = c;
    if (direction == kNoDirection) continue;
    if (direction > 7) throw std::invalid_argument(who + ": not a D8 direction");
    const int i = static_cast<int>(sample % size.x) + kDi[direction];
    const int j = static_cast<int>(sample / size.x) + kDj[direction];
    const std::int32_t r =
        i < 0 || j < 0 || i >= size.x || j >= size.y ? -1 : id_of(static_cast<std::int64_t>(j) * size.x + i);
    if (r < 0) throw std::invalid_argument(who + ": a channel cell drains off the channel network");
    receiver[static_cast<std::size_t>(c)] = r;
    donors[static_cast<std::size_t>(r)].emplace_back(opposite(direction), c);
  }
  std::vector<std::int32_t> stack;
  net.order.reserve(samples.size());
  for (auto& d : donors) std::sort(d.begin(), d.end());
  for (std::int32_t c = 0; c < n; ++c) {
    if (receiver[static_cast<std::size_t>(c)] != c) continue;
    stack.push_back(c);
    while (!stack.empty()) {
      const std::int32_t x = stack.back();
      stack.pop_back();
      net.order.push_back(x);
      for (const auto& [k, d] : donors[static_cast<std::size_t>(x)]) stack.push_back(d);
    }
  }
  if (net.order.size() != samples.size()) throw std::invalid_argument(who + ": the channel network loops");
  return net;
}

}  // namespace orogen::hydrology
