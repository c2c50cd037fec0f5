// WriteControlMap: splat weights as Terrain3D's (Godot 4) bit-packed control map. The words are checked against
// the format's documented bit layout, against a brute-force choice of the two heaviest layers, and end to end
// through the file: the EXR's floats must carry the words' bits unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include <OpenImageIO/imageio.h>

#include "nodes/io/control_map.h"
#include "evaluator/run_node.h"
#include "graph/output_path.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

struct Fields {
  unsigned base, overlay, blend;
  bool hole, navigation, autoshader;
};

// Decoding as Terrain3D's shader does (its documented decode column).
Fields decode(std::uint32_t x) {
  return {x >> 27 & 0x1Fu, x >> 22 & 0x1Fu, x >> 14 & 0xFFu, (x >> 2 & 1u) != 0, (x >> 1 & 1u) != 0, (x & 1u) != 0};
}

TEST(ControlMap, WordsFollowTheDocumentedBitLayout) {
  EXPECT_EQ(encode_control(0, 0, 0, false, false, false), 0u);
  EXPECT_EQ(encode_control(31, 0, 0, false, false, false), 0xF8000000u);
  EXPECT_EQ(encode_control(0, 31, 0, false, false, false), 0x07C00000u);
  EXPECT_EQ(encode_control(0, 0, 255, false, false, false), 0x003FC000u);
  EXPECT_EQ(encode_control(0, 0, 0, true, false, false), 4u);
  EXPECT_EQ(encode_control(0, 0, 0, false, true, false), 2u);
  EXPECT_EQ(encode_control(0, 0, 0, false, false, true), 1u);
  EXPECT_EQ(encode_control(3, 1, 128, false, true, false), (3u << 27) | (1u << 22) | (128u << 14) | 2u);
  // Fields never spill into each other.
  const auto f = decode(encode_control(21, 9, 200, true, false, true));
  EXPECT_EQ(f.base, 21u);
  EXPECT_EQ(f.overlay, 9u);
  EXPECT_EQ(f.blend, 200u);
  EXPECT_TRUE(f.hole);
  EXPECT_FALSE(f.navigation);
  EXPECT_TRUE(f.autoshader);
}

// Against a brute force: sort the layers by weight (ties to the lower layer), take the first two.
TEST(ControlMap, BaseAndOverlayAreTheTwoHeaviestLayersAndBlendTheOverlaysShare) {
  for (const int layers : {1, 2, 3, 5, 8, 32}) {
    SCOPED_TRACE(layers);
    Image w(Domain::from_extent({0, 0}, {100, 100}, {23, 23}), layers);
    std::mt19937 rng(7u + static_cast<unsigned>(layers));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& v : w.data) v = u(rng) < 0.4f ? 0.0f : std::floor(u(rng) * 8.0f) / 2.0f;  // zeros and ties
    for (int c = 0; c < layers; ++c) w.data[c] = 0.0f;  // one sample without any weight
    const auto words = control_words(w, {.navigation = true, .autoshader = false});
    ASSERT_EQ(words.size(), w.domain.sample_count());
    int blended = 0;
    for (std::size_t s = 0; s < words.size(); ++s) {
      const float* v = w.data.data() + s * static_cast<std::size_t>(layers);
      std::vector<int> order(static_cast<std::size_t>(layers));
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return v[a] > v[b]; });
      const auto f = decode(words[s]);
      EXPECT_TRUE(f.navigation);
      EXPECT_FALSE(f.autoshader || f.hole);
      if (!(v[order[0]] > 0.0f)) {
        EXPECT_EQ(f.base, 0u) << s;
        EXPECT_EQ(f.overlay, 0u) << s;
        EXPECT_EQ(f.blend, 0u) << s;
        continue;
      }
      ASSERT_EQ(f.base, static_cast<unsigned>(order[0])) << "sample " << s;
      if (layers == 1 || !(v[order[1]] > 0.0f)) {
        EXPECT_EQ(f.overlay, f.base) << s;
        EXPECT_EQ(f.blend, 0u) << s;
        continue;
      }
      ASSERT_EQ(f.overlay, static_cast<unsigned>(order[1])) << "sample " << s;
      const double share = v[order[1]] / (static_cast<double>(v[order[0]]) + v[order[1]]);
      EXPECT_LE(std::abs(f.blend - 255.0 * share), 0.5) << "sample " << s;
      EXPECT_LE(f.blend, 128u);
      blended += f.blend > 0;
    }
    if (layers > 1) {
      EXPECT_GT(blended, 0);
    }
  }
}

TEST(ControlMap, MoreThan32LayersOrBadWeightsAreRefused) {
  EXPECT_THROW(control_words(Image(Domain::from_extent({0, 0}, {1, 1}, {2, 2}), 33, 1.0f), {}), std::invalid_argument);
  for (float bad : {-0.5f, NAN, INFINITY}) {
    Image w(Domain::from_extent({0, 0}, {1, 1}, {3, 3}), 2, 0.5f);
    w.data[4 * 2 + 1] = bad;
    try {
      control_words(w, {});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("layer 1 at sample 4"), std::string::npos) << e.what();
    }
  }
}

// End to end: SplatWeights' layers of a noise terrain through the node; the EXR read back as raw floats carries
// the words the function computes from the same weights, bit for bit.
TEST(ControlMap, TheNodeWritesTheWordsBitForBit) {
  const Domain domain = Domain::from_extent({0, 0}, {2000, 2000}, {65, 65});
  const auto height =
      run_node("FBM", domain, {{"feature_size", 600.0}, {"amplitude", 300.0}, {"seed", std::uint64_t{2}}});
  const auto splat = run_node("SplatWeights", domain, {}, {{"in", height.outputs[0]}}).get<Image>();
  ASSERT_EQ(splat->channels, 5);  // SplatWeights' default table
  OutputPolicy policy;
  policy.output_dir = scratch_dir("control-map") / "out";
  run_node("WriteControlMap", domain, {{"path", std::string("godot/control.exr")}, {"autoshader", true}},
           {{"in", PortValue(splat)}}, policy);

  auto in = OIIO::ImageInput::open((policy.output_dir / "godot" / "control.exr").string());
  ASSERT_TRUE(in);
  const auto& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 1);
  EXPECT_EQ(spec.channelnames, std::vector<std::string>{"R"});
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  ASSERT_EQ(spec.width, 65);
  ASSERT_EQ(spec.height, 65);
  std::vector<float> file(65 * 65);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, file.data()));

  const auto expected = control_words(*splat, {.navigation = false, .autoshader = true});
  std::set<unsigned> bases;
  for (int row = 0; row < 65; ++row)
    for (int i = 0; i < 65; ++i) {
      const std::size_t s = static_cast<std::size_t>(64 - row) * 65 + i;  // the file's first row is north
      ASSERT_EQ(std::bit_cast<std::uint32_t>(file[static_cast<std::size_t>(row) * 65 + i]), expected[s])
          << "row " << row << " column " << i;
      bases.insert(decode(expected[s]).base);
    }
  EXPECT_GT(bases.size(), 1u) << "more than one layer is the base somewhere";
}

}  // namespace
}  // namespace orogen::test
