#pragma once
// Running a node type's tile-graph algorithm (graph/tile_graph.h) over a tiling in one process, as the stages of a
// tiled or distributed build do (cli/tile_graph_stages.h), for the tests that compare it with the whole-domain node:
// random terrains whose depressions, flats and drainage cross tile borders and corners, the tiling's windows, and the
// tiles' outputs put together (shared samples must agree bit for bit).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/heightfield.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/tile_graph.h"
#include "support/tile_windows.h"

namespace orogen::test {

struct Terrain {
  glm::ivec2 size;
  std::vector<float> z;
};

// Random heights: `levels` > 0 quantizes them to integers (wide flats and ties), else continuous; plus a bowl on
// the domain's centre and a trench along its lower quarter, so depressions span tiles and cross their corners.
inline Terrain terrain(glm::ivec2 size, unsigned seed, int levels) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Terrain t{size, {}};
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      float v = u(rng) * 10.0f;
      if (levels > 0) v = std::floor(v * levels / 10.0f);
      const float dx = (i - size.x / 2.0f) / size.x, dy = (j - size.y / 2.0f) / size.y;
      v -= 30.0f * std::max(0.0f, 0.3f - std::sqrt(dx * dx + dy * dy));
      if (std::abs(j - size.y / 4) <= 1 && i > 2 && i < size.x - 3) v -= 8.0f;
      t.z.push_back(v + 0.05f * static_cast<float>(i));
    }
  return t;
}

// Per cell: the number of cells whose path along `receiver` (a cell's receiver, itself at an outlet or pit) ends
// at it: the area, in cells, that drains to each outlet.
inline std::vector<std::int64_t> cells_ending_at(const std::vector<std::int32_t>& receiver) {
  std::vector<std::int64_t> ending(receiver.size(), 0);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(receiver.size()); ++c) {
    std::int32_t x = c;
    while (receiver[static_cast<std::size_t>(x)] != x) x = receiver[static_cast<std::size_t>(x)];
    ++ending[static_cast<std::size_t>(x)];
  }
  return ending;
}

inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// 10 m between samples.
inline Domain domain_of(const Terrain& t) {
  return Domain::from_extent({0, 0}, {10.0 * (t.size.x - 1), 10.0 * (t.size.y - 1)}, t.size);
}

// The terrain as a heightfield on domain_of(t).
inline Heightfield heights_of(const Terrain& t) {
  Heightfield h(domain_of(t));
  h.data = t.z;
  return h;
}

inline std::vector<ParamValue> params_of(const NodeType& type, const std::map<std::string, ParamValue>& set) {
  std::vector<ParamValue> values;
  for (const auto& p : type.params) values.push_back(set.count(p.name) ? set.at(p.name) : p.default_value);
  return values;
}

// The registered algorithm of `type_name` for the parameters `set` (the rest at their defaults), or nullptr.
inline std::unique_ptr<TileGraphAlgorithm> algorithm_of(const std::string& type_name,
                                                        const std::map<std::string, ParamValue>& set,
                                                        const Domain& whole) {
  const NodeType& type = *NodeRegistry::instance().find(type_name);
  const auto values = params_of(type, set);
  EXPECT_NE(find_tile_graph(type_name), nullptr) << type_name;
  return tile_graph_for(type_name, ParamView(type, values), whole);
}

// Starts `algorithm` on the tiles of `counts` over `whole`: input k is inputs[k] (on `whole`) cut into the tile's
// window, unlinked where it is null.
inline std::vector<std::unique_ptr<TileGraphTile>> start_tiles(const TileGraphAlgorithm& algorithm, const Domain& whole,
                                                               glm::ivec2 counts,
                                                               const std::vector<HeightfieldPtr>& inputs) {
  const glm::ivec2 size = whole.resolution;
  std::vector<std::unique_ptr<TileGraphTile>> tiles;
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti) {
      const glm::ivec2 first{edge(ti, size.x, counts.x), edge(tj, size.y, counts.y)};
      const glm::ivec2 n = glm::ivec2(edge(ti + 1, size.x, counts.x), edge(tj + 1, size.y, counts.y)) - first + 1;
      std::vector<PortValue> values(inputs.size());
      for (std::size_t k = 0; k < inputs.size(); ++k)
        if (inputs[k]) values[k] = crop(whole, inputs[k], first, n);
      tiles.push_back(algorithm.start(values));
    }
  return tiles;
}

// Starts `algorithm` on the tiles of `counts` over `t`: the heights as the first input, `inputs` - 1 inputs after it
// (fields[k - 1] cut into the tiles for input k, unlinked where it is null or missing).
inline std::vector<std::unique_ptr<TileGraphTile>> start_tiles(
    const TileGraphAlgorithm& algorithm, const Terrain& t, glm::ivec2 counts, std::size_t inputs = 1,
    const std::vector<const std::vector<float>*>& fields = {}) {
  const Domain whole = domain_of(t);
  std::vector<HeightfieldPtr> maps(inputs);
  maps[0] = std::make_shared<Heightfield>(heights_of(t));
  for (std::size_t k = 1; k < inputs; ++k)
    if (k - 1 < fields.size() && fields[k - 1]) {
      auto h = std::make_shared<Heightfield>(whole);
      h->data = *fields[k - 1];
      maps[k] = h;
    }
  return start_tiles(algorithm, whole, counts, maps);
}

// A test's hook on the answers: it may change tile `tile`'s answer of round `round` (a mutation), or drop it (false).
using AnswerHook = std::function<bool(std::size_t tile, int round, std::string& answer)>;

// The tiles' rounds until the algorithm is done, every message through its bytes; the number of rounds.
inline int run_rounds(const TileGraphAlgorithm& algorithm, std::vector<std::unique_ptr<TileGraphTile>>& tiles,
                      const AnswerHook& hook = {}) {
  for (int round = 0;; ++round) {
    std::vector<std::string> messages;
    for (auto& tile : tiles) messages.push_back(tile->message(round));
    auto answers = algorithm.solve(round, messages);
    for (std::size_t k = 0; k < tiles.size(); ++k)
      if (!hook || hook(k, round, answers[k])) tiles[k]->answer(round, answers[k]);
    if (!algorithm.another_round(round, messages)) return round + 1;
  }
}

// A hook that drops the answers for which `skip(tile, round)` holds.
inline AnswerHook dropping(const std::function<bool(std::size_t tile, int round)>& skip) {
  if (!skip) return {};
  return [skip](std::size_t tile, int round, std::string&) { return !skip(tile, round); };
}

// Runs `algorithm` on the tiles (start_tiles) and puts every output of the tiles together on the whole domain.
// `rounds_run` gets the number of rounds.
inline std::vector<std::vector<float>> run_across_tiles(const TileGraphAlgorithm& algorithm, const Terrain& t,
                                                        glm::ivec2 counts, std::size_t inputs = 1,
                                                        int* rounds_run = nullptr,
                                                        const std::vector<const std::vector<float>*>& fields = {}) {
  auto tiles = start_tiles(algorithm, t, counts, inputs, fields);
  const int rounds = run_rounds(algorithm, tiles);
  if (rounds_run) *rounds_run = rounds;
  std::vector<std::vector<float>> joined;
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    joined.resize(outputs.size(), std::vector<float>(t.z.size(), std::numeric_limits<float>::quiet_NaN()));
    for (std::size_t o = 0; o < outputs.size(); ++o)
      join_tile_map(joined[o], *std::get<HeightfieldPtr>(outputs[o]), t.size.x, nullptr);
  }
  return joined;
}

// Damaged bytes of round `round` are refused: a message one byte short, a tile's message missing, an answer one byte
// short. `messages` are the tiles' messages of that round, after the answers of the rounds before. Without
// `missing_refused` a missing message is not checked (an algorithm whose solve does not count the tiles).
inline void expect_damaged_bytes_refused(const TileGraphAlgorithm& algorithm,
                                         std::vector<std::unique_ptr<TileGraphTile>>& tiles, int round,
                                         const std::vector<std::string>& messages, bool missing_refused = true) {
  auto damaged = messages;
  damaged[1].pop_back();
  EXPECT_THROW(algorithm.solve(round, damaged), std::invalid_argument) << "a truncated message";
  if (missing_refused) {
    damaged = messages;
    damaged.pop_back();
    EXPECT_THROW(algorithm.solve(round, damaged), std::invalid_argument) << "a missing message";
  }
  const auto answers = algorithm.solve(round, messages);
  EXPECT_THROW(tiles[0]->answer(round, std::string_view(answers[0]).substr(1)), std::invalid_argument)
      << "a truncated answer";
}

}  // namespace orogen::test
