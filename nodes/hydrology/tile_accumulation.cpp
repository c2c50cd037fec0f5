#include "nodes/hydrology/tile_accumulation.h"

#include <bit>
#include <stdexcept>
#include <unordered_map>

#include <emmintrin.h>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {
namespace {

template <class T>
T take(std::string_view& in) {
  return bytes::take<T>(in, "tile accumulation");
}

// `weight` summed down the receivers (-1: none). Each cell whose donors are all done passes its sum on: a walk down
// from every source cell goes on for as long as it brings a receiver's last donor, so every cell is visited once,
// along the flow paths (neighbouring samples), without an order of the cells held in memory. Throws
// std::invalid_argument, naming `what`, when the receivers loop.
std::vector<std::int64_t> accumulate(const std::vector<std::int32_t>& receiver, std::vector<std::int64_t> weight,
                                     const char* what) {
  constexpr std::uint8_t kDone = 0xff;  // a D8 cell has at most 8 donors
  const std::size_t n = receiver.size();
  std::vector<std::uint8_t> donors(n, 0);
  for (const std::int32_t r : receiver)
    if (r >= 0) ++donors[static_cast<std::size_t>(r)];
  const std::int32_t* __restrict rec = receiver.data();
  std::uint8_t* __restrict left = donors.data();
  std::int64_t* __restrict sum = weight.data();
  std::size_t walked = 0;
  const auto walk = [&](std::size_t x) {
    for (;;) {
      left[x] = kDone;
      ++walked;
      const std::int32_t r = rec[x];
      if (r < 0) return;
      const auto y = static_cast<std::size_t>(r);
      sum[y] += sum[x];
      if (--left[y] != 0) return;
      x = y;
    }
  };
  // The sources (no donor) 16 at a time, a compare and a bit mask, instead of a branch a cell that goes either way
  // at random. A block's sources are those of its start: a walk never enters a source, and a cell it brings to
  // zero it walks on from at once.
  const __m128i zero = _mm_setzero_si128();
  std::size_t c = 0;
  for (; c + 16 <= n; c += 16) {
    auto sources = static_cast<unsigned>(
        _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(left + c)), zero)));
    for (; sources; sources &= sources - 1) walk(c + static_cast<std::size_t>(std::countr_zero(sources)));
  }
  for (; c < n; ++c)
    if (left[c] == 0) walk(c);
  if (walked != n) throw std::invalid_argument(std::string(what) + ": the flow directions loop");
  return weight;
}

}  // namespace

std::vector<std::int32_t> upstream_first(const std::vector<std::int32_t>& receiver, const char* what) {
  std::vector<std::int32_t> donors(receiver.size(), 0), order;
  order.reserve(receiver.size());
  for (const std::int32_t r : receiver) {
    if (r < -1 || r >= static_cast<std::int32_t>(receiver.size()))
      throw std::invalid_argument(std::string(what) + ": a receiver outside the tile");
    if (r >= 0) ++donors[static_cast<std::size_t>(r)];
  }
  for (std::size_t c = 0; c < receiver.size(); ++c)
    if (!donors[c]) order.push_back(static_cast<std::int32_t>(c));
  for (std::size_t h = 0; h < order.size(); ++h)
    if (const std::int32_t r = receiver[static_cast<std::size_t>(order[h])];
        r >= 0 && !--donors[static_cast<std::size_t>(r)])
      order.push_back(r);
  if (order.size() != receiver.size()) throw std::invalid_argument(std::string(what) + ": the flow directions loop");
  return order;
}

TileAccumulation start_tile_accumulation(std::span<const std::uint8_t> direction, const TileRect& rect,
                                         glm::ivec2 domain_size) {
  const int w = rect.size.x, h = rect.size.y;
  if (w < 1 || h < 1 || direction.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
    throw std::invalid_argument("start_tile_accumulation: directions do not match the tile's size");
  TileAccumulation t;
  t.rect = rect;
  t.domain = domain_size;
  t.receiver.assign(direction.size(), -1);
  t.owned.assign(direction.size(), 0);
  // A tile before this one holds its first column (first row) when it does not start at the domain's edge.
  const bool left = rect.first.x > 0, below = rect.first.y > 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
      t.owned[c] = !(left && i == 0) && !(below && j == 0);
      const int k = direction[c];
      if (k == kNoDirection) continue;
      if (k > 7) throw std::invalid_argument("start_tile_accumulation: not a D8 direction");
      const int ri = i + kDi[k], rj = j + kDj[k];
      if (ri < 0 || rj < 0 || ri >= w || rj >= h) continue;  // leaves the tile: another tile takes the edge
      if ((left && i == 0 && ri == 0) || (below && j == 0 && rj == 0)) continue;  // the tile before takes it
      t.receiver[c] = rj * w + ri;
    }
  t.local = accumulate(t.receiver, std::vector<std::int64_t>(t.owned.begin(), t.owned.end()), "tile accumulation");
  // The next perimeter cell downstream of each perimeter cell: a walk down to a perimeter cell, an end, or a cell an
  // earlier walk passed (whose answer it noted), so each cell is walked once.
  const auto perimeter = perimeter_cells(rect.size);
  const auto index = perimeter_index(rect.size);
  constexpr std::int32_t kUnknown = -2;
  std::vector<std::int32_t> next(direction.size(), kUnknown), path;
  t.link.reserve(perimeter.size());
  for (const std::int32_t p : perimeter) {
    path.clear();
    std::int32_t found = -1;
    for (std::int32_t x = p;;) {
      const std::int32_t r = t.receiver[static_cast<std::size_t>(x)];
      if (r < 0) break;
      if (index[static_cast<std::size_t>(r)] >= 0) {
        found = index[static_cast<std::size_t>(r)];
        break;
      }
      if (next[static_cast<std::size_t>(r)] != kUnknown) {
        found = next[static_cast<std::size_t>(r)];
        break;
      }
      path.push_back(r);
      x = r;
    }
    for (const std::int32_t y : path) next[static_cast<std::size_t>(y)] = found;
    t.link.push_back(found);
  }
  return t;
}

std::string accumulation_message(const TileAccumulation& t) {
  std::string out;
  put_tile_rect(out, t.rect);
  const auto perimeter = perimeter_cells(t.rect.size);
  bytes::put(out, static_cast<std::uint64_t>(perimeter.size()));
  for (std::size_t k = 0; k < perimeter.size(); ++k)
    bytes::put(out, t.local[static_cast<std::size_t>(perimeter[k])]), bytes::put(out, t.link[k]);
  return out;
}

std::vector<std::string> solve_tile_accumulation(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  struct Tile {
    TileRect rect;
    std::vector<std::int32_t> node;  // per perimeter cell: its sample's node
    std::vector<std::int64_t> local;
    std::vector<std::int32_t> link;
  };
  std::vector<Tile> tiles(messages.size());
  std::unordered_map<std::int64_t, std::int32_t> node_of;  // sample index -> node
  std::vector<std::int64_t> acc;                           // per node: the sum of L, then the accumulation
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::string_view in(messages[t]);
    Tile& tile = tiles[t];
    const TileRect& r = tile.rect = take_tile_rect(in, domain_size, "solve_tile_accumulation");
    const auto perimeter = perimeter_cells(r.size);
    if (take<std::uint64_t>(in) != perimeter.size())
      throw std::invalid_argument("solve_tile_accumulation: a tile's perimeter does not match its size");
    for (const std::int32_t c : perimeter) {
      const auto [it, fresh] = node_of.emplace(domain_sample(r, domain_size, c), static_cast<std::int32_t>(acc.size()));
      if (fresh) acc.push_back(0);
      tile.node.push_back(it->second);
      tile.local.push_back(take<std::int64_t>(in));
      tile.link.push_back(take<std::int32_t>(in));
      if (tile.link.back() < -1 || tile.link.back() >= static_cast<std::int32_t>(perimeter.size()))
        throw std::invalid_argument("solve_tile_accumulation: a link names no perimeter cell");
      acc[static_cast<std::size_t>(tile.node.back())] += tile.local.back();
    }
    if (!in.empty()) throw std::invalid_argument("solve_tile_accumulation: trailing bytes");
  }
  // acc(s) = sum of L over the tiles holding s + sum over (tile, q) linking to s of (acc(q) - L_tile(q)).
  struct Out {
    std::int32_t to;
    std::int64_t local;
  };
  std::vector<std::vector<Out>> out(acc.size());
  std::vector<std::int32_t> pending(acc.size(), 0);
  for (const Tile& tile : tiles)
    for (std::size_t k = 0; k < tile.link.size(); ++k)
      if (tile.link[k] >= 0) {
        const std::int32_t to = tile.node[static_cast<std::size_t>(tile.link[k])];
        out[static_cast<std::size_t>(tile.node[k])].push_back({to, tile.local[k]});
        ++pending[static_cast<std::size_t>(to)];
      }
  std::vector<std::int32_t> ready;
  for (std::size_t s = 0; s < acc.size(); ++s)
    if (!pending[s]) ready.push_back(static_cast<std::int32_t>(s));
  for (std::size_t h = 0; h < ready.size(); ++h) {
    const auto s = static_cast<std::size_t>(ready[h]);
    for (const Out& o : out[s]) {
      acc[static_cast<std::size_t>(o.to)] += acc[s] - o.local;
      if (!--pending[static_cast<std::size_t>(o.to)]) ready.push_back(o.to);
    }
  }
  if (ready.size() != acc.size()) throw std::invalid_argument("solve_tile_accumulation: the links form a cycle");
  // Y(q) = acc(q) - L(q) - what the tile's own edges bring to q from its upstream perimeter cells.
  std::vector<std::string> answers(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const Tile& tile = tiles[t];
    std::vector<std::int64_t> y(tile.link.size());
    for (std::size_t k = 0; k < y.size(); ++k) y[k] = acc[static_cast<std::size_t>(tile.node[k])] - tile.local[k];
    for (std::size_t k = 0; k < y.size(); ++k)
      if (tile.link[k] >= 0)
        y[static_cast<std::size_t>(tile.link[k])] -= acc[static_cast<std::size_t>(tile.node[k])] - tile.local[k];
    bytes::put_vector(answers[t], y);
  }
  return answers;
}

std::vector<std::int64_t> finish_tile_accumulation(const TileAccumulation& t, std::string_view answer) {
  const auto y = bytes::take_vector<std::int64_t>(answer, "tile accumulation");
  if (!answer.empty()) throw std::invalid_argument("tile accumulation: trailing bytes");
  const auto perimeter = perimeter_cells(t.rect.size);
  if (y.size() != perimeter.size()) throw std::invalid_argument("tile accumulation: one inflow per perimeter cell");
  std::vector<std::int64_t> weight(t.owned.begin(), t.owned.end());
  for (std::size_t k = 0; k < perimeter.size(); ++k) weight[static_cast<std::size_t>(perimeter[k])] += y[k];
  return accumulate(t.receiver, std::move(weight), "tile accumulation");
}

}  // namespace orogen::hydrology
