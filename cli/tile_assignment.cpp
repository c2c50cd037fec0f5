#include "cli/tile_assignment.h"

namespace orogen::cli {

namespace {

// First tile number of rank r's run: floor(r T / R).
long long run_start(long long tiles, int rank, int ranks) { return tiles * rank / ranks; }

}  // namespace

long long tile_number(glm::ivec2 counts, glm::ivec2 index) {
  return static_cast<long long>(index.y) * counts.x + index.x;
}

int tile_owner(glm::ivec2 counts, glm::ivec2 index, int ranks) {
  const long long tiles = static_cast<long long>(counts.x) * counts.y, k = tile_number(counts, index);
  // The largest r with floor(r T / R) <= k.
  int r = static_cast<int>(((k + 1) * ranks - 1) / tiles);
  while (r > 0 && run_start(tiles, r, ranks) > k) --r;
  while (r + 1 < ranks && run_start(tiles, r + 1, ranks) <= k) ++r;
  return r;
}

std::vector<glm::ivec2> tiles_of_rank(glm::ivec2 counts, int rank, int ranks) {
  const long long tiles = static_cast<long long>(counts.x) * counts.y;
  std::vector<glm::ivec2> mine;
  for (long long k = run_start(tiles, rank, ranks); k < run_start(tiles, rank + 1, ranks); ++k)
    mine.emplace_back(static_cast<int>(k % counts.x), static_cast<int>(k / counts.x));
  return mine;
}

}  // namespace orogen::cli
