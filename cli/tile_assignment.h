#pragma once
// Which rank builds which tile in a distributed build (docs/distributed.md). The assignment is fixed and
// depends only on the tile counts and the rank count: the tiles, numbered row by row (k = J N + I for tile
// (I, J) of N x M), are cut into R contiguous runs, rank r taking tiles floor(r T / R) to floor((r+1) T / R) - 1
// of the T = N M tiles. Runs are contiguous so a rank's tiles are neighbours (shared halos, fewer perimeter
// links), and any two ranks' loads differ by at most one tile.
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::cli {

// The row-major index of tile `index` among `counts` tiles.
long long tile_number(glm::ivec2 counts, glm::ivec2 index);
// The rank that builds tile `index` of `counts` tiles on `ranks` ranks.
int tile_owner(glm::ivec2 counts, glm::ivec2 index, int ranks);
// The tiles rank `rank` of `ranks` builds, in row-major order.
std::vector<glm::ivec2> tiles_of_rank(glm::ivec2 counts, int rank, int ranks);

}  // namespace orogen::cli
