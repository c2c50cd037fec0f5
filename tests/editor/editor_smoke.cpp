// Smoke test of the real program: under Xvfb with Mesa's software OpenGL, orogen-editor opens an example
// graph, renders frames until its preview is evaluated, saves a screenshot and exits. The screenshot must
// not be blank and must show the graph: node title colours of the example's categories, the canvas, and a
// previewed terrain (many distinct colours in the preview area).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

namespace {

struct Shot {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
};

std::filesystem::path scratch() {
  const auto dir = std::filesystem::path(OROGEN_EDITOR_TEST_SCRATCH) / "editor-smoke";
  std::filesystem::create_directories(dir);
  return dir;
}

Shot take(const std::string& name, const std::string& extra,
          const std::string& graph = std::string(OROGEN_SOURCE_DIR) + "/graphs/terrain.json") {
  const auto dir = scratch();
  const auto png = dir / (name + ".png");
  std::filesystem::remove(png);
  const std::string cmd = "LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1600x900x24\" \"" +
                          std::string(OROGEN_EDITOR_BINARY) + "\" \"" + graph + "\" --screenshot \"" + png.string() +
                          "\" --frames 60 --state-dir \"" + (dir / "state").string() + "\" " + extra + " > \"" +
                          (dir / (name + ".log")).string() + "\" 2>&1";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd << "\nsee " << (dir / (name + ".log"));
  Shot shot;
  auto in = OIIO::ImageInput::open(png.string());
  if (!in) {
    ADD_FAILURE() << "no screenshot at " << png;
    return shot;
  }
  const auto& spec = in->spec();
  shot.width = spec.width;
  shot.height = spec.height;
  shot.rgb.resize(static_cast<std::size_t>(spec.width) * spec.height * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, shot.rgb.data()));
  return shot;
}

// Pixels of exactly this colour (node title bars are flat fills).
std::size_t count_colour(const Shot& s, int r, int g, int b) {
  std::size_t n = 0;
  for (std::size_t k = 0; k + 2 < s.rgb.size(); k += 3) n += s.rgb[k] == r && s.rgb[k + 1] == g && s.rgb[k + 2] == b;
  return n;
}

std::size_t distinct_colours(const Shot& s, int x0, int y0, int x1, int y1) {
  std::set<int> colours;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const unsigned char* p = s.at(x, y);
      colours.insert((p[0] >> 2) << 12 | (p[1] >> 2) << 6 | (p[2] >> 2));
    }
  return colours.size();
}

TEST(EditorSmoke, OverviewShowsTheGraphAndItsPreview) {
  const Shot s = take("overview", "");
  ASSERT_EQ(s.width, 1600);
  ASSERT_EQ(s.height, 900);
  EXPECT_GT(distinct_colours(s, 0, 0, s.width, s.height), 500u) << "not blank";
  // Title bars of the example's node families: noise (purple), field (blue), io (grey).
  EXPECT_GT(count_colour(s, 122, 82, 190), 500u) << "noise node titles";
  EXPECT_GT(count_colour(s, 46, 120, 170), 500u) << "field node titles";
  EXPECT_GT(count_colour(s, 95, 100, 110), 300u) << "io node titles";
  EXPECT_GT(count_colour(s, 30, 32, 36), 100000u) << "canvas background";
  // The preview (right column, top) shows a terrain: hundreds of colours.
  EXPECT_GT(distinct_colours(s, 1100, 100, 1500, 450), 300u) << "previewed terrain";
}

TEST(EditorSmoke, ViewportRendersTheTerrainIn3D) {
  const Shot s = take("viewport", "--view 3d --select elevation");
  ASSERT_EQ(s.width, 1600);
  // Sky around the terrain, and a lit terrain with many shades in the middle of the viewport.
  std::size_t sky = 0;
  for (int y = 90; y < 480; ++y)
    for (int x = 1040; x < 1590; ++x) {
      const unsigned char* p = s.at(x, y);
      sky += std::abs(p[0] - 128) <= 3 && std::abs(p[1] - 153) <= 3 && std::abs(p[2] - 184) <= 3;
    }
  EXPECT_GT(sky, 10000u) << "sky background of the 3D view";
  EXPECT_GT(distinct_colours(s, 1150, 200, 1450, 420), 200u) << "shaded terrain";
}

// WriteScene previewed in 3D draws its class meshes at the points: against the same view of the same graph
// without class meshes and with the classes without one skipped (the terrain alone), many pixels of the
// viewport change.
TEST(EditorSmoke, SceneWriterDrawsItsInstancesOnTheTerrain) {
  const std::string graph = std::string(OROGEN_SOURCE_DIR) + "/graphs/scene.json";
  std::ifstream in(graph);
  std::stringstream text;
  text << in.rdbuf();
  std::string bare = text.str();
  // Drop the class-mesh links and leave out the classes without a mesh.
  const std::string links = R"("mesh_0": "tree.out", "mesh_3": "tree.out", "mesh_4": "rock.out")";
  const auto at = bare.find(links);
  ASSERT_NE(at, std::string::npos) << "graphs/scene.json changed: update this test";
  bare.replace(at - 2, links.size() + 2, "");  // with the ", " before it
  const std::string missing = R"("missing_mesh": "proxy")";
  const auto p = bare.find(missing);
  ASSERT_NE(p, std::string::npos);
  bare.replace(p, missing.size(), R"("missing_mesh": "skip")");
  const auto bare_path = scratch() / "scene-bare.json";
  std::ofstream(bare_path) << bare;

  // The writer (terrain mesh + instances), then the Instance node (instances on the ground upstream).
  for (const char* node : {"write", "instances"}) {
    SCOPED_TRACE(node);
    const std::string view = std::string("--select ") + node + " --view 3d --camera=-30,16,8 --preview-width 860";
    const Shot with = take(std::string("scene-") + node, view, graph);
    const Shot without = take(std::string("scene-bare-") + node, view, bare_path.string());
    ASSERT_EQ(with.width, 1600);
    ASSERT_EQ(without.width, 1600);
    std::size_t changed = 0, total = 0;
    for (int y = 100; y < 480; ++y)
      for (int x = 760; x < 1590; ++x, ++total) {
        const unsigned char *a = with.at(x, y), *b = without.at(x, y);
        changed += std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]) > 30;
      }
    EXPECT_GT(changed, total / 20) << "instances cover a good part of the view";
    EXPECT_LT(changed, total * 3 / 4) << "the terrain is still seen between them";
  }
}

}  // namespace
