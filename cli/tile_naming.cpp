#include "cli/tile_naming.h"

namespace orogen::cli {

std::optional<TileNaming> parse_tile_naming(const std::string& text) {
  if (text == "orogen") return TileNaming::Orogen;
  if (text == "unreal") return TileNaming::Unreal;
  return std::nullopt;
}

glm::ivec2 named_tile_index(TileNaming naming, glm::ivec2 index, glm::ivec2 counts) {
  if (naming == TileNaming::Unreal) return {index.x, counts.y - 1 - index.y};
  return index;
}

}  // namespace orogen::cli
