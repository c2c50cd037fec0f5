#include "nodes/hydrology/tile_shares.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <utility>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/flow_shares.h"
#include "nodes/hydrology/tile_ring.h"

namespace orogen::hydrology {
namespace {

constexpr const char* kWhat = "flow shares across tiles";
constexpr std::uint8_t kDone = 0xFF;

// The tiles holding a domain sample (up to four: tiles share their border samples), from the tiles' rectangles.
class TileLocator {
 public:
  explicit TileLocator(std::vector<TileRect> rects) : rects_(std::move(rects)) {
    for (std::size_t t = 0; t < rects_.size(); ++t) {
      columns_.push_back(rects_[t].first.x);
      rows_.push_back(rects_[t].first.y);
      at_[{rects_[t].first.x, rects_[t].first.y}] = static_cast<int>(t);
    }
    for (auto* v : {&columns_, &rows_}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
  }
  const TileRect& rect(int t) const { return rects_[static_cast<std::size_t>(t)]; }
  // Calls fn(tile) for every tile holding sample (x, y).
  template <class Fn>
  void holders(int x, int y, Fn&& fn) const {
    const auto xs = last_two_starts(columns_, x), ys = last_two_starts(rows_, y);
    for (int cy : ys)
      for (int cx : xs) {
        if (cx < 0 || cy < 0) continue;
        const auto it = at_.find({cx, cy});
        if (it != at_.end() && holds(it->second, x, y)) fn(it->second);
      }
  }
  bool holds(int t, int x, int y) const {
    const TileRect& r = rect(t);
    return x >= r.first.x && y >= r.first.y && x < r.first.x + r.size.x && y < r.first.y + r.size.y;
  }

 private:
  // The two last starts at or before v (-1 where there is none): a sample lies in at most two tiles along an axis.
  static std::array<int, 2> last_two_starts(const std::vector<int>& starts, int v) {
    const auto k = std::upper_bound(starts.begin(), starts.end(), v) - starts.begin();
    return {k >= 2 ? starts[static_cast<std::size_t>(k - 2)] : -1,
            k >= 1 ? starts[static_cast<std::size_t>(k - 1)] : -1};
  }

  std::vector<TileRect> rects_;
  std::vector<int> columns_, rows_;
  std::map<std::pair<int, int>, int> at_;
};

// Calls wait(u, cell key) for every tile u that waits for the edge `key` (domain sample * 8 + k, the donor being the
// sample's neighbour k): the tiles holding the receiver but not the donor; cell key = u's tile cell * 8 + k.
template <class Fn>
void for_each_waiting(const TileLocator& tiles, std::int64_t key, glm::ivec2 domain, Fn&& wait) {
  const std::int64_t sample = key >> 3;
  const int k = static_cast<int>(key & 7);
  if (key < 0 || sample >= static_cast<std::int64_t>(domain.x) * domain.y)
    throw std::invalid_argument("flow shares across tiles: an edge outside the domain");
  const int x = static_cast<int>(sample % domain.x), y = static_cast<int>(sample / domain.x);
  const int mx = x + kDi[k], my = y + kDj[k];
  tiles.holders(x, y, [&](int u) {
    if (tiles.holds(u, mx, my)) return;
    const TileRect& r = tiles.rect(u);
    wait(u, (static_cast<std::int64_t>(y - r.first.y) * r.size.x + (x - r.first.x)) * 8 + k);
  });
}

}  // namespace

TileShares::TileShares(std::vector<float> ringed_z, const TileRect& rect, glm::ivec2 domain_size, double dx, double dy,
                       const RoutingOptions& routing, std::vector<float> weight)
    : rect_(rect), domain_(domain_size), weight_(std::move(weight)), area_(dx * dy) {
  const TileRect ringed = ringed_rect(rect, domain_size);
  at_ = rect.first - ringed.first;
  gw_ = ringed.size.x;
  const int gh = ringed.size.y;
  const std::size_t tile_cells = static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y);
  const std::size_t ringed_cells = static_cast<std::size_t>(gw_) * static_cast<std::size_t>(gh);
  if (ringed_z.size() != ringed_cells)
    throw std::invalid_argument("flow shares across tiles: heights do not match the tile and its ring");
  if (!weight_.empty() && weight_.size() != tile_cells)
    throw std::invalid_argument("flow shares across tiles: weights do not match the tile");
  // The ringed tile as a grid of its own: its border cells drain (outlets, no receivers), which is right for the
  // domain's border, and the ring's cells are never donors here (their shares come from the tiles holding them).
  RoutingOptions opt = routing;
  opt.outlets = {};
  shares_ = std::make_unique<FlowShares>(FlowGrid(gw_, gh, dx, dy), ringed_z, opt);
  ringed_z = {};  // the shares are all the rounds need of the heights
  const FlowShares& s = *shares_;
  acc_.assign(ringed_cells, 0.0);
  remaining_.assign(ringed_cells, kDone);
  outside_.assign(perimeter_cells(rect.size).size(), 0);
  inflow_.assign(outside_.size() * 8, 0.0);
  exports_.assign(ringed_cells, 0);
  pending_ = static_cast<std::int64_t>(tile_cells);
  const bool after_column = rect.first.x > 0, after_row = rect.first.y > 0;
  for (int j = 0; j < rect.size.y; ++j)
    for (int i = 0; i < rect.size.x; ++i) {
      const std::int32_t c = ringed_cell(i, j);
      const bool perimeter = perimeter_position(rect.size, i, j) >= 0;
      int donors = 0;
      for (int k = 0; k < 8; ++k) {
        const int ii = i + kDi[k], jj = j + kDj[k];
        if (ii < 0 || jj < 0 || ii >= rect.size.x || jj >= rect.size.y) continue;  // outside the tile
        if (!s.donor(c, k)) continue;
        ++donors;
        // The edge into a perimeter cell, if this tile takes it: another tile may hold the receiver, not the donor.
        const bool on_first_column = after_column && i == 0 && ii == 0;
        const bool on_first_row = after_row && j == 0 && jj == 0;
        if (perimeter && !on_first_column && !on_first_row) {
          const std::int64_t sample = static_cast<std::int64_t>(rect.first.y + j) * domain_size.x + rect.first.x + i;
          out_.push_back({c + s.offset(k), static_cast<std::uint8_t>(opposite(k)), sample * 8 + k});
        }
      }
      remaining_[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(donors);
    }
  std::stable_sort(out_.begin(), out_.end(), [](const OutEdge& a, const OutEdge& b) { return a.donor < b.donor; });
}

TileShares::~TileShares() = default;

bool TileShares::in_tile(std::int32_t r) const {
  const int i = r % gw_ - at_.x, j = r / gw_ - at_.y;
  return i >= 0 && j >= 0 && i < rect_.size.x && j < rect_.size.y;
}

std::string TileShares::edges_message() const {
  std::string out;
  put_tile_rect(out, rect_);
  std::vector<std::int64_t> keys;
  keys.reserve(out_.size());
  for (const OutEdge& e : out_) keys.push_back(e.key);
  bytes::put_vector(out, keys);
  return out;
}

void TileShares::take_edges(std::string_view answer) {
  const auto awaited = bytes::take_vector<std::uint8_t>(answer, kWhat);
  const auto incoming = bytes::take_vector<std::int64_t>(answer, kWhat);
  if (!answer.empty()) throw std::invalid_argument("flow shares across tiles: trailing bytes");
  if (awaited.size() != out_.size()) throw std::invalid_argument("flow shares across tiles: edges do not match");
  for (std::size_t e = 0; e < out_.size(); ++e)
    if (awaited[e]) {
      out_[e].awaited = true;
      exports_[static_cast<std::size_t>(out_[e].donor)] = 1;
    }
  const std::int64_t cells = static_cast<std::int64_t>(rect_.size.x) * rect_.size.y;
  for (const std::int64_t key : incoming) {
    const std::int64_t cell = key >> 3;
    const int k = static_cast<int>(key & 7);
    const std::int32_t p = cell >= 0 && cell < cells ? perimeter_of(cell) : -1;
    if (p < 0 || (outside_[static_cast<std::size_t>(p)] >> k) & 1u)
      throw std::invalid_argument("flow shares across tiles: an edge from outside that is not on the perimeter");
    outside_[static_cast<std::size_t>(p)] |= static_cast<std::uint8_t>(1u << k);
    const int i = static_cast<int>(cell % rect_.size.x), j = static_cast<int>(cell / rect_.size.x);
    ++remaining_[static_cast<std::size_t>(ringed_cell(i, j))];
  }
  std::vector<std::int32_t> ready;
  for (int j = 0; j < rect_.size.y; ++j)
    for (int i = 0; i < rect_.size.x; ++i)
      if (remaining_[static_cast<std::size_t>(ringed_cell(i, j))] == 0) ready.push_back(ringed_cell(i, j));
  run(ready);
}

void TileShares::finish(std::int32_t r, std::vector<std::int32_t>& ready) {
  const FlowShares& s = *shares_;
  const int i = r % gw_ - at_.x, j = r / gw_ - at_.y;
  const std::size_t cell =
      static_cast<std::size_t>(j) * static_cast<std::size_t>(rect_.size.x) + static_cast<std::size_t>(i);
  // The pull of flow_shares.h: own weight, then every donor's share in neighbour order, from this tile's own cells or
  // from the shares that arrived.
  double sum = weight_.empty() ? area_ : static_cast<double>(weight_[cell]);
  const std::int32_t p = perimeter_position(rect_.size, i, j);
  const std::uint8_t outside = p >= 0 ? outside_[static_cast<std::size_t>(p)] : 0;
  for (int k = 0; k < 8; ++k) {
    const int ii = i + kDi[k], jj = j + kDj[k];
    if (ii >= 0 && jj >= 0 && ii < rect_.size.x && jj < rect_.size.y) {
      if (!s.donor(r, k)) continue;
      const std::int32_t m = r + s.offset(k);
      sum += acc_[static_cast<std::size_t>(m)] * s.fraction(m, opposite(k));
    } else if ((outside >> k) & 1u) {
      sum += inflow_[static_cast<std::size_t>(p) * 8 + static_cast<std::size_t>(k)];
    }
  }
  acc_[static_cast<std::size_t>(r)] = sum;
  remaining_[static_cast<std::size_t>(r)] = kDone;
  --pending_;
  if (exports_[static_cast<std::size_t>(r)]) {
    const auto first =
        std::lower_bound(out_.begin(), out_.end(), r, [](const OutEdge& e, std::int32_t d) { return e.donor < d; });
    for (auto e = first; e != out_.end() && e->donor == r; ++e)
      if (e->awaited) {
        send_keys_.push_back(e->key);
        send_values_.push_back(sum * s.fraction(r, e->k));
      }
  }
  for (unsigned b = s.receivers(r); b; b &= b - 1) {
    const std::int32_t m = r + s.offset(std::countr_zero(b));
    if (!in_tile(m)) continue;  // another tile holds that edge
    if (--remaining_[static_cast<std::size_t>(m)] == 0) ready.push_back(m);
  }
}

void TileShares::run(std::vector<std::int32_t>& ready) {
  while (!ready.empty()) {
    const std::int32_t r = ready.back();
    ready.pop_back();
    finish(r, ready);
  }
}

std::string TileShares::shares_message() {
  std::string out;
  bytes::put(out, static_cast<std::uint8_t>(done()));
  put_tile_rect(out, rect_);
  bytes::put_vector(out, send_keys_);
  bytes::put_vector(out, send_values_);
  send_keys_.clear();
  send_values_.clear();
  return out;
}

void TileShares::take_shares(std::string_view answer) {
  const auto keys = bytes::take_vector<std::int64_t>(answer, kWhat);
  const auto values = bytes::take_vector<double>(answer, kWhat);
  if (!answer.empty() || keys.size() != values.size())
    throw std::invalid_argument("flow shares across tiles: malformed shares");
  const std::int64_t cells = static_cast<std::int64_t>(rect_.size.x) * rect_.size.y;
  std::vector<std::int32_t> ready;
  for (std::size_t e = 0; e < keys.size(); ++e) {
    const std::int64_t cell = keys[e] >> 3;
    const int k = static_cast<int>(keys[e] & 7);
    const std::int32_t p = cell >= 0 && cell < cells ? perimeter_of(cell) : -1;
    if (p < 0 || !((outside_[static_cast<std::size_t>(p)] >> k) & 1u))
      throw std::invalid_argument("flow shares across tiles: a share along an edge the tile does not wait for");
    inflow_[static_cast<std::size_t>(p) * 8 + static_cast<std::size_t>(k)] = values[e];
    const std::int32_t r = ringed_cell(static_cast<int>(cell % rect_.size.x), static_cast<int>(cell / rect_.size.x));
    if (remaining_[static_cast<std::size_t>(r)] == kDone || remaining_[static_cast<std::size_t>(r)] == 0)
      throw std::invalid_argument("flow shares across tiles: a share for a cell that is done");
    if (--remaining_[static_cast<std::size_t>(r)] == 0) ready.push_back(r);
  }
  run(ready);
}

std::vector<double> TileShares::take_accumulation() {
  if (!done()) throw std::logic_error("flow shares across tiles: accumulation before every cell is done");
  // What the rounds needed goes first: only the accumulation and its copy without the ring are ever held together.
  shares_.reset();
  remaining_ = {};
  exports_ = {};
  std::vector<double> acc = std::move(acc_);
  return without_ring<double>(acc, rect_, domain_);
}

std::vector<std::string> solve_share_edges(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<TileRect> rects;
  std::vector<std::vector<std::int64_t>> keys;
  for (std::string_view in : messages) {
    rects.push_back(take_tile_rect(in, domain_size, kWhat));
    keys.push_back(bytes::take_vector<std::int64_t>(in, kWhat));
    if (!in.empty()) throw std::invalid_argument("flow shares across tiles: trailing bytes");
  }
  const TileLocator tiles(rects);
  std::vector<std::vector<std::uint8_t>> awaited(messages.size());
  std::vector<std::vector<std::int64_t>> incoming(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    awaited[t].assign(keys[t].size(), 0);
    for (std::size_t e = 0; e < keys[t].size(); ++e)
      for_each_waiting(tiles, keys[t][e], domain_size, [&](int u, std::int64_t cell_key) {
        incoming[static_cast<std::size_t>(u)].push_back(cell_key);
        awaited[t][e] = 1;
      });
  }
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    bytes::put_vector(answers[t], awaited[t]);
    bytes::put_vector(answers[t], incoming[t]);
  }
  return answers;
}

bool shares_done(std::span<const std::string_view> messages) {
  for (std::string_view in : messages) {
    if (!bytes::take<std::uint8_t>(in, kWhat)) return false;
  }
  return true;
}

std::vector<std::string> solve_shares(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<TileRect> rects;
  std::vector<std::vector<std::int64_t>> keys;
  std::vector<std::vector<double>> values;
  bool moved = false, all_done = true;
  for (std::string_view in : messages) {
    all_done = bytes::take<std::uint8_t>(in, kWhat) != 0 && all_done;
    rects.push_back(take_tile_rect(in, domain_size, kWhat));
    keys.push_back(bytes::take_vector<std::int64_t>(in, kWhat));
    values.push_back(bytes::take_vector<double>(in, kWhat));
    if (!in.empty() || keys.back().size() != values.back().size())
      throw std::invalid_argument("flow shares across tiles: malformed shares");
    moved = moved || !keys.back().empty();
  }
  if (!moved && !all_done)
    throw std::invalid_argument("flow shares across tiles: no share moved but cells wait (a cycle in the flow)");
  const TileLocator tiles(rects);
  std::vector<std::vector<std::int64_t>> to_keys(messages.size());
  std::vector<std::vector<double>> to_values(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t)
    for (std::size_t e = 0; e < keys[t].size(); ++e)
      for_each_waiting(tiles, keys[t][e], domain_size, [&](int u, std::int64_t cell_key) {
        to_keys[static_cast<std::size_t>(u)].push_back(cell_key);
        to_values[static_cast<std::size_t>(u)].push_back(values[t][e]);
      });
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    bytes::put_vector(answers[t], to_keys[t]);
    bytes::put_vector(answers[t], to_values[t]);
  }
  return answers;
}

}  // namespace orogen::hydrology
