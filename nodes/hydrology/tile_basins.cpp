#include "nodes/hydrology/tile_basins.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "graph/tile_bytes.h"

namespace orogen::hydrology {
namespace {

constexpr const char* kWhat = "tile basins";

}  // namespace

TileBasins start_tile_basins(const TileAccumulation& edges) {
  TileBasins t;
  t.rect = edges.rect;
  t.domain = edges.domain;
  t.owned = edges.owned;
  const std::size_t n = edges.receiver.size();
  t.end.assign(n, -1);
  std::vector<std::int32_t> path;
  for (std::size_t c = 0; c < n; ++c) {
    if (t.end[c] >= 0) continue;
    path.clear();
    auto x = static_cast<std::int32_t>(c);
    while (t.end[static_cast<std::size_t>(x)] < 0 && edges.receiver[static_cast<std::size_t>(x)] >= 0) {
      path.push_back(x);
      if (path.size() > n) throw std::invalid_argument("tile basins: the flow directions loop");
      x = edges.receiver[static_cast<std::size_t>(x)];
    }
    const std::int32_t stop = t.end[static_cast<std::size_t>(x)] >= 0 ? t.end[static_cast<std::size_t>(x)] : x;
    t.end[static_cast<std::size_t>(x)] = stop;
    for (const std::int32_t p : path) t.end[static_cast<std::size_t>(p)] = stop;
  }
  return t;
}

std::string basin_links_message(const TileBasins& t) {
  std::string out;
  put_tile_rect(out, t.rect);
  const auto perimeter = perimeter_cells(t.rect.size);
  const auto index = perimeter_index(t.rect.size);
  std::vector<std::int32_t> link;
  std::vector<std::int64_t> inside;
  for (const std::int32_t p : perimeter) {
    const std::int32_t e = t.end[static_cast<std::size_t>(p)];
    const std::int32_t k = index[static_cast<std::size_t>(e)];
    link.push_back(e != p && k >= 0 ? k : -1);
    inside.push_back(k < 0 ? domain_sample(t.rect, t.domain, e) : -1);
  }
  bytes::put_vector(out, link);
  bytes::put_vector(out, inside);
  return out;
}

std::vector<std::string> solve_basin_links(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::unordered_map<std::int64_t, std::int32_t> node_of;  // sample -> node
  std::vector<std::int64_t> sample, fixed;                 // per node: its sample; an outlet inside a tile, or -1
  std::vector<std::int32_t> next;                          // per node: the node its path stops at, or -1
  std::vector<std::vector<std::int32_t>> nodes(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::string_view in(messages[t]);
    const TileRect r = take_tile_rect(in, domain_size, kWhat);
    const auto perimeter = perimeter_cells(r.size);
    const auto link = bytes::take_vector<std::int32_t>(in, kWhat);
    const auto inside = bytes::take_vector<std::int64_t>(in, kWhat);
    if (!in.empty()) throw std::invalid_argument("tile basins: trailing bytes");
    if (link.size() != perimeter.size() || inside.size() != perimeter.size())
      throw std::invalid_argument("tile basins: a tile's perimeter does not match its size");
    for (const std::int32_t c : perimeter) {
      const std::int64_t s = domain_sample(r, domain_size, c);
      const auto [it, fresh] = node_of.emplace(s, static_cast<std::int32_t>(sample.size()));
      if (fresh) sample.push_back(s), fixed.push_back(-1), next.push_back(-1);
      nodes[t].push_back(it->second);
    }
    for (std::size_t k = 0; k < perimeter.size(); ++k) {
      const auto n = static_cast<std::size_t>(nodes[t][k]);
      if (link[k] < -1 || link[k] >= static_cast<std::int32_t>(perimeter.size()) ||
          inside[k] >= static_cast<std::int64_t>(domain_size.x) * domain_size.y || (link[k] >= 0 && inside[k] >= 0))
        throw std::invalid_argument("tile basins: a link names no perimeter cell or sample");
      if (link[k] < 0 && inside[k] < 0) continue;
      if (next[n] >= 0 || fixed[n] >= 0) throw std::invalid_argument("tile basins: two tiles take one flow edge");
      if (link[k] >= 0)
        next[n] = nodes[t][static_cast<std::size_t>(link[k])];
      else
        fixed[n] = inside[k];
    }
  }
  // The outlet of every node: where its chain of links ends (a fixed outlet, or the node itself).
  std::vector<std::int64_t> outlet(sample.size(), -1);
  std::vector<std::uint8_t> visiting(sample.size(), 0);
  std::vector<std::int32_t> chain;
  for (std::size_t s = 0; s < sample.size(); ++s) {
    if (outlet[s] >= 0) continue;
    chain.clear();
    auto x = static_cast<std::int32_t>(s);
    while (outlet[static_cast<std::size_t>(x)] < 0 && fixed[static_cast<std::size_t>(x)] < 0 &&
           next[static_cast<std::size_t>(x)] >= 0) {
      if (visiting[static_cast<std::size_t>(x)]) throw std::invalid_argument("tile basins: the links form a cycle");
      visiting[static_cast<std::size_t>(x)] = 1;
      chain.push_back(x);
      x = next[static_cast<std::size_t>(x)];
    }
    const auto ux = static_cast<std::size_t>(x);
    const std::int64_t o = outlet[ux] >= 0 ? outlet[ux] : fixed[ux] >= 0 ? fixed[ux] : sample[ux];
    outlet[ux] = o;
    for (const std::int32_t c : chain) outlet[static_cast<std::size_t>(c)] = o;
  }
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::vector<std::int64_t> y;
    y.reserve(nodes[t].size());
    for (const std::int32_t n : nodes[t]) y.push_back(outlet[static_cast<std::size_t>(n)]);
    bytes::put_vector(answers[t], y);
  }
  return answers;
}

void take_basin_outlets(TileBasins& t, std::string_view answer) {
  const auto y = bytes::take_vector<std::int64_t>(answer, kWhat);
  if (!answer.empty()) throw std::invalid_argument("tile basins: trailing bytes");
  const auto perimeter = perimeter_cells(t.rect.size);
  if (y.size() != perimeter.size()) throw std::invalid_argument("tile basins: one outlet per perimeter cell");
  const auto index = perimeter_index(t.rect.size);
  t.outlet.resize(t.end.size());
  for (std::size_t c = 0; c < t.end.size(); ++c) {
    const std::int32_t e = t.end[c];
    const std::int32_t k = index[static_cast<std::size_t>(e)];
    t.outlet[c] = k >= 0 ? y[static_cast<std::size_t>(k)] : domain_sample(t.rect, t.domain, e);
  }
}

std::string basin_count_message(TileBasins& t) {
  std::map<std::int64_t, std::int64_t> cells;
  for (std::size_t c = 0; c < t.outlet.size(); ++c) cells[t.outlet[c]] += t.owned[c];
  std::vector<std::int64_t> count;
  t.outlets.clear();
  for (const auto& [o, n] : cells) t.outlets.push_back(o), count.push_back(n);
  std::string out;
  bytes::put_vector(out, t.outlets);
  bytes::put_vector(out, count);
  return out;
}

std::vector<std::string> solve_basin_counts(std::span<const std::string_view> messages, double cell_area,
                                            double min_area) {
  std::vector<std::vector<std::int64_t>> outlets(messages.size());
  std::map<std::int64_t, std::int64_t> cells;
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::string_view in(messages[t]);
    outlets[t] = bytes::take_vector<std::int64_t>(in, kWhat);
    const auto count = bytes::take_vector<std::int64_t>(in, kWhat);
    if (!in.empty()) throw std::invalid_argument("tile basins: trailing bytes");
    if (count.size() != outlets[t].size()) throw std::invalid_argument("tile basins: one count per outlet");
    for (std::size_t k = 0; k < count.size(); ++k) cells[outlets[t][k]] += count[k];
  }
  // Numbered by decreasing area, ties by outlet index (the order in which watersheds() meets the outlets).
  std::vector<std::pair<std::int64_t, std::int64_t>> order(cells.begin(), cells.end());
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::map<std::int64_t, std::int32_t> number;
  std::int32_t basins = 0;
  for (const auto& [o, n] : order) number[o] = static_cast<double>(n) * cell_area >= min_area && n > 0 ? ++basins : 0;
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::vector<std::int32_t> id;
    std::vector<std::int64_t> count;
    for (const std::int64_t o : outlets[t]) id.push_back(number.at(o)), count.push_back(cells.at(o));
    bytes::put_vector(answers[t], id);
    bytes::put_vector(answers[t], count);
  }
  return answers;
}

void basin_maps(const TileBasins& t, std::string_view answer, double cell_area, std::span<float> id,
                std::span<float> area) {
  const auto number = bytes::take_vector<std::int32_t>(answer, kWhat);
  const auto count = bytes::take_vector<std::int64_t>(answer, kWhat);
  if (!answer.empty()) throw std::invalid_argument("tile basins: trailing bytes");
  if (number.size() != t.outlets.size() || count.size() != t.outlets.size())
    throw std::invalid_argument("tile basins: one number and count per outlet");
  if (id.size() != t.outlet.size() || area.size() != t.outlet.size())
    throw std::invalid_argument("tile basins: maps do not match the tile's size");
  for (std::size_t c = 0; c < t.outlet.size(); ++c) {
    const auto k =
        static_cast<std::size_t>(std::lower_bound(t.outlets.begin(), t.outlets.end(), t.outlet[c]) - t.outlets.begin());
    id[c] = static_cast<float>(number[k]);
    area[c] = static_cast<float>(static_cast<double>(count[k]) * cell_area);
  }
}

}  // namespace orogen::hydrology
