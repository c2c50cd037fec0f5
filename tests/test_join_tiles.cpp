// The joining of the tiles' points and curves files under --merge (cli/join_tiles.h): curves renumbered so
// that parents still name their curves, points on a shared line of samples kept once, and tiles that do not
// match refused by name.
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "cli/join_tiles.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

fs::path put(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string text_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(JoinTiles, CurvesJsonRenumbersIndicesAndParents) {
  const fs::path dir = scratch_dir("join_curves_json");
  const auto feature = [](int index, int parent, const char* xy) {
    return std::string("{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[") + xy +
           "]},\"properties\":{\"index\":" + std::to_string(index) + ",\"parent\":" + std::to_string(parent) +
           ",\"width\":[1,2]}}";
  };
  const std::string open = "{\"type\":\"FeatureCollection\",\"features\":[";
  const auto a = put(dir / "a.json", open + "\n" + feature(0, -1, "[0,0,1],[1,0,1]") + ",\n" +
                                         feature(1, 0, "[1,0,1],[2,0,1]") + "\n]}\n");
  const auto empty = put(dir / "e.json", open + "\n]}\n");
  const auto b =
      put(dir / "b.json", open + "\n" + feature(0, -1, "[5,0,1],[6,0,1]") + ",\n" + feature(1, 0, "[6,0,1],[7,0,1]") +
                              ",\n" + feature(2, 1, "[7,0,1],[8,0,1]") + "\n]}\n");
  cli::join_curves_json({a, empty, b}, dir / "joined.json");
  EXPECT_EQ(text_of(dir / "joined.json"),
            open + "\n" + feature(0, -1, "[0,0,1],[1,0,1]") + ",\n" + feature(1, 0, "[1,0,1],[2,0,1]") + ",\n" +
                feature(2, -1, "[5,0,1],[6,0,1]") + ",\n" + feature(3, 2, "[6,0,1],[7,0,1]") + ",\n" +
                feature(4, 3, "[7,0,1],[8,0,1]") + "\n]}\n");
  const auto broken = put(dir / "broken.json", open + "\n{\"type\":\"Feature\"}\n]}\n");
  try {
    cli::join_curves_json({a, broken}, dir / "never.json");
    ADD_FAILURE() << "a feature without its index was joined";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos) << e.what();
  }
}

TEST(JoinTiles, CurvesObjMovesGroupsParentsAndVertexNumbers) {
  const fs::path dir = scratch_dir("join_curves_obj");
  const auto a = put(dir / "a.obj",
                     "# Orogen curves: 1 polylines, world metres, z up\ng curve_0\n# parent 0 -1\nv 0 0 1\nv 1 0 1\n"
                     "# attr width 1 2\nl 1 2\n");
  const auto b = put(dir / "b.obj",
                     "# Orogen curves: 2 polylines, world metres, z up\ng curve_0\n# parent 0 -1\nv 5 0 1\nv 6 0 1\n"
                     "# attr width 1 2\nl 1 2\ng curve_1\n# parent 1 0\nv 6 0 1\nv 7 0 1\nv 8 0 1\n"
                     "# attr width 1 2 3\nl 3 4 5\n");
  cli::join_curves_obj({a, b}, dir / "joined.obj");
  EXPECT_EQ(text_of(dir / "joined.obj"),
            "# Orogen curves: 3 polylines, world metres, z up\ng curve_0\n# parent 0 -1\nv 0 0 1\nv 1 0 1\n"
            "# attr width 1 2\nl 1 2\ng curve_1\n# parent 1 -1\nv 5 0 1\nv 6 0 1\n# attr width 1 2\nl 3 4\n"
            "g curve_2\n# parent 2 1\nv 6 0 1\nv 7 0 1\nv 8 0 1\n# attr width 1 2 3\nl 5 6 7\n");
}

TEST(JoinTiles, PointsOnASharedLineOfSamplesAreKeptOnce) {
  const fs::path dir = scratch_dir("join_points");
  const std::string header = "x,y,z,class\n";
  // Tiles share the line x = 50: the point (50, 7) is in both; (50.5, 7) and the second (10, 3) are not on it,
  // so they stay (two tiles cannot both hold a point off their shared line).
  const auto a = put(dir / "a.csv", header + "10,3,1,0\n50,7,2,0\n10,3,1,0\n");
  const auto b = put(dir / "b.csv", header + "50,7,2,0\n50.5,7,2,1\n");
  cli::join_points_csv({a, b}, dir / "joined.csv", {50.0}, {});
  EXPECT_EQ(text_of(dir / "joined.csv"), header + "10,3,1,0\n50,7,2,0\n10,3,1,0\n50.5,7,2,1\n");

  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex ";
  const std::string ply_props = "\nproperty float x\nproperty float y\nend_header\n";
  const auto pa = put(dir / "a.ply", ply_head + "2" + ply_props + "1 20\n3 20\n");
  const auto pb = put(dir / "b.ply", ply_head + "2" + ply_props + "3 20\n4 21\n");
  cli::join_points_ply({pa, pb}, dir / "joined.ply", {}, {20.0});
  EXPECT_EQ(text_of(dir / "joined.ply"), ply_head + "3" + ply_props + "1 20\n3 20\n4 21\n");

  const auto other = put(dir / "other.csv", "x,y,z,class,radius\n1,1,1,0,3\n");
  try {
    cli::join_points_csv({a, other}, dir / "never.csv", {}, {});
    ADD_FAILURE() << "tiles with other columns were joined";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("other.csv has other columns"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "never.csv"));
}

}  // namespace
}  // namespace orogen::test
