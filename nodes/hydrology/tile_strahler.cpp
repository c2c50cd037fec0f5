#include "nodes/hydrology/tile_strahler.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/tile_accumulation.h"

namespace orogen::hydrology {
namespace {

constexpr const char* kWhat = "tile Strahler orders";

// The donors of two disjoint sets together.
DonorSummary merged(DonorSummary a, DonorSummary b) {
  if (a.order != b.order) return a.order > b.order ? a : b;
  return {a.order, a.count + b.count};
}

bool operator!=(DonorSummary a, DonorSummary b) { return a.order != b.order || a.count != b.count; }

struct Message {
  TileRect rect;
  bool changed = false;
  std::vector<DonorSummary> own;
};

Message decode(std::string_view in, glm::ivec2 domain_size) {
  Message m;
  m.rect = take_tile_rect(in, domain_size, kWhat);
  m.changed = bytes::take<std::uint8_t>(in, kWhat) != 0;
  m.own = bytes::take_vector<DonorSummary>(in, kWhat);
  if (!in.empty()) throw std::invalid_argument("tile Strahler orders: trailing bytes");
  if (m.own.size() != perimeter_cells(m.rect.size).size())
    throw std::invalid_argument("tile Strahler orders: one summary per perimeter cell expected");
  for (const DonorSummary& s : m.own)
    if (s.order < 0 || s.count < 0) throw std::invalid_argument("tile Strahler orders: a negative summary");
  return m;
}

}  // namespace

TileStrahler::TileStrahler(const std::vector<std::int32_t>& receiver, const std::vector<std::uint8_t>& channel,
                           const TileRect& rect, glm::ivec2 domain_size)
    : rect_(rect), domain_(domain_size) {
  const std::size_t n = static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y);
  if (rect.size.x < 1 || rect.size.y < 1 || receiver.size() != n || channel.size() != n)
    throw std::invalid_argument("TileStrahler: receivers and channel cells must cover the tile");
  for (std::size_t c = 0; c < n; ++c)
    if (channel[c]) cells_.push_back(static_cast<std::int32_t>(c));
  // Off the network a cell has no channel donor (a channel cell's receiver drains more cells, so it is one too), so
  // the orders need the channel's own edges alone.
  receiver_.assign(cells_.size(), -1);
  for (std::size_t u = 0; u < cells_.size(); ++u) {
    const std::int32_t r = receiver[static_cast<std::size_t>(cells_[u])];
    if (r < -1 || r >= static_cast<std::int32_t>(n))
      throw std::invalid_argument("tile Strahler orders: a receiver outside the tile");
    if (r >= 0 && channel[static_cast<std::size_t>(r)])
      receiver_[u] = static_cast<std::int32_t>(std::lower_bound(cells_.begin(), cells_.end(), r) - cells_.begin());
  }
  upstream_first_ = upstream_first(receiver_, "tile Strahler orders");
  const std::size_t perimeter_count = perimeter_cells(rect.size).size();
  own_.resize(perimeter_count);
  external_.resize(perimeter_count);
  sent_.resize(perimeter_count);
  compute();
}

void TileStrahler::compute() {
  std::vector<DonorSummary> donors(cells_.size());  // this tile's donors of each channel cell, upstream ones first
  order_.assign(cells_.size(), 0);
  for (const std::int32_t u : upstream_first_) {
    const auto k = static_cast<std::size_t>(u);
    const std::int32_t c = cells_[k];
    DonorSummary all = donors[k];
    if (const std::int32_t p = perimeter_position(rect_.size, c % rect_.size.x, c / rect_.size.x); p >= 0) {
      own_[static_cast<std::size_t>(p)] = donors[k];
      all = merged(all, external_[static_cast<std::size_t>(p)]);
    }
    // As strahler_orders: 1 at a source, the highest donor order, plus one where two or more donors have it.
    order_[k] = all.order == 0 ? 1 : all.count >= 2 ? all.order + 1 : all.order;
    if (const std::int32_t r = receiver_[k]; r >= 0)
      donors[static_cast<std::size_t>(r)] = merged(donors[static_cast<std::size_t>(r)], {order_[k], 1});
  }
}

std::string TileStrahler::message() {
  bool changed = first_;
  for (std::size_t k = 0; k < own_.size(); ++k) changed = changed || own_[k] != sent_[k];
  sent_ = own_;
  first_ = false;
  std::string out;
  put_tile_rect(out, rect_);
  bytes::put(out, static_cast<std::uint8_t>(changed));
  bytes::put_vector(out, own_);
  return out;
}

void TileStrahler::answer(std::string_view bytes) {
  auto external = bytes::take_vector<DonorSummary>(bytes, kWhat);
  if (!bytes.empty()) throw std::invalid_argument("tile Strahler orders: trailing bytes");
  if (external.size() != external_.size())
    throw std::invalid_argument("tile Strahler orders: one summary per perimeter cell expected");
  external_ = std::move(external);
  compute();
}

std::vector<std::uint8_t> channel_cells(const std::vector<std::int64_t>& counts, double cell_area, double threshold) {
  std::vector<std::uint8_t> channel(counts.size());
  for (std::size_t c = 0; c < counts.size(); ++c) channel[c] = static_cast<double>(counts[c]) * cell_area >= threshold;
  return channel;
}

std::vector<std::string> solve_strahler_perimeters(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<Message> tiles;
  tiles.reserve(messages.size());
  for (std::string_view m : messages) tiles.push_back(decode(m, domain_size));
  // Per shared sample: the tiles' summaries there, as (tile, perimeter index).
  struct Holder {
    std::int32_t tile, k;
  };
  std::unordered_map<std::int64_t, std::vector<Holder>> holders;
  std::vector<std::vector<std::int64_t>> sample(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const auto cells = perimeter_cells(tiles[t].rect.size);
    sample[t].reserve(cells.size());
    for (std::size_t k = 0; k < cells.size(); ++k) {
      sample[t].push_back(domain_sample(tiles[t].rect, domain_size, cells[k]));
      holders[sample[t].back()].push_back({static_cast<std::int32_t>(t), static_cast<std::int32_t>(k)});
    }
  }
  std::vector<std::string> answers(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    std::vector<DonorSummary> external(tiles[t].own.size());
    for (std::size_t k = 0; k < external.size(); ++k)
      for (const Holder& h : holders.at(sample[t][k]))
        if (h.tile != static_cast<std::int32_t>(t))
          external[k] = merged(external[k], tiles[static_cast<std::size_t>(h.tile)].own[static_cast<std::size_t>(h.k)]);
    bytes::put_vector(answers[t], external);
  }
  return answers;
}

bool strahler_changed(std::span<const std::string_view> messages) {
  for (std::string_view in : messages) {
    for (int k = 0; k < 4; ++k) bytes::take<int>(in, kWhat);  // the tile's rectangle
    if (bytes::take<std::uint8_t>(in, kWhat)) return true;
  }
  return false;
}

}  // namespace orogen::hydrology
