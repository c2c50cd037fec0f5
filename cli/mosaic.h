#pragma once
// Mosaics of tiled builds: for every raster a tiled build writes in a format GDAL reads (TIFF, PNG), a GDAL
// virtual raster (`<name>.vrt`, https://gdal.org/drivers/raster/vrt.html) beside its tiles that places each tile
// at its samples, so `gdalinfo DIR/height.vrt` and GIS tools open the whole world as one image. Tiles share
// their border samples (cli/tiling.h); the VRT draws them in tile order over each other, and the shared samples
// are equal. Georeferenced by the domain (pixel centres at the samples, +y north) with the writer's `crs` when
// it has one. EXR tiles get none: Debian's GDAL has no EXR driver (write TIFF for a mosaic); nor do RAW tiles.
#include <set>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "graph/graph.h"
#include "graph/output_path.h"
#include "cli/tile_naming.h"

namespace orogen::cli {

// Writes the mosaics of `graph`'s raster writers, but those of `skip_nodes`, for a build of every tile of
// `counts`; each file replaces the previous one atomically; tiles are found by their names under `naming`.
// Returns the files written; `warnings` gets what was left out and why.
std::vector<std::string> write_mosaics(const Graph& graph, const Domain& full, glm::ivec2 counts, TileNaming naming,
                                       const OutputPolicy& policy, std::vector<std::string>& warnings,
                                       const std::set<std::string>& skip_nodes = {});

// The VRT document of tiles `tile_files` (row-major, tile (I, J) at I + J N) of `counts` over `full`, each with
// `channels` bands of GDAL type `data_type` ("Float32", "UInt16", "Byte"); file names relative to the VRT; `crs`
// empty or as WriteHeightfield's crs.
std::string mosaic_vrt(const Domain& full, glm::ivec2 counts, const std::vector<std::string>& tile_files, int channels,
                       const std::string& data_type, const std::string& crs);

}  // namespace orogen::cli
