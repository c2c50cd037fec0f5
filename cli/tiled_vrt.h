#pragma once
// A GDAL virtual raster (VRT) over the tiles of a tiled build, so QGIS and GDAL open a tiled world as one
// layer: each tile's file placed at its samples' offset in the whole domain (north row first; the rows and
// columns tiles share are read from either, they are equal). Kept apart from cli/tiling.* so every way of
// building tiles (one process, MPI) can write it.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"

namespace orogen::cli {

struct VrtTile {
  std::filesystem::path file;  // relative to the VRT's directory, or absolute
  glm::ivec2 first{0, 0};      // first sample of the tile in the whole domain (x east, y north)
  glm::ivec2 size{1, 1};       // its samples, shared borders included
};

// The VRT text: `domain` the whole build's, `data_type` GDAL's name ("Float32", "UInt16"), `crs` empty or as
// WriteHeightfield's crs.
std::string tiled_vrt_xml(const Domain& domain, const std::vector<VrtTile>& tiles, const std::string& data_type,
                          const std::string& crs);

}  // namespace orogen::cli
