#include "nodes/hydrology/tile_ring.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

#include "graph/tile_bytes.h"

namespace orogen::hydrology {
namespace {

constexpr const char* kWhat = "tile ring";

// Calls fn(i, j) for the cells of a w x h tile within one sample of its perimeter, row-major.
template <class Fn>
void for_each_band_cell(glm::ivec2 size, Fn&& fn) {
  for (int j = 0; j < size.y; ++j) {
    const bool edge_row = j <= 1 || j >= size.y - 2;
    for (int i = 0; i < size.x; ++i)
      if (edge_row || i <= 1 || i >= size.x - 2) fn(i, j);
  }
}

// Calls fn(i, j) for the cells of ringed_rect(rect) outside rect, in its coordinates, row-major.
template <class Fn>
void for_each_ring_cell(const TileRect& rect, const TileRect& ringed, Fn&& fn) {
  const glm::ivec2 lo = rect.first - ringed.first, hi = lo + rect.size - 1;
  for (int j = 0; j < ringed.size.y; ++j)
    for (int i = 0; i < ringed.size.x; ++i)
      if (i < lo.x || j < lo.y || i > hi.x || j > hi.y) fn(i, j);
}

}  // namespace

TileRect ringed_rect(const TileRect& rect, glm::ivec2 domain_size) {
  const glm::ivec2 lo = glm::max(rect.first - 1, glm::ivec2(0));
  const glm::ivec2 hi = glm::min(rect.first + rect.size, domain_size - 1);
  return {lo, hi - lo + 1};
}

namespace {

// The bits of a value, to compare copies of one sample exactly.
inline std::uint32_t bits_of(float v) { return std::bit_cast<std::uint32_t>(v); }
inline std::uint64_t bits_of(double v) { return std::bit_cast<std::uint64_t>(v); }

template <class T>
std::string ring_message_of(std::span<const T> values, const TileRect& rect) {
  if (values.size() != static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y))
    throw std::invalid_argument("ring_message: values do not match the tile's size");
  std::string out;
  put_tile_rect(out, rect);
  std::vector<T> band;
  for_each_band_cell(rect.size, [&](int i, int j) {
    band.push_back(
        values[static_cast<std::size_t>(j) * static_cast<std::size_t>(rect.size.x) + static_cast<std::size_t>(i)]);
  });
  bytes::put_vector(out, band);
  return out;
}

template <class T>
std::vector<std::string> solve_rings_of(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<TileRect> rects(messages.size());
  std::unordered_map<std::int64_t, T> value_of;  // sample index -> value, over every tile's band
  for (std::size_t t = 0; t < messages.size(); ++t) {
    std::string_view in(messages[t]);
    const TileRect& r = rects[t] = take_tile_rect(in, domain_size, kWhat);
    const auto band = bytes::take_vector<T>(in, kWhat);
    if (!in.empty()) throw std::invalid_argument("tile ring: trailing bytes");
    std::size_t k = 0;
    bool fits = true;
    for_each_band_cell(r.size, [&](int i, int j) {
      if (k >= band.size()) {
        fits = false;
        return;
      }
      const T v = band[k++];
      const auto [it, fresh] = value_of.emplace(domain_sample(r, domain_size, j * r.size.x + i), v);
      if (!fresh && bits_of(it->second) != bits_of(v))
        throw std::invalid_argument("tile ring: tiles disagree on a shared sample");
    });
    if (!fits || k != band.size()) throw std::invalid_argument("tile ring: a tile's band does not match its size");
  }
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    const TileRect ringed = ringed_rect(rects[t], domain_size);
    std::vector<T> ring;
    for_each_ring_cell(rects[t], ringed, [&](int i, int j) {
      const auto it = value_of.find(static_cast<std::int64_t>(ringed.first.y + j) * domain_size.x + ringed.first.x + i);
      if (it == value_of.end()) throw std::invalid_argument("tile ring: no tile holds a sample around a tile");
      ring.push_back(it->second);
    });
    bytes::put_vector(answers[t], ring);
  }
  return answers;
}

template <class T>
std::vector<T> with_ring_of(std::span<const T> values, const TileRect& rect, glm::ivec2 domain_size,
                            std::string_view answer) {
  if (values.size() != static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y))
    throw std::invalid_argument("with_ring: values do not match the tile's size");
  const TileRect ringed = ringed_rect(rect, domain_size);
  const auto ring = bytes::take_vector<T>(answer, kWhat);
  if (!answer.empty()) throw std::invalid_argument("tile ring: trailing bytes");
  const auto width = static_cast<std::size_t>(ringed.size.x);
  std::vector<T> out(width * static_cast<std::size_t>(ringed.size.y));
  std::size_t k = 0;
  for_each_ring_cell(rect, ringed, [&](int i, int j) {
    if (k >= ring.size()) throw std::invalid_argument("tile ring: too few values around the tile");
    out[static_cast<std::size_t>(j) * width + static_cast<std::size_t>(i)] = ring[k++];
  });
  if (k != ring.size()) throw std::invalid_argument("tile ring: too many values around the tile");
  const glm::ivec2 at = rect.first - ringed.first;
  for (int j = 0; j < rect.size.y; ++j)
    std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(j) * rect.size.x, rect.size.x,
                out.begin() + static_cast<std::ptrdiff_t>((at.y + j) * ringed.size.x + at.x));
  return out;
}

}  // namespace

std::string ring_message(std::span<const float> values, const TileRect& rect) { return ring_message_of(values, rect); }
std::string ring_message(std::span<const double> values, const TileRect& rect) { return ring_message_of(values, rect); }

std::vector<std::string> solve_rings(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  return solve_rings_of<float>(messages, domain_size);
}
std::vector<std::string> solve_double_rings(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  return solve_rings_of<double>(messages, domain_size);
}

std::vector<float> with_ring(std::span<const float> values, const TileRect& rect, glm::ivec2 domain_size,
                             std::string_view answer) {
  return with_ring_of(values, rect, domain_size, answer);
}
std::vector<double> with_ring(std::span<const double> values, const TileRect& rect, glm::ivec2 domain_size,
                              std::string_view answer) {
  return with_ring_of(values, rect, domain_size, answer);
}

namespace {

void put_part(std::string& out, std::string_view part) {
  bytes::put(out, static_cast<std::uint64_t>(part.size()));
  out += part;
}
std::string_view take_part(std::string_view& in) {
  const auto n = bytes::take<std::uint64_t>(in, kWhat);
  if (n > in.size()) throw std::invalid_argument("tile ring: a truncated pair");
  const std::string_view part = in.substr(0, static_cast<std::size_t>(n));
  in.remove_prefix(static_cast<std::size_t>(n));
  return part;
}

}  // namespace

std::string ring_pair_message(std::span<const float> first, std::span<const float> second, const TileRect& rect) {
  std::string out;
  put_part(out, ring_message(first, rect));
  put_part(out, ring_message(second, rect));
  return out;
}

std::vector<std::string> solve_ring_pairs(std::span<const std::string_view> messages, glm::ivec2 domain_size) {
  std::vector<std::string_view> first, second;
  for (std::string_view in : messages) {
    first.push_back(take_part(in));
    second.push_back(take_part(in));
    if (!in.empty()) throw std::invalid_argument("tile ring: trailing bytes");
  }
  const auto a = solve_rings(first, domain_size), b = solve_rings(second, domain_size);
  std::vector<std::string> answers(messages.size());
  for (std::size_t t = 0; t < answers.size(); ++t) put_part(answers[t], a[t]), put_part(answers[t], b[t]);
  return answers;
}

std::pair<std::vector<float>, std::vector<float>> with_ring_pair(std::span<const float> first,
                                                                 std::span<const float> second, const TileRect& rect,
                                                                 glm::ivec2 domain_size, std::string_view answer) {
  const std::string_view a = take_part(answer), b = take_part(answer);
  if (!answer.empty()) throw std::invalid_argument("tile ring: trailing bytes");
  return {with_ring(first, rect, domain_size, a), with_ring(second, rect, domain_size, b)};
}

}  // namespace orogen::hydrology
