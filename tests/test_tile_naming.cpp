// --tile-naming (issue 28, defect 2): the tiles of a build stitched back as an engine stitches them, from the
// file names alone, give the untiled build. unreal: _x0_y0 is the top-left tile and rows count down (Unreal's
// tiled landscape import, World Machine); orogen: rows count up from the south.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

// 33 x 49 samples in 2 x 3 tiles: rows of 17 samples, sharing their border rows.
const char* kGraph = R"({
  "format": "orogen-graph", "version": 5,
  "domain": {"origin": [0, 0], "size": [640, 960], "resolution": [33, 49]},
  "nodes": [
    {"id": "noise", "type": "FBM", "params": {"feature_size": 300, "amplitude": 100, "seed": 4}},
    {"id": "save", "type": "WriteHeightfield", "inputs": {"in": "noise.out"}, "params": {"path": "h.exr"}}
  ]
})";

// An image as stored: file row 0 (north) first.
struct Stored {
  int width = 0, height = 0;
  std::vector<float> px;
  float at(int x, int r) const { return px[static_cast<std::size_t>(r) * width + x]; }
};

Stored read(const fs::path& p) {
  Stored s;
  auto in = OIIO::ImageInput::open(p.string());
  EXPECT_TRUE(in) << p;
  if (!in) return s;
  s.width = in->spec().width, s.height = in->spec().height;
  s.px.resize(static_cast<std::size_t>(s.width) * s.height);
  EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, s.px.data()));
  return s;
}

// Stitches h_x<I>_y<J>.exr tiles sharing their borders: `y_down` places _y0 at the top (rows counting down),
// else at the bottom.
Stored stitch(const fs::path& dir, int nx, int ny, bool y_down) {
  std::vector<std::vector<Stored>> tiles(ny, std::vector<Stored>(nx));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      tiles[j][i] = read(dir / ("h_x" + std::to_string(i) + "_y" + std::to_string(j) + ".exr"));
  // Top to bottom in the picture: the named rows in order (y_down) or reversed.
  std::vector<int> order;
  for (int k = 0; k < ny; ++k) order.push_back(y_down ? k : ny - 1 - k);
  Stored out;
  for (int i = 0; i < nx; ++i) out.width += tiles[0][i].width - (i ? 1 : 0);
  for (int j : order) out.height += tiles[j][0].height - (out.height ? 1 : 0);
  out.px.assign(static_cast<std::size_t>(out.width) * out.height, NAN);
  int top = 0;
  for (int j : order) {
    int left = 0;
    for (int i = 0; i < nx; ++i) {
      const Stored& t = tiles[j][i];
      for (int r = 0; r < t.height; ++r)
        for (int x = 0; x < t.width; ++x) out.px[static_cast<std::size_t>(top + r) * out.width + left + x] = t.at(x, r);
      left += t.width - 1;
    }
    top += tiles[j][0].height - 1;
  }
  return out;
}

TEST(TileNaming, StitchedByTheirNamesTheTilesGiveTheUntiledBuild) {
  const auto dir = scratch_dir("tile-naming");
  write_text(dir / "g.json", kGraph);
  const auto whole = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", (dir / "w").string()});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const Stored expected = read(dir / "w" / "h.exr");
  for (const std::string naming : {"unreal", "orogen"}) {
    SCOPED_TRACE(naming);
    const auto out = dir / naming;
    const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", out.string(), "--tiles",
                                              "2x3", "--tile-naming", naming});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Stored got = stitch(out, 2, 3, naming == "unreal");
    ASSERT_EQ(got.width, expected.width);
    ASSERT_EQ(got.height, expected.height);
    EXPECT_EQ(std::memcmp(got.px.data(), expected.px.data(), got.px.size() * sizeof(float)), 0);
    // Stitched the other way, rows come out of order: the naming is what the test checks.
    const Stored wrong = stitch(out, 2, 3, naming != "unreal");
    EXPECT_NE(std::memcmp(wrong.px.data(), expected.px.data(), got.px.size() * sizeof(float)), 0);
  }
}

TEST(TileNaming, OneTileIsPickedByItsName) {
  const auto dir = scratch_dir("tile-naming-one");
  write_text(dir / "g.json", kGraph);
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", (dir / "o").string(),
                                            "--tiles", "2x3", "--tile", "1,0", "--tile-naming", "unreal"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir / "o" / "h_x1_y0.exr"));
  const auto all = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", (dir / "a").string(),
                                              "--tiles", "2x3", "--tile-naming", "unreal"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const Stored one = read(dir / "o" / "h_x1_y0.exr"), same = read(dir / "a" / "h_x1_y0.exr");
  EXPECT_EQ(one.px, same.px);
}

TEST(TileNaming, UnknownNamingIsRefused) {
  const auto dir = scratch_dir("tile-naming-bad");
  write_text(dir / "g.json", kGraph);
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "o").string(), "--tiles",
                                            "2x2", "--tile-naming", "worldmachine"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--tile-naming 'worldmachine': expected 'orogen' or 'unreal'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
}

}  // namespace
}  // namespace orogen::test
