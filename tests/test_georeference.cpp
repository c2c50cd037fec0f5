// GIS hand-off (issue 28): WriteHeightfield's crs writes a GDAL side file, so gdalinfo and QGIS place the
// raster where the graph's domain says, north up, each sample the center of its pixel.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <OpenImageIO/imageio.h>

#include "nodes/io/georeference.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

TEST(Georeference, TheGeotransformPutsEachSampleAtItsPixelCenter) {
  const Domain d = Domain::from_extent({500000, 4649000}, {1000, 500}, {101, 51});
  const GeoTransform g = geotransform_of(d);
  EXPECT_DOUBLE_EQ(g.values[0], 499995.0);  // left edge: half a cell west of the first sample
  EXPECT_DOUBLE_EQ(g.values[1], 10.0);
  EXPECT_DOUBLE_EQ(g.values[3], 4649505.0);  // top edge: half a cell north of the northern row
  EXPECT_DOUBLE_EQ(g.values[5], -10.0);
  EXPECT_NE(gdal_pam_xml(d, "EPSG:32633").find("<SRS>EPSG:32633</SRS>"), std::string::npos);
  EXPECT_EQ(gdal_pam_xml(d, "").find("<SRS>"), std::string::npos);
  // A WKT or PROJ string may hold XML's special characters; the side file stays well formed.
  EXPECT_EQ(xml_escaped(R"(a<b>&"c")"), "a&lt;b&gt;&amp;&quot;c&quot;");
  EXPECT_NE(gdal_pam_xml(d, "+proj=x <y>").find("<SRS>+proj=x &lt;y&gt;</SRS>"), std::string::npos);
}

TEST(Georeference, GdalPlacesTheHeightsWhereTheDomainSays) {
  if (std::system("command -v gdallocationinfo > /dev/null 2>&1") != 0) GTEST_SKIP() << "gdal-bin is not installed";
  const auto dir = scratch_dir("georeference");
  write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 5,
    "domain": {"origin": [500000, 4649000], "size": [1000, 1000], "resolution": [101, 101]},
    "nodes": [{"id": "noise", "type": "FBM", "params": {"amplitude": 200}},
              {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"},
               "params": {"path": "h.tif", "crs": "EPSG:32633"}}]})");
  const auto e = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", dir.string()});
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const auto info = run_process("/usr/bin/env", {"gdalinfo", (dir / "h.tif").string()});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("UTM zone 33N"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("Origin = (499995.000000000000000,4650005.000000000000000)"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("Pixel Size = (10.000000000000000,-10.000000000000000)"), std::string::npos) << info.out;
  // The sample at x = 500100, y = 4649800 (i = 10, j = 80) is file row 100 - 80 = 20, column 10.
  auto in = OIIO::ImageInput::open((dir / "h.tif").string());
  ASSERT_TRUE(in);
  std::vector<float> px(101 * 101);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, px.data()));
  const auto at = run_process(
      "/usr/bin/env", {"gdallocationinfo", "-valonly", "-geoloc", (dir / "h.tif").string(), "500100", "4649800"});
  ASSERT_EQ(at.exit_code, 0) << at.err;
  EXPECT_NEAR(std::stod(at.out), px[20 * 101 + 10], 1e-3) << at.out;
}

// A tiled build's VRT, flattened by GDAL, is the untiled build: QGIS opens the tiled world as one layer.
TEST(Georeference, TheTilesVrtIsTheWholeRaster) {
  if (std::system("command -v gdal_translate > /dev/null 2>&1") != 0) GTEST_SKIP() << "gdal-bin is not installed";
  const auto dir = scratch_dir("tiled-vrt");
  write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 5,
    "domain": {"origin": [500000, 4649000], "size": [800, 1000], "resolution": [81, 101]},
    "nodes": [{"id": "noise", "type": "FBM", "params": {"amplitude": 200}},
              {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"},
               "params": {"path": "maps/h.tif", "crs": "EPSG:32633"}}]})");
  auto read = [](const std::filesystem::path& p) {
    auto in = OIIO::ImageInput::open(p.string());
    EXPECT_TRUE(in) << p;
    std::vector<float> px(in ? static_cast<std::size_t>(in->spec().width) * in->spec().height : 0);
    if (in) EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, px.data()));
    return px;
  };
  const auto whole = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", (dir / "w").string()});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  for (const std::string naming : {"orogen", "unreal"}) {
    SCOPED_TRACE(naming);
    const auto out = dir / naming;
    const auto e = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", out.string(), "--tiles",
                                              "3x2", "--tile-naming", naming});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    ASSERT_TRUE(std::filesystem::exists(out / "maps" / "h.vrt"));
    const auto t = run_process("/usr/bin/env", {"gdal_translate", "-q", "-of", "GTiff",
                                                (out / "maps" / "h.vrt").string(), (out / "flat.tif").string()});
    ASSERT_EQ(t.exit_code, 0) << t.err;
    EXPECT_EQ(read(out / "flat.tif"), read(dir / "w" / "maps" / "h.tif"));
  }
}

}  // namespace
}  // namespace orogen::test
