#include "nodes/hydrology/tile_lakes.h"

#include <algorithm>
#include <stdexcept>

#include "nodes/hydrology/depressions.h"
#include "graph/tile_bytes.h"
#include "nodes/hydrology/tile_components.h"

namespace orogen::hydrology {

namespace {

constexpr const char* kWhat = "tile lakes";

}  // namespace

TileLakeLabels label_tile_lakes(std::span<const float> water, std::span<const float> ground, const TileRect& rect,
                                glm::ivec2 whole) {
  const std::size_t n = static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y);
  if (water.size() != n || ground.size() != n)
    throw std::invalid_argument("label_tile_lakes: water and ground must cover the tile");
  std::vector<std::uint8_t> wet(n);
  for (std::size_t c = 0; c < n; ++c) wet[c] = water[c] > ground[c];
  TileLakeLabels out;
  const int count = label_components(rect.size.x, rect.size.y, wet, out.label);
  TileLakes& lakes = out.lakes;
  lakes.rect = rect;
  lakes.first_cell.assign(static_cast<std::size_t>(count), -1);
  lakes.deepest.assign(static_cast<std::size_t>(count), 0.0f);
  lakes.cells.assign(static_cast<std::size_t>(count), 0);
  // A shared sample belongs to the tile before it: the last row and column are the next tile's, but at the end.
  const int owned_x = rect.first.x + rect.size.x == whole.x ? rect.size.x : rect.size.x - 1;
  const int owned_y = rect.first.y + rect.size.y == whole.y ? rect.size.y : rect.size.y - 1;
  for (int j = 0; j < rect.size.y; ++j)
    for (int i = 0; i < rect.size.x; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(rect.size.x) + i;
      if (!out.label[c]) continue;
      const auto k = static_cast<std::size_t>(out.label[c] - 1);
      // The tile's row-major order is the whole domain's restricted to the tile: the first cell met is the lowest.
      if (lakes.first_cell[k] < 0)
        lakes.first_cell[k] = static_cast<std::int64_t>(rect.first.y + j) * whole.x + rect.first.x + i;
      lakes.deepest[k] = std::max(lakes.deepest[k], water[c] - ground[c]);
      if (i < owned_x && j < owned_y) ++lakes.cells[k];
    }
  const auto perimeter = perimeter_cells(rect.size);
  lakes.perimeter.resize(perimeter.size());
  for (std::size_t p = 0; p < perimeter.size(); ++p)
    lakes.perimeter[p] = out.label[static_cast<std::size_t>(perimeter[p])];
  return out;
}

std::vector<std::vector<std::int32_t>> solve_tile_lakes(const std::vector<TileLakes>& tiles, glm::ivec2 whole,
                                                        const KeepLake& keep) {
  std::vector<std::int32_t> offset(tiles.size() + 1, 0);
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const TileLakes& l = tiles[t];
    const TileRect& r = l.rect;
    if (r.first.x < 0 || r.first.y < 0 || r.size.x < 1 || r.size.y < 1 || r.first.x + r.size.x > whole.x ||
        r.first.y + r.size.y > whole.y)
      throw std::invalid_argument("tile lakes: tile " + std::to_string(t) + " lies outside the domain");
    const std::size_t count = l.first_cell.size();
    if (l.deepest.size() != count || l.cells.size() != count || l.perimeter.size() != perimeter_cells(r.size).size() ||
        count > std::size_t(1) << 30)
      throw std::invalid_argument("tile lakes: tile " + std::to_string(t) + " has inconsistent sizes");
    for (const std::int32_t k : l.perimeter)
      if (k < 0 || static_cast<std::size_t>(k) > count)
        throw std::invalid_argument("tile lakes: tile " + std::to_string(t) + " names an unknown lake");
    offset[t + 1] = offset[t] + static_cast<std::int32_t>(count);
  }
  LowestRootUnionFind components = join_numbered_components(
      tiles, whole, offset, "tile lakes: neighboring tiles disagree whether a shared sample is under water");
  // Per whole lake (its root): the lowest first cell, the deepest water, the cells.
  const auto n = static_cast<std::size_t>(offset.back());
  std::vector<std::int64_t> first(n, -1), cells(n, 0);
  std::vector<float> deepest(n, 0.0f);
  for (std::size_t t = 0; t < tiles.size(); ++t)
    for (std::size_t k = 0; k < tiles[t].first_cell.size(); ++k) {
      const auto root = static_cast<std::size_t>(components.root(offset[t] + static_cast<std::int32_t>(k)));
      first[root] = first[root] < 0 ? tiles[t].first_cell[k] : std::min(first[root], tiles[t].first_cell[k]);
      deepest[root] = std::max(deepest[root], tiles[t].deepest[k]);
      cells[root] += tiles[t].cells[k];
    }
  std::vector<std::int32_t> kept;
  for (std::size_t c = 0; c < n; ++c)
    if (components.root(static_cast<std::int32_t>(c)) == static_cast<std::int32_t>(c) && keep(deepest[c], cells[c]))
      kept.push_back(static_cast<std::int32_t>(c));
  std::sort(kept.begin(), kept.end(), [&](std::int32_t a, std::int32_t b) {
    return first[static_cast<std::size_t>(a)] < first[static_cast<std::size_t>(b)];
  });
  std::vector<std::int32_t> number(n, 0);
  for (std::size_t k = 0; k < kept.size(); ++k)
    number[static_cast<std::size_t>(kept[k])] = static_cast<std::int32_t>(k + 1);
  std::vector<std::vector<std::int32_t>> out(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    out[t].resize(tiles[t].first_cell.size());
    for (std::size_t k = 0; k < out[t].size(); ++k)
      out[t][k] = number[static_cast<std::size_t>(components.root(offset[t] + static_cast<std::int32_t>(k)))];
  }
  return out;
}

std::string encode(const TileLakes& l) {
  std::string out;
  bytes::put(out, l.rect.first.x), bytes::put(out, l.rect.first.y);
  bytes::put(out, l.rect.size.x), bytes::put(out, l.rect.size.y);
  bytes::put_vector(out, l.first_cell);
  bytes::put_vector(out, l.deepest);
  bytes::put_vector(out, l.cells);
  bytes::put_vector(out, l.perimeter);
  return out;
}

TileLakes decode_tile_lakes(std::string_view in) {
  TileLakes l;
  l.rect.first.x = bytes::take<int>(in, kWhat), l.rect.first.y = bytes::take<int>(in, kWhat);
  l.rect.size.x = bytes::take<int>(in, kWhat), l.rect.size.y = bytes::take<int>(in, kWhat);
  l.first_cell = bytes::take_vector<std::int64_t>(in, kWhat);
  l.deepest = bytes::take_vector<float>(in, kWhat);
  l.cells = bytes::take_vector<std::int64_t>(in, kWhat);
  l.perimeter = bytes::take_vector<std::int32_t>(in, kWhat);
  if (!in.empty()) throw std::invalid_argument("tile lakes: trailing bytes");
  return l;
}

std::vector<std::string> solve_lake_messages(std::span<const std::string_view> messages, glm::ivec2 whole,
                                             const KeepLake& keep) {
  std::vector<TileLakes> lakes;
  lakes.reserve(messages.size());
  for (std::string_view m : messages) lakes.push_back(decode_tile_lakes(m));
  const auto numbers = solve_tile_lakes(lakes, whole, keep);
  std::vector<std::string> answers(numbers.size());
  for (std::size_t t = 0; t < numbers.size(); ++t) bytes::put_vector(answers[t], numbers[t]);
  return answers;
}

}  // namespace orogen::hydrology
