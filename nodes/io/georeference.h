#pragma once
// Where a height raster lies on the Earth, for GIS: a GDAL PAM side file (`height.tif` -> `height.tif.aux.xml`)
// with the geotransform of the raster and its coordinate reference system. GDAL, and so QGIS, read it beside
// any raster it opens (GeoTIFF, PNG, EXR), and `gdalinfo` shows it. The world's metres are the CRS's units:
// the domain's origin is a position in the CRS (e.g. UTM eastings and northings).
#include <string>

#include "graph/domain.h"

namespace orogen {

// GDAL's geotransform (x of the left edge, pixel width, 0, y of the top edge, 0, -pixel height) for a raster
// of the domain's samples, north row first, each sample the center of its pixel.
struct GeoTransform {
  double values[6];
};
GeoTransform geotransform_of(const Domain& d);

// The PAM XML: the geotransform and, when `crs` is not empty, the CRS as given ("EPSG:32633", a WKT or PROJ
// string: GDAL interprets it with OGRSpatialReference::SetFromUserInput).
std::string gdal_pam_xml(const Domain& d, const std::string& crs);

// `text` with &, <, > and " as XML entities, for attribute values and element text (the PAM file here, the
// tiled builds' VRT in cli/mosaic.cpp).
std::string xml_escaped(const std::string& text);

}  // namespace orogen
