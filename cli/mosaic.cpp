#include "cli/mosaic.h"

#include <filesystem>
#include <set>
#include <sstream>

#include "cli/tiling.h"
#include "graph/atomic_file.h"
#include "nodes/io/georeference.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/image_codec.h"

namespace orogen::cli {

namespace {

// GDAL's name for the sample type of an image file's header; empty if a VRT cannot describe it.
std::string gdal_type(PixelType t) {
  if (t == PixelType::F32) return "Float32";
  if (t == PixelType::U16) return "UInt16";
  if (t == PixelType::U8) return "Byte";
  if (t == PixelType::I16) return "Int16";
  return {};
}

}  // namespace

std::string mosaic_vrt(const Domain& full, glm::ivec2 counts, const std::vector<std::string>& tile_files, int channels,
                       const std::string& data_type, const std::string& crs) {
  std::ostringstream s;
  s.precision(17);
  const int height = full.resolution.y;
  s << "<VRTDataset rasterXSize=\"" << full.resolution.x << "\" rasterYSize=\"" << height << "\">\n";
  if (!crs.empty()) s << "  <SRS>" << xml_escaped(crs) << "</SRS>\n";
  // Pixel centres at the samples; the first image row is the northern one (as the PAM side files say).
  const GeoTransform g = geotransform_of(full);
  s << "  <GeoTransform>" << g.values[0] << ", " << g.values[1] << ", " << g.values[2] << ", " << g.values[3] << ", "
    << g.values[4] << ", " << g.values[5] << "</GeoTransform>\n";
  for (int band = 1; band <= channels; ++band) {
    s << "  <VRTRasterBand dataType=\"" << data_type << "\" band=\"" << band << "\">\n";
    for (int j = 0; j < counts.y; ++j)
      for (int i = 0; i < counts.x; ++i) {
        const TileWindow w = tile_window(full.resolution, counts, {i, j});
        const int row = height - (w.first.y + w.size.y);  // the tile's northern row in the image
        s << "    <SimpleSource>\n"
          << "      <SourceFilename relativeToVRT=\"1\">"
          << xml_escaped(tile_files[static_cast<std::size_t>(j * counts.x + i)]) << "</SourceFilename>\n"
          << "      <SourceBand>" << band << "</SourceBand>\n"
          << "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"" << w.size.x << "\" ySize=\"" << w.size.y << "\"/>\n"
          << "      <DstRect xOff=\"" << w.first.x << "\" yOff=\"" << row << "\" xSize=\"" << w.size.x << "\" ySize=\""
          << w.size.y << "\"/>\n"
          << "    </SimpleSource>\n";
      }
    s << "  </VRTRasterBand>\n";
  }
  s << "</VRTDataset>\n";
  return s.str();
}

std::vector<std::string> write_mosaics(const Graph& graph, const Domain& full, glm::ivec2 counts, TileNaming naming,
                                       const OutputPolicy& policy, std::vector<std::string>& warnings,
                                       const std::set<std::string>& skip_nodes) {
  namespace fs = std::filesystem;
  std::vector<std::string> written;
  std::set<fs::path> taken;
  for (const auto& node : graph.nodes()) {
    const NodeType& type = *node.type;
    if (!type.writes_files || skip_nodes.count(node.id)) continue;
    const bool raster = std::any_of(type.inputs.begin(), type.inputs.end(), [](const PortDecl& p) {
      return p.type == PortType::Heightfield || p.type == PortType::Image;
    });
    if (!raster || type.own_lattice) continue;
    for (const auto& decl : type.params) {
      if (!decl.output_file) continue;
      const auto* path = std::get_if<std::string>(&graph.param(node.id, decl.name));
      if (!path || path->empty()) continue;
      const std::string ext = lower_extension(*path);
      if (ext != ".tif" && ext != ".tiff" && ext != ".png") continue;
      const fs::path vrt = resolve_output_path(policy, fs::path(*path).replace_extension(".vrt").generic_string());
      if (!taken.insert(vrt).second) {
        warnings.push_back("no mosaic for '" + node.id + "': " + vrt.filename().string() + " is another writer's");
        continue;
      }
      std::vector<std::string> tiles;
      for (int j = 0; j < counts.y; ++j)
        for (int i = 0; i < counts.x; ++i)
          tiles.push_back(
              fs::path(with_suffix(*path, tile_suffix(named_tile_index(naming, {i, j}, counts)))).filename().string());
      const fs::path first = vrt.parent_path() / tiles.front();
      std::string error;
      // The tiles were just written, so the codec is loaded already.
      const auto in = image_codec().open_reader(first.string(), error);
      if (!in) {
        warnings.push_back("no mosaic for '" + node.id + "': cannot read " + first.string());
        continue;
      }
      const ImageInfo spec = in->info();
      const std::string data_type = gdal_type(spec.format);
      if (data_type.empty()) {
        warnings.push_back("no mosaic for '" + node.id + "': GDAL's VRT has no type for " + spec.format_text +
                           " samples");
        continue;
      }
      const auto* crs = type.find_param("crs") ? std::get_if<std::string>(&graph.param(node.id, "crs")) : nullptr;
      write_text_atomically(vrt, mosaic_vrt(full, counts, tiles, spec.channels, data_type, crs ? *crs : ""));
      written.push_back(vrt.string());
    }
  }
  return written;
}

}  // namespace orogen::cli
