#pragma once
// The channel network joined from the channel cells the tiles send (rivers and drainage metrics across tiles): the
// whole domain's D8 network and stack order restricted to the channel cells. Non-channel cells have no channel cell
// upstream, so leaving them out keeps the order.
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::hydrology {

struct ChannelNetwork {
  std::vector<std::int32_t> receiver;  // the cell itself at an outlet
  // Donors by neighbor index k as seen from the receiver (D8Flow::donors' bits), sorted.
  std::vector<std::vector<std::pair<int, std::int32_t>>> donors;
  // stack_order restricted to the channel: roots in row-major order, donors pushed in neighbor order.
  std::vector<std::int32_t> order;
};

// `samples`: the cells' row-major indices in a domain of `size`, sorted; `directions`: their D8 directions. Throws
// std::invalid_argument, messages starting with `who`, on a cell outside the domain or sent twice, a bad direction, a
// cell draining off the channel cells, or a loop.
ChannelNetwork channel_network(const std::vector<std::int64_t>& samples, const std::vector<std::uint8_t>& directions,
                               glm::ivec2 size, const std::string& who);

// Sorts `cells` (each with `sample` and `direction`) by sample and joins them.
template <class Cell>
ChannelNetwork sorted_channel_network(std::vector<Cell>& cells, glm::ivec2 size, const std::string& who) {
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return a.sample < b.sample; });
  std::vector<std::int64_t> samples;
  std::vector<std::uint8_t> directions;
  samples.reserve(cells.size()), directions.reserve(cells.size());
  for (const Cell& c : cells) {
    samples.push_back(static_cast<std::int64_t>(c.sample));
    directions.push_back(static_cast<std::uint8_t>(c.direction));
  }
  return channel_network(samples, directions, size, who);
}

}  // namespace orogen::hydrology
