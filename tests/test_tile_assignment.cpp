// The fixed assignment of tiles to ranks (cli/tile_assignment.h): contiguous row-major runs, every tile on
// exactly one rank, loads within one tile of each other, tile_owner the inverse of tiles_of_rank.
#include <gtest/gtest.h>

#include "cli/tile_assignment.h"

namespace orogen::cli {
namespace {

TEST(TileAssignment, EveryTileOnOneRankInContiguousBalancedRuns) {
  for (int nx = 1; nx <= 9; ++nx)
    for (int ny = 1; ny <= 7; ++ny) {
      const glm::ivec2 counts{nx, ny};
      const int tiles = nx * ny;
      for (int ranks = 1; ranks <= tiles; ++ranks) {
        std::vector<int> owner(static_cast<std::size_t>(tiles), -1);
        std::size_t least = tiles, most = 0;
        long long next = 0;  // runs follow each other in rank order
        for (int r = 0; r < ranks; ++r) {
          const auto mine = tiles_of_rank(counts, r, ranks);
          least = std::min(least, mine.size()), most = std::max(most, mine.size());
          for (const glm::ivec2 t : mine) {
            ASSERT_EQ(tile_number(counts, t), next++) << nx << "x" << ny << " on " << ranks;
            owner[static_cast<std::size_t>(tile_number(counts, t))] = r;
            EXPECT_EQ(tile_owner(counts, t, ranks), r);
          }
        }
        EXPECT_EQ(next, tiles);
        EXPECT_GE(least, 1u);
        EXPECT_LE(most - least, 1u);
      }
    }
}

TEST(TileAssignment, DocumentedExample) {
  // 3x2 tiles on 4 ranks: T = 6, rank r from floor(6 r / 4): tiles 0 | 1 2 | 3 | 4 5.
  EXPECT_EQ(tiles_of_rank({3, 2}, 0, 4), (std::vector<glm::ivec2>{{0, 0}}));
  EXPECT_EQ(tiles_of_rank({3, 2}, 1, 4), (std::vector<glm::ivec2>{{1, 0}, {2, 0}}));
  EXPECT_EQ(tiles_of_rank({3, 2}, 2, 4), (std::vector<glm::ivec2>{{0, 1}}));
  EXPECT_EQ(tiles_of_rank({3, 2}, 3, 4), (std::vector<glm::ivec2>{{1, 1}, {2, 1}}));
}

}  // namespace
}  // namespace orogen::cli
