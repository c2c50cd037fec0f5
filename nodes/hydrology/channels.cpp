#include "nodes/hydrology/channels.h"

#include <bit>

namespace orogen::hydrology {

std::vector<std::uint8_t> channel_donor_counts(const FlowGrid& g, const D8Flow& f,
                                               std::span<const std::uint8_t> channel) {
  std::vector<std::uint8_t> count(f.receiver.size(), 0);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(count.size()); ++c) {
    if (!channel[c]) continue;
    int n = 0;
    for (unsigned m = f.donors[c]; m; m &= m - 1) n += channel[c + g.offset(std::countr_zero(m))] != 0;
    count[c] = static_cast<std::uint8_t>(n);
  }
  return count;
}

std::vector<std::int32_t> strahler_orders(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> order,
                                          std::span<const std::uint8_t> channel) {
  std::vector<std::int32_t> so(f.receiver.size(), 0);
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const std::int32_t c = *it;
    if (!channel[c]) continue;
    int best = 0, ties = 0;
    for (unsigned m = f.donors[c]; m; m &= m - 1) {
      const std::int32_t d = c + g.offset(std::countr_zero(m));
      if (!channel[d]) continue;
      if (so[d] > best) {
        best = so[d];
        ties = 1;
      } else if (so[d] == best) {
        ++ties;
      }
    }
    so[c] = best == 0 ? 1 : (ties >= 2 ? best + 1 : best);
  }
  return so;
}

std::vector<Reach> extract_reaches(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> order,
                                   std::span<const std::uint8_t> channel, std::span<const std::int32_t> strahler) {
  return channel_reaches(order, channel, f.receiver, channel_donor_counts(g, f, channel), strahler);
}

std::vector<Reach> channel_reaches(std::span<const std::int32_t> order, std::span<const std::uint8_t> channel,
                                   std::span<const std::int32_t> receiver, std::span<const std::uint8_t> donors,
                                   std::span<const std::int32_t> strahler) {
  std::vector<std::int32_t> reach_of_head(receiver.size(), -1);
  std::vector<Reach> reaches;
  for (const std::int32_t head : order) {
    if (!channel[head] || donors[head] == 1) continue;
    Reach r;
    r.order = strahler[head];
    r.cells.push_back(head);
    for (std::int32_t x = head;;) {
      const std::int32_t next = receiver[x];
      if (next == x) break;
      r.cells.push_back(next);
      if (donors[next] >= 2) {
        r.parent = reach_of_head[next];
        break;
      }
      x = next;
    }
    if (r.cells.size() < 2) continue;  // a confluence that is itself an outlet
    reach_of_head[head] = static_cast<std::int32_t>(reaches.size());
    reaches.push_back(std::move(r));
  }
  return reaches;
}

}  // namespace orogen::hydrology
