#include "nodes/hydrology/tile_breach.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "nodes/hydrology/breach_rule.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_ring.h"

namespace orogen::hydrology {

TileBreach::TileBreach(std::span<const float> ground, std::span<const float> surface, const TileRect& rect,
                       glm::ivec2 domain_size, double dx, double dy, bool epsilon)
    : epsilon_(epsilon), minima_(rect) {
  const TileRect ringed = ringed_rect(rect, domain_size);
  const std::size_t ringed_cells = static_cast<std::size_t>(ringed.size.x) * static_cast<std::size_t>(ringed.size.y);
  if (ground.size() != ringed_cells || surface.size() != ringed_cells)
    throw std::invalid_argument("TileBreach: heights do not match the tile with its ring");
  // The ringed tile as a grid of its own: its border cells (outlets) are the ring and the domain's border, and every
  // neighbour of a tile cell off the domain's border is in it, so receivers and pits are the whole domain's.
  const FlowGrid g(ringed.size.x, ringed.size.y, dx, dy);
  const D8Flow flow = d8_flow(g, surface);
  ground_ = without_ring<float>(ground, rect, domain_size);
  pit_ = without_ring<std::uint8_t>(breach_pits(g, ground), rect, domain_size);
  const glm::ivec2 at = rect.first - ringed.first;
  const int w = rect.size.x, h = rect.size.y;
  receiver_.assign(ground_.size(), -1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::int32_t rc = g.index(i + at.x, j + at.y), r = flow.receiver[static_cast<std::size_t>(rc)];
      const int ri = r % g.nx - at.x, rj = r / g.nx - at.y;
      if (r != rc && ri >= 0 && rj >= 0 && ri < w && rj < h)
        receiver_[static_cast<std::size_t>(j * w + i)] = rj * w + ri;
    }
  arrived_.assign(ground_.size(), std::numeric_limits<float>::infinity());
  for (const std::int32_t c : upstream_first(receiver_, "TileBreach")) {
    const std::int32_t r = receiver_[static_cast<std::size_t>(c)];
    if (r < 0) continue;
    const auto k = static_cast<std::size_t>(c);
    const float passed = breach_passed(ground_[k], arrived_[k], pit_[k] != 0, epsilon_);
    float& next = arrived_[static_cast<std::size_t>(r)];
    if (passed < next) next = passed;
  }
}

void TileBreach::carry(std::int32_t c) {
  for (std::int32_t r = receiver_[static_cast<std::size_t>(c)]; r >= 0;
       c = r, r = receiver_[static_cast<std::size_t>(c)]) {
    const auto k = static_cast<std::size_t>(c);
    const float passed = breach_passed(ground_[k], arrived_[k], pit_[k] != 0, epsilon_);
    float& next = arrived_[static_cast<std::size_t>(r)];
    if (!(passed < next)) return;  // what follows already has as low a value
    next = passed;
  }
}

void TileBreach::answer(std::string_view bytes) {
  for (const std::int32_t c : minima_.answer(bytes, arrived_)) carry(c);
}

std::vector<float> TileBreach::carved() const {
  std::vector<float> out(ground_.size());
  for (std::size_t c = 0; c < out.size(); ++c) out[c] = std::min(ground_[c], arrived_[c]);
  return out;
}

}  // namespace orogen::hydrology
