#include "nodes/hydrology/tile_fill.h"

#include <algorithm>
#include <bit>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/radix_heap.h"

namespace orogen::hydrology {

namespace {

// Priority queue entry: the lowest level first, ties by cell (or node) index, so the run is deterministic.
struct FloodEntry {
  float level;
  std::int64_t index;
  bool operator>(const FloodEntry& o) const { return level > o.level || (level == o.level && index > o.index); }
};
using MinQueue = std::priority_queue<FloodEntry, std::vector<FloodEntry>, std::greater<FloodEntry>>;

using bytes::put;

template <class T>
T take(std::string_view& in) {
  return bytes::take<T>(in, "spill graph");
}

}  // namespace

std::vector<std::int32_t> perimeter_cells(glm::ivec2 size) {
  std::vector<std::int32_t> cells;
  cells.reserve(static_cast<std::size_t>(2 * (size.x + size.y)));
  for (int j = 0; j < size.y; ++j)
    if (j == 0 || j == size.y - 1) {
      for (int i = 0; i < size.x; ++i) cells.push_back(j * size.x + i);
    } else {
      cells.push_back(j * size.x);
      if (size.x > 1) cells.push_back(j * size.x + size.x - 1);
    }
  return cells;
}

std::vector<std::int32_t> perimeter_index(glm::ivec2 size) {
  std::vector<std::int32_t> index(static_cast<std::size_t>(size.x) * static_cast<std::size_t>(size.y), -1);
  const auto perimeter = perimeter_cells(size);
  for (std::size_t k = 0; k < perimeter.size(); ++k)
    index[static_cast<std::size_t>(perimeter[k])] = static_cast<std::int32_t>(k);
  return index;
}

std::int64_t domain_sample(const TileRect& r, glm::ivec2 domain_size, std::int32_t c) {
  return static_cast<std::int64_t>(r.first.y + c / r.size.x) * domain_size.x + r.first.x + c % r.size.x;
}

void put_tile_rect(std::string& out, const TileRect& r) {
  put(out, r.first.x), put(out, r.first.y), put(out, r.size.x), put(out, r.size.y);
}

TileRect take_tile_rect(std::string_view& in, glm::ivec2 domain_size, const char* what) {
  TileRect r;
  r.first.x = bytes::take<int>(in, what), r.first.y = bytes::take<int>(in, what);
  r.size.x = bytes::take<int>(in, what), r.size.y = bytes::take<int>(in, what);
  if (r.size.x < 1 || r.size.y < 1 || r.first.x < 0 || r.first.y < 0 || r.first.x + r.size.x > domain_size.x ||
      r.first.y + r.size.y > domain_size.y)
    throw std::invalid_argument(std::string(what) + ": a tile lies outside the domain");
  return r;
}

namespace {

// A flood queue entry in one integer: the level's bits turned to sort as unsigned integers (negative levels
// reversed, -0 taken as +0), then the cell. Every cell is queued once, so the keys are distinct and the pops come in
// (level, cell) order, as a queue of (level, cell) pairs gives them; half the bytes, and no float compares.
std::uint64_t flood_key(float level, std::size_t cell) {
  const auto bits = std::bit_cast<std::uint32_t>(level + 0.0f);  // -0 + 0 is +0
  const std::uint32_t ordered = (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
  return static_cast<std::uint64_t>(ordered) << 32 | static_cast<std::uint64_t>(cell);
}
std::size_t key_cell(std::uint64_t key) { return static_cast<std::size_t>(key & 0xffffffffu); }

}  // namespace

TileFlood flood_tile(std::span<const float> z, const TileRect& rect, std::span<const std::uint8_t> drained) {
  const int w = rect.size.x, h = rect.size.y;
  if (w < 1 || h < 1 || z.size() != static_cast<std::size_t>(w) * h)
    throw std::invalid_argument("flood_tile: heights do not match the tile's size");
  if (z.size() > std::size_t{0xffffffffu})
    throw std::invalid_argument("flood_tile: a tile of more than 2^32 - 1 samples");
  if (!drained.empty() && drained.size() != z.size())
    throw std::invalid_argument("flood_tile: the drained cells do not match the tile's size");
  auto is_drained = [&](std::size_t c) { return !drained.empty() && drained[c] != 0; };
  TileFlood f;
  f.graph.rect = rect;
  f.level.assign(z.begin(), z.end());
  f.label.assign(z.size(), -1);
  // The cells that may spill into lower ground, in (level, cell) order. After the first pop no key pushed is below the
  // last one popped: a cell from the queue or the pit queue floods at the level L last popped and sends neighbours at
  // L to the pit queue, so only levels above L reach the queue, and a slope cell's level is above L too. That is what
  // a radix heap needs; it pops in the same order as a binary heap, at a fraction of the cost.
  RadixHeap queue;
  const auto perimeter = perimeter_cells(rect.size);
  const auto drained_label = static_cast<std::int32_t>(perimeter.size());
  // The lowest spill level between each pair of labels met, keyed by (lower label, higher label); sorted by the key
  // at the end, the edges come in pair order.
  std::unordered_map<std::uint64_t, float> edges;
  const auto edge_key = [](std::int32_t a, std::int32_t b) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 | static_cast<std::uint32_t>(b);
  };
  for (std::size_t k = 0; k < perimeter.size(); ++k) {
    const auto c = static_cast<std::size_t>(perimeter[k]);
    f.label[c] = static_cast<std::int32_t>(k);
    f.graph.perimeter.push_back(z[c]);
    queue.push(flood_key(z[c], c));
    if (is_drained(c)) edges.emplace(edge_key(static_cast<std::int32_t>(k), drained_label), z[c]);
  }
  // The 8 neighbours in the order (dj, di) = (-1, -1), (-1, 0), ... (1, 1); an interior cell's without bounds checks.
  const std::ptrdiff_t sw = w;
  const std::ptrdiff_t offsets[8] = {-sw - 1, -sw, -sw + 1, -1, 1, sw - 1, sw, sw + 1};
  // The neighbours are listed first and visited in one loop, so that `fn` is inlined at one place.
  const auto neighbours = [&](std::size_t c, auto&& fn) {
    // The cells fit 32 bits (checked above): a 32-bit division is several times faster than a 64-bit one.
    const auto c32 = static_cast<std::uint32_t>(c), w32 = static_cast<std::uint32_t>(w);
    const int j = static_cast<int>(c32 / w32), i = static_cast<int>(c32 - static_cast<std::uint32_t>(j) * w32);
    std::size_t list[8];
    int count = 0;
    if (i > 0 && j > 0 && i < w - 1 && j < h - 1) {
      for (const std::ptrdiff_t o : offsets)
        list[count++] = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + o);
    } else {
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int x = i + di, y = j + dj;
          if ((di == 0 && dj == 0) || x < 0 || y < 0 || x >= w || y >= h) continue;
          list[count++] = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
        }
    }
    for (int k = 0; k < count; ++k) fn(list[k]);
  };
  // Drained cells next to the others flood from their own height, as one label of their own.
  if (!drained.empty())
    for (std::size_t c = 0; c < z.size(); ++c) {
      if (!is_drained(c) || f.label[c] >= 0) continue;
      bool border = false;
      neighbours(c, [&](std::size_t n) { border = border || !is_drained(n); });
      if (!border) continue;
      f.label[c] = drained_label;
      queue.push(flood_key(z[c], c));
    }
  // Cells raised to their flooder's level go through a plain queue, ahead of the priority queue (the pit queue of
  // Barnes, Lehman and Mulla 2014, Priority-Flood): the same levels, far fewer heap operations.
  std::vector<std::size_t> pit;
  std::size_t pit_head = 0;
  // A cell above its flooder's level whose unlabelled neighbours are none of them lower than it is flooded from at
  // once, off a FIFO (the slope cells of Zhou, Sun and Fu 2016): each of those neighbours gets its own height as its
  // level, the least it can have, whenever the flood reaches it, so the order does not matter. Only cells that may
  // spill into lower ground wait in the priority queue. A label still passes from a cell to a neighbour whose level
  // is no lower, so the spill graph's solve gives the same levels (the labels may differ from a strict flood's).
  // The test for lower ground is made when a cell leaves the FIFO, not when it joins: breadth first, by then the
  // climb around it has usually flooded its lower neighbours, and it need not wait in the priority queue (on a 1025^2
  // fBm tile 217 thousand cells wait in it where 536 thousand did; the whole-domain fill's climb, flow_routing.cpp,
  // found the same).
  std::vector<std::size_t> slope;
  std::size_t slope_head = 0;
  const auto on_slope = [&](std::size_t n) {
    bool lower = false;
    const bool drained_n = is_drained(n);
    neighbours(
        n, [&](std::size_t m) { lower = lower || (f.label[m] < 0 && z[m] < z[n] && !(drained_n && is_drained(m))); });
    return !lower;
  };
  // Every cell is queued once (when it is labelled), so each pop is a cell not yet flooded from.
  while (!queue.empty() || pit_head < pit.size() || slope_head < slope.size()) {
    std::size_t c;
    bool from_slope = false;
    if (pit_head < pit.size()) {
      c = pit[pit_head++];
      if (pit_head == pit.size()) pit.clear(), pit_head = 0;
    } else if (slope_head < slope.size()) {
      c = slope[slope_head++];
      if (slope_head == slope.size()) {
        slope.clear(), slope_head = 0;
      } else if (slope_head > (std::size_t{1} << 16) && slope_head * 2 > slope.size()) {
        // A long climb whose front has moved far: drop what was taken, so the FIFO holds its front, not the climb.
        slope.erase(slope.begin(), slope.begin() + static_cast<std::ptrdiff_t>(slope_head)), slope_head = 0;
      }
      if (!on_slope(c)) {
        queue.push(flood_key(f.level[c], c));
        continue;
      }
      from_slope = true;
    } else {
      c = key_cell(queue.pop());
    }
    const bool from_drained = is_drained(c);
    const std::int32_t label = f.label[c];
    const float level = f.level[c];
    neighbours(c, [&](std::size_t n) {
      if (f.label[n] < 0) {
        if (from_drained && is_drained(n)) return;  // drained ground stays as it is: no flood crosses it
        f.label[n] = label;
        f.level[n] = std::max(z[n], level);
        // A slope cell's level is above the queue's: a neighbour at that level floods on from it only as a slope
        // cell (the pit queue's cells flood at the level being drained).
        if (f.level[n] == level && !from_slope)
          pit.push_back(n);
        else
          slope.push_back(n);
      } else if (f.label[n] != label) {
        const auto [a, b] = std::minmax(label, f.label[n]);
        const float spill = std::max(level, f.level[n]);
        auto [it, fresh] = edges.emplace(edge_key(a, b), spill);
        if (!fresh) it->second = std::min(it->second, spill);
      }
    });
  }
  std::vector<std::pair<std::uint64_t, float>> sorted(edges.begin(), edges.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  f.graph.edges.reserve(sorted.size());
  for (const auto& [key, spill] : sorted)
    f.graph.edges.push_back(
        {static_cast<std::int32_t>(key >> 32), static_cast<std::int32_t>(key & 0xffffffffu), spill});
  return f;
}

std::vector<std::vector<float>> solve_spill_graphs(const std::vector<TileSpillGraph>& tiles, glm::ivec2 domain_size) {
  // Nodes: every perimeter cell of every tile, numbered tile by tile.
  std::vector<std::int64_t> offset(tiles.size() + 1, 0);
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const TileRect& r = tiles[t].rect;
    if (r.first.x < 0 || r.first.y < 0 || r.first.x + r.size.x > domain_size.x || r.first.y + r.size.y > domain_size.y)
      throw std::invalid_argument("solve_spill_graphs: a tile lies outside the domain");
    if (tiles[t].perimeter.size() != perimeter_cells(r.size).size())
      throw std::invalid_argument("solve_spill_graphs: a tile's perimeter does not match its size");
    offset[t + 1] = offset[t] + static_cast<std::int64_t>(tiles[t].perimeter.size()) + 1;  // and its drained node
  }
  struct Link {
    std::int64_t to;
    float level;
  };
  std::vector<std::vector<Link>> links(static_cast<std::size_t>(offset.back()));
  const auto link = [&](std::int64_t a, std::int64_t b, float level) {
    links[static_cast<std::size_t>(a)].push_back({b, level});
    links[static_cast<std::size_t>(b)].push_back({a, level});
  };
  std::vector<float> level(links.size(), std::numeric_limits<float>::infinity());
  MinQueue queue;
  // A sample on several tiles' perimeters: the first node seen at it, then its height.
  std::unordered_map<std::int64_t, std::pair<std::int64_t, float>> shared;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const TileSpillGraph& g = tiles[t];
    const auto cells = perimeter_cells(g.rect.size);
    // The tile's drained cells (flood_tile) drain whatever reaches them.
    const std::int64_t drained = offset[t] + static_cast<std::int64_t>(cells.size());
    level[static_cast<std::size_t>(drained)] = -std::numeric_limits<float>::infinity();
    queue.push({level[static_cast<std::size_t>(drained)], drained});
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::int64_t node = offset[t] + static_cast<std::int64_t>(k);
      const int gx = g.rect.first.x + cells[k] % g.rect.size.x, gy = g.rect.first.y + cells[k] / g.rect.size.x;
      const float z = g.perimeter[k];
      if (gx == 0 || gy == 0 || gx == domain_size.x - 1 || gy == domain_size.y - 1) {
        // The domain's border drains at its own height.
        level[static_cast<std::size_t>(node)] = z;
        queue.push({z, node});
      }
      const std::int64_t sample = static_cast<std::int64_t>(gy) * domain_size.x + gx;
      auto [it, fresh] = shared.emplace(sample, std::make_pair(node, z));
      if (fresh) continue;
      if (it->second.second != z)
        throw std::invalid_argument("solve_spill_graphs: tiles disagree on the height of a shared sample");
      link(it->second.first, node, z);
    }
    for (const SpillEdge& e : g.edges) {
      if (e.a < 0 || e.b < 0 || e.a >= static_cast<std::int32_t>(cells.size()) ||
          e.b > static_cast<std::int32_t>(cells.size()))
        throw std::invalid_argument("solve_spill_graphs: a spill edge names no perimeter cell");
      link(offset[t] + e.a, offset[t] + e.b, e.level);
    }
  }
  // Minimax Dijkstra: the lowest level at which water from each node reaches the border.
  std::vector<std::uint8_t> done(links.size(), 0);
  while (!queue.empty()) {
    const FloodEntry top = queue.top();
    queue.pop();
    const auto u = static_cast<std::size_t>(top.index);
    if (done[u]) continue;
    done[u] = 1;
    for (const Link& l : links[u]) {
      const float through = std::max(level[u], l.level);
      if (through < level[static_cast<std::size_t>(l.to)]) {
        level[static_cast<std::size_t>(l.to)] = through;
        queue.push({through, l.to});
      }
    }
  }
  std::vector<std::vector<float>> out(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t)
    out[t].assign(level.begin() + offset[t], level.begin() + offset[t + 1] - 1);
  return out;
}

std::vector<float> apply_spill_levels(const TileFlood& flood, std::span<const float> spill_levels) {
  if (spill_levels.size() != flood.graph.perimeter.size())
    throw std::invalid_argument("apply_spill_levels: one level per perimeter cell expected");
  std::vector<float> out(flood.level.size());
  for (std::size_t c = 0; c < out.size(); ++c) {
    // Drained cells and those the flood never reached (drained too) keep their height.
    const auto label = static_cast<std::size_t>(flood.label[c]);
    out[c] = flood.label[c] >= 0 && label < spill_levels.size() ? std::max(flood.level[c], spill_levels[label])
                                                                : flood.level[c];
  }
  return out;
}

namespace {

// A round's message: the tile's rectangle, then (perimeter index, value) pairs.
TileRect take_rect(std::string_view& in) {
  TileRect r;
  r.first.x = take<int>(in), r.first.y = take<int>(in);
  r.size.x = take<int>(in), r.size.y = take<int>(in);
  return r;
}
struct PerimeterValue {
  std::int32_t k;
  float value;
};
std::vector<PerimeterValue> take_values(std::string_view& in, std::size_t perimeter) {
  const auto n = take<std::uint64_t>(in);
  if (n > in.size() / (sizeof(std::int32_t) + sizeof(float)))
    throw std::invalid_argument("perimeter values: truncated");
  std::vector<PerimeterValue> values(static_cast<std::size_t>(n));
  for (auto& v : values) {
    v.k = take<std::int32_t>(in), v.value = take<float>(in);
    if (v.k < 0 || static_cast<std::size_t>(v.k) >= perimeter)
      throw std::invalid_argument("perimeter values: a value names no perimeter cell");
  }
  if (!in.empty()) throw std::invalid_argument("perimeter values: trailing bytes");
  return values;
}

}  // namespace

PerimeterMinima::PerimeterMinima(const TileRect& rect)
    : rect_(rect),
      perimeter_(perimeter_cells(rect.size)),
      sent_(perimeter_.size(), std::numeric_limits<float>::infinity()) {}

std::string PerimeterMinima::message(std::span<const float> values) {
  std::vector<PerimeterValue> fell;
  for (std::size_t k = 0; k < perimeter_.size(); ++k) {
    const float v = values[static_cast<std::size_t>(perimeter_[k])];
    if (v < sent_[k]) fell.push_back({static_cast<std::int32_t>(k), v}), sent_[k] = v;
  }
  std::string out;
  put_tile_rect(out, rect_);
  put(out, static_cast<std::uint64_t>(fell.size()));
  for (const auto& f : fell) put(out, f.k), put(out, f.value);
  return out;
}

std::vector<std::int32_t> PerimeterMinima::answer(std::string_view bytes, std::span<float> values) {
  std::vector<std::int32_t> fell;
  for (const auto& [k, value] : take_values(bytes, perimeter_.size())) {
    sent_[static_cast<std::size_t>(k)] = std::min(sent_[static_cast<std::size_t>(k)], value);  // known to all
    const std::int32_t c = perimeter_[static_cast<std::size_t>(k)];
    float& v = values[static_cast<std::size_t>(c)];
    if (value < v) v = value, fell.push_back(c);
  }
  return fell;
}

TileEpsilon::TileEpsilon(std::vector<float> level, const TileRect& rect, glm::ivec2 domain_size,
                         std::span<const std::uint8_t> drained)
    : rect_(rect), level_(std::move(level)), minima_(rect) {
  if (level_.size() != static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y) ||
      (!drained.empty() && drained.size() != level_.size()))
    throw std::invalid_argument("TileEpsilon: levels do not match the tile's size");
  e_.assign(level_.size(), std::numeric_limits<float>::infinity());
  // Drained cells are final at their level (their height); those next to the others relax them.
  std::vector<std::int32_t> seeds;
  const int w = rect.size.x, h = rect.size.y;
  for (std::size_t c = 0; c < drained.size(); ++c) {
    if (!drained[c]) continue;
    e_[c] = level_[c];
    const int i = static_cast<int>(c) % w, j = static_cast<int>(c) / w;
    bool border = false;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int x = i + di, y = j + dj;
        if (x >= 0 && y >= 0 && x < w && y < h) border = border || !drained[static_cast<std::size_t>(y * w + x)];
      }
    if (border) seeds.push_back(static_cast<std::int32_t>(c));
  }
  // The domain's border drains at its own height (the outlets of fill_depressions).
  for (const std::int32_t c : minima_.perimeter()) {
    const int gx = rect.first.x + c % rect.size.x, gy = rect.first.y + c / rect.size.x;
    if (gx == 0 || gy == 0 || gx == domain_size.x - 1 || gy == domain_size.y - 1) {
      e_[static_cast<std::size_t>(c)] = level_[static_cast<std::size_t>(c)];
      seeds.push_back(c);
    }
  }
  relax_epsilon(rect.size.x, rect.size.y, level_, e_, seeds);
}

void TileEpsilon::answer(std::string_view bytes) {
  const std::vector<std::int32_t> seeds = minima_.answer(bytes, e_);
  if (!seeds.empty()) relax_epsilon(rect_.size.x, rect_.size.y, level_, e_, seeds);
}

std::vector<std::string> solve_perimeter_minima(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  struct Tile {
    TileRect rect;
    std::vector<std::int32_t> perimeter;
    std::vector<PerimeterValue> values;
  };
  std::vector<Tile> tiles(messages.size());
  // The lowest value reported for every shared sample, by sample index.
  std::unordered_map<std::int64_t, float> lowest;
  auto sample = [&](const Tile& t, std::int32_t k) {
    return domain_sample(t.rect, domain_size, t.perimeter[static_cast<std::size_t>(k)]);
  };
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::string_view in(messages[t]);
    Tile& tile = tiles[t];
    const TileRect& r = tile.rect = take_tile_rect(in, domain_size, "solve_perimeter_minima");
    tile.perimeter = perimeter_cells(r.size);
    tile.values = take_values(in, tile.perimeter.size());
    for (const auto& [k, value] : tile.values) {
      auto [it, fresh] = lowest.emplace(sample(tile, k), value);
      if (!fresh) it->second = std::min(it->second, value);
    }
  }
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    std::vector<PerimeterValue> mine;
    if (!lowest.empty())
      for (std::size_t k = 0; k < tiles[t].perimeter.size(); ++k)
        if (const auto it = lowest.find(sample(tiles[t], static_cast<std::int32_t>(k))); it != lowest.end())
          mine.push_back({static_cast<std::int32_t>(k), it->second});
    put(answers[t], static_cast<std::uint64_t>(mine.size()));
    for (const auto& m : mine) put(answers[t], m.k), put(answers[t], m.value);
  }
  return answers;
}

bool perimeter_minima_fell(std::span<const std::string_view> messages) {
  for (std::string_view in : messages) {
    take_rect(in);
    if (take<std::uint64_t>(in) > 0) return true;
  }
  return false;
}

std::string encode(const TileSpillGraph& g) {
  std::string out;
  put(out, g.rect.first.x), put(out, g.rect.first.y), put(out, g.rect.size.x), put(out, g.rect.size.y);
  put(out, static_cast<std::uint64_t>(g.perimeter.size()));
  for (const float z : g.perimeter) put(out, z);
  put(out, static_cast<std::uint64_t>(g.edges.size()));
  for (const SpillEdge& e : g.edges) put(out, e.a), put(out, e.b), put(out, e.level);
  return out;
}

std::vector<std::string> solve_spill_messages(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<TileSpillGraph> graphs;
  graphs.reserve(messages.size());
  for (std::string_view m : messages) graphs.push_back(decode_spill_graph(m));
  const auto levels = solve_spill_graphs(graphs, domain_size);
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < levels.size(); ++t) bytes::put_vector(answers[t], levels[t]);
  return answers;
}

TileSpillGraph decode_spill_graph(std::string_view in) {
  TileSpillGraph g;
  g.rect.first.x = take<int>(in), g.rect.first.y = take<int>(in);
  g.rect.size.x = take<int>(in), g.rect.size.y = take<int>(in);
  const auto n = take<std::uint64_t>(in);
  if (n > in.size() / sizeof(float)) throw std::invalid_argument("spill graph: truncated bytes");
  g.perimeter.resize(static_cast<std::size_t>(n));
  for (float& z : g.perimeter) z = take<float>(in);
  const auto m = take<std::uint64_t>(in);
  if (m > in.size() / (2 * sizeof(std::int32_t) + sizeof(float)))
    throw std::invalid_argument("spill graph: truncated bytes");
  g.edges.resize(static_cast<std::size_t>(m));
  for (SpillEdge& e : g.edges) e.a = take<std::int32_t>(in), e.b = take<std::int32_t>(in), e.level = take<float>(in);
  if (!in.empty()) throw std::invalid_argument("spill graph: trailing bytes");
  return g;
}

}  // namespace orogen::hydrology
