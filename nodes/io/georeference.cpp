#include "nodes/io/georeference.h"

#include <cstdio>

namespace orogen {

GeoTransform geotransform_of(const Domain& d) {
  const double left = d.x(0) - 0.5 * d.spacing.x;
  const double top = d.y(d.height() - 1) + 0.5 * d.spacing.y;
  return {{left, d.spacing.x, 0.0, top, 0.0, -d.spacing.y}};
}

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string gdal_pam_xml(const Domain& d, const std::string& crs) {
  const GeoTransform g = geotransform_of(d);
  char transform[256];
  std::snprintf(transform, sizeof transform, "%.17g, %.17g, %.17g, %.17g, %.17g, %.17g", g.values[0], g.values[1],
                g.values[2], g.values[3], g.values[4], g.values[5]);
  std::string xml = "<PAMDataset>\n";
  if (!crs.empty()) xml += "  <SRS>" + xml_escaped(crs) + "</SRS>\n";
  xml += "  <GeoTransform>" + std::string(transform) + "</GeoTransform>\n";
  xml += "</PAMDataset>\n";
  return xml;
}

}  // namespace orogen
