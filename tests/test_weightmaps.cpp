// WriteWeightmaps: splat weights as 8-bit grayscale maps, one per layer, summing to exactly 255 per sample
// (Unreal Engine's weight-blended paint layers), read back from the files as an engine would.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "nodes/io/heightfield_file.h"
#include "nodes/io/weightmaps.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

Image random_weights(int side, int layers, unsigned seed) {
  Image img(Domain::from_extent({0, 0}, {100, 100}, {side, side}), layers);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& w : img.data) w = u(rng) < 0.3f ? 0.0f : u(rng) * 7.0f;  // zeros, any sum
  for (int c = 0; c < layers; ++c) img.data[c] = 0.0f;                 // and one sample with no weight at all
  return img;
}

int code(const Image& layer, std::size_t s) { return static_cast<int>(std::lround(layer.data[s] * 255.0f)); }

TEST(Weightmaps, CodesSumTo255AndEachIsWithinOneOfItsShare) {
  for (int layers : {1, 2, 3, 5, 8, 13}) {
    SCOPED_TRACE(layers);
    const Image w = random_weights(37, layers, 11u + static_cast<unsigned>(layers));
    const auto maps = weightmap_layers(w);
    ASSERT_EQ(maps.size(), static_cast<std::size_t>(layers));
    std::size_t empty = 0;
    for (std::size_t s = 0; s < w.domain.sample_count(); ++s) {
      const float* v = w.data.data() + s * layers;
      double sum = 0;
      for (int c = 0; c < layers; ++c) sum += v[c];
      int total = 0;
      for (int c = 0; c < layers; ++c) {
        const int k = code(maps[c], s);
        ASSERT_EQ(static_cast<float>(k) / 255.0f, maps[c].data[s]) << "not an exact 8-bit code";
        total += k;
        if (sum > 0) {
          EXPECT_LT(std::abs(k - 255.0 * v[c] / sum), 1.0) << "layer " << c << " sample " << s;
        }
      }
      if (sum > 0) {
        EXPECT_EQ(total, 255) << "sample " << s;
      } else {
        EXPECT_EQ(total, 0) << "sample " << s;
        ++empty;
      }
    }
    EXPECT_GT(empty, 0u);  // the all-zero case was exercised
  }
}

TEST(Weightmaps, ExactSharesAreKeptAndTiesGoToTheLowerLayer) {
  Image w(Domain::from_extent({0, 0}, {1, 1}, {2, 2}), 3);
  const float samples[4][3] = {{1, 0, 0}, {1, 1, 1}, {0, 2, 2}, {51, 102, 102}};
  for (int s = 0; s < 4; ++s)
    for (int c = 0; c < 3; ++c) w.data[s * 3 + c] = samples[s][c];
  const auto maps = weightmap_layers(w);
  const int expected[4][3] = {{255, 0, 0}, {85, 85, 85}, {0, 128, 127}, {51, 102, 102}};
  for (int s = 0; s < 4; ++s)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(code(maps[c], s), expected[s][c]) << "sample " << s << " layer " << c;
}

TEST(Weightmaps, NegativeOrNonFiniteWeightsAreRefusedNamingLayerAndSample) {
  for (float bad : {-0.5f, NAN, INFINITY}) {
    Image w(Domain::from_extent({0, 0}, {1, 1}, {3, 3}), 2, 0.5f);
    w.data[4 * 2 + 1] = bad;
    try {
      weightmap_layers(w);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("layer 1 at sample 4"), std::string::npos) << e.what();
    }
  }
}

TEST(Weightmaps, LayerNamesAreFileSafeUniqueAndNeverEmpty) {
  Image w(Domain::from_extent({0, 0}, {1, 1}, {2, 2}), 5);
  w.channel_names = {"rock", "wet sand", "", "rock", "gr/ass"};
  EXPECT_EQ(weightmap_layer_names(w), (std::vector<std::string>{"rock", "wet_sand", "layer2", "rock_2", "gr_ass"}));
  w.channel_names.clear();
  EXPECT_EQ(weightmap_layer_names(w).front(), "layer0");
}

// The node end to end: SplatWeights' layers written by the CLI, read back as files, one map per layer named in
// the list, summing to 255 everywhere.
TEST(Weightmaps, TheNodeWritesOneMapPerLayerAndItsList) {
  const auto dir = scratch_dir("weightmaps");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [2000, 2000], "resolution": [65, 65] },
  "nodes": [
    { "id": "height", "type": "FBM", "params": { "feature_size": 600, "amplitude": 300, "seed": 2 } },
    { "id": "splat", "type": "SplatWeights", "inputs": { "in": "height.out" } },
    { "id": "maps", "type": "WriteWeightmaps", "inputs": { "in": "splat.out" },
      "params": { "path": "unreal/paint.json" } }
  ]
})");
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto list = nlohmann::json::parse(read_text(dir / "out" / "unreal" / "paint.json"));
  EXPECT_EQ(list["sum"], 255);
  const auto& layers = list["layers"];
  ASSERT_EQ(layers.size(), 5u);  // SplatWeights' default table
  std::vector<HeightRaster> maps;
  std::set<std::string> names;
  for (const auto& layer : layers) {
    const std::string file = layer["file"];
    EXPECT_EQ(file, "paint_" + layer["name"].get<std::string>() + ".png");
    names.insert(layer["name"].get<std::string>());
    maps.push_back(read_height_raster(dir / "out" / "unreal" / file));
    EXPECT_EQ(maps.back().channels, 1);
    EXPECT_EQ(maps.back().format, "uint8");
    EXPECT_EQ(maps.back().width, 65);
  }
  EXPECT_EQ(names.size(), layers.size());
  std::set<int> used;  // more than one layer is painted somewhere
  for (std::size_t s = 0; s < maps[0].values.size(); ++s) {
    int total = 0;
    for (std::size_t c = 0; c < maps.size(); ++c) {
      const int k = static_cast<int>(std::lround(maps[c].values[s] * 255.0));
      total += k;
      if (k > 0) used.insert(static_cast<int>(c));
    }
    ASSERT_EQ(total, 255) << "sample " << s;
  }
  EXPECT_GT(used.size(), 1u);
}

// Negative weights (here a normal map's signed components) are refused with the node and the sample named, and
// nothing is written.
TEST(Weightmaps, NegativeWeightsFailTheNodeAndWriteNothing) {
  const auto dir = scratch_dir("weightmaps-bad");
  write_text(dir / "g.json", R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [1000, 1000], "resolution": [17, 17] },
  "nodes": [
    { "id": "h", "type": "FBM", "params": { "feature_size": 300, "amplitude": 100 } },
    { "id": "n", "type": "Normals", "inputs": { "in": "h.out" } },
    { "id": "maps", "type": "WriteWeightmaps", "inputs": { "in": "n.out" } }
  ]
})");
  const auto r = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("maps"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("must be finite and >= 0"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "weightmaps"));
}

}  // namespace
}  // namespace orogen::test
