#include "cli/tiled_vrt.h"

#include <sstream>

#include "nodes/io/georeference.h"

namespace orogen::cli {

std::string tiled_vrt_xml(const Domain& domain, const std::vector<VrtTile>& tiles, const std::string& data_type,
                          const std::string& crs) {
  const int width = domain.width(), height = domain.height();
  const GeoTransform g = geotransform_of(domain);
  std::ostringstream x;
  x.precision(17);
  x << "<VRTDataset rasterXSize=\"" << width << "\" rasterYSize=\"" << height << "\">\n";
  if (!crs.empty()) x << "  <SRS>" << crs << "</SRS>\n";
  x << "  <GeoTransform>" << g.values[0] << ", " << g.values[1] << ", " << g.values[2] << ", " << g.values[3] << ", "
    << g.values[4] << ", " << g.values[5] << "</GeoTransform>\n";
  x << "  <VRTRasterBand dataType=\"" << data_type << "\" band=\"1\">\n";
  for (const auto& t : tiles) {
    // The tile's northern row is the whole domain's row (height - 1) - (first.y + size.y - 1), counted from
    // the north.
    const int top = height - (t.first.y + t.size.y);
    x << "    <SimpleSource>\n"
      << "      <SourceFilename relativeToVRT=\"" << (t.file.is_relative() ? 1 : 0) << "\">" << t.file.string()
      << "</SourceFilename>\n"
      << "      <SourceBand>1</SourceBand>\n"
      << "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"" << t.size.x << "\" ySize=\"" << t.size.y << "\"/>\n"
      << "      <DstRect xOff=\"" << t.first.x << "\" yOff=\"" << top << "\" xSize=\"" << t.size.x << "\" ySize=\""
      << t.size.y << "\"/>\n"
      << "    </SimpleSource>\n";
  }
  x << "  </VRTRasterBand>\n</VRTDataset>\n";
  return x.str();
}

}  // namespace orogen::cli
