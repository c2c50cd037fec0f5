// Fuzzy search of the node palette: typed names, abbreviations, categories and descriptions rank the
// expected type first.
#include <gtest/gtest.h>

#include "editor/model/fuzzy_match.h"
#include "editor/model/palette.h"
#include "editor/model/text_summary.h"

namespace orogen::editor {
namespace {

NodeType make(std::string name, std::string category, std::string description) {
  NodeType t;
  t.name = std::move(name);
  t.category = std::move(category);
  t.description = std::move(description);
  return t;
}

class PaletteTest : public ::testing::Test {
 protected:
  std::vector<NodeType> storage{
      make("Perlin", "noise", "Gradient noise on a lattice."),
      make("PerlinWarp", "noise", "Perlin noise domain warp."),
      make("FBM", "noise", "Fractal Brownian motion: octaves of a basis noise."),
      make("HydraulicErosion", "erosion", "Pipe-model water erosion after Mei et al."),
      make("ThermalErosion", "erosion", "Talus-angle slumping of steep slopes."),
      make("Constant", "field", "A flat field: every sample has the same value."),
      make("WriteHeightfield", "io", "Writes a heightfield to EXR, PNG, RAW or TIFF."),
      make("ReadHeightfield", "io", "Reads a heightfield file."),
      make("Worley", "noise", "Cellular noise: distances to feature points."),
  };
  std::vector<const NodeType*> types() const {
    std::vector<const NodeType*> out;
    for (const auto& t : storage) out.push_back(&t);
    return out;
  }
  std::string first(std::string_view q) const {
    auto r = search_palette(q, types());
    return r.empty() ? "" : r.front().type->name;
  }
};

TEST(FuzzyMatch, SubsequenceRequiredAndPositionsReported) {
  EXPECT_FALSE(fuzzy_match("xyz", "Perlin"));
  auto m = fuzzy_match("hyer", "HydraulicErosion");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->positions, (std::vector<int>{0, 1, 9, 10}));  // "Hy" then the "Er" of the second word
}

TEST(FuzzyMatch, WordStartsAndRunsScoreHigher) {
  EXPECT_GT(fuzzy_match("er", "HydraulicErosion")->score, fuzzy_match("er", "Perlin")->score);
  EXPECT_GT(fuzzy_match("per", "Perlin")->score, fuzzy_match("per", "SuperWarp")->score);
}

TEST_F(PaletteTest, ExactAndPrefixNamesComeFirst) {
  EXPECT_EQ(first("perlin"), "Perlin");
  EXPECT_EQ(first("Perl"), "Perlin");
  EXPECT_EQ(first("fbm"), "FBM");
  EXPECT_EQ(first("worley"), "Worley");
}

TEST_F(PaletteTest, AbbreviationsAndCamelHumps) {
  EXPECT_EQ(first("hyd"), "HydraulicErosion");
  EXPECT_EQ(first("therm ero"), "ThermalErosion");
  EXPECT_EQ(first("wh"), "WriteHeightfield");
  EXPECT_EQ(first("rh"), "ReadHeightfield");
}

TEST_F(PaletteTest, CategoriesAndDescriptionsMatchToo) {
  const auto erosion = search_palette("erosion", types());
  ASSERT_GE(erosion.size(), 2u);
  EXPECT_EQ(erosion[0].type->category, "erosion");
  EXPECT_EQ(erosion[1].type->category, "erosion");
  EXPECT_EQ(first("flat"), "Constant");  // only its description says "flat"
  EXPECT_EQ(first("cellular"), "Worley");
  EXPECT_TRUE(search_palette("zzzz", types()).empty());
}

TEST_F(PaletteTest, EmptyQueryListsEverythingByCategory) {
  const auto all = search_palette("", types());
  ASSERT_EQ(all.size(), storage.size());
  for (std::size_t k = 1; k < all.size(); ++k) EXPECT_LE(all[k - 1].type->category, all[k].type->category);
}

TEST_F(PaletteTest, StateTypesBackspacesAndHighlights) {
  PaletteState p(types());
  p.type_text("hyd");
  ASSERT_NE(p.choice(), nullptr);
  EXPECT_EQ(p.choice()->name, "HydraulicErosion");
  p.backspace();
  p.backspace();
  p.backspace();
  EXPECT_EQ(p.query(), "");
  EXPECT_EQ(p.results().size(), storage.size());
  p.move_highlight(+100);
  EXPECT_EQ(p.highlighted(), static_cast<int>(storage.size()) - 1);
  p.move_highlight(-1000);
  EXPECT_EQ(p.highlighted(), 0);
}

TEST_F(PaletteTest, TheHighlightStaysOnTheChosenTypeAsTheFilterNarrows) {
  PaletteState p(types());
  p.type_text("er");
  const auto index_of = [&p](std::string_view name) {
    for (std::size_t k = 0; k < p.results().size(); ++k)
      if (p.results()[k].type->name == name) return static_cast<int>(k);
    return -1;
  };
  // Of the two erosions, the one that is not the best match of "er" (else the test proves nothing).
  const std::string other = index_of("ThermalErosion") > 0 ? "ThermalErosion" : "HydraulicErosion";
  const std::string best = other == "ThermalErosion" ? "HydraulicErosion" : "ThermalErosion";
  ASSERT_GT(index_of(other), 0);
  p.set_highlight(index_of(other));  // the user moved to it (arrows or pointer)
  p.type_text("o");
  ASSERT_GT(index_of(other), 0);
  ASSERT_NE(p.choice(), nullptr);
  EXPECT_EQ(p.choice()->name, other) << "typing on does not take the highlight away";
  EXPECT_EQ(p.highlighted(), index_of(other));
  p.set_query(best);  // it no longer matches: the best match is highlighted, and the choice is forgotten
  EXPECT_EQ(p.choice()->name, best);
  p.set_query("ero");
  EXPECT_EQ(p.highlighted(), 0);

  PaletteState q(types());  // without a move of the user's, the highlight follows the best match
  q.type_text("ther");
  q.type_text("m");
  EXPECT_EQ(q.highlighted(), 0);
  EXPECT_EQ(q.choice()->name, "ThermalErosion");
}

TEST(TextSummary, WrapsAtSpacesWithinTheWidth) {
  const TextMeasure chars = [](std::string_view s) { return static_cast<double>(s.size()); };
  EXPECT_EQ(wrap_text("aaa bbb ccc", 7, chars), (std::vector<std::string>{"aaa bbb", "ccc"}));
  EXPECT_EQ(wrap_text("a verylongword b", 5, chars), (std::vector<std::string>{"a", "verylongword", "b"}));
  EXPECT_EQ(wrap_text("one\ntwo three", 20, chars), (std::vector<std::string>{"one", "two three"}));
  EXPECT_EQ(wrap_text("", 20, chars), (std::vector<std::string>{""}));
}

TEST(TextSummary, ALongDescriptionIsCutToItsLinesWithAnEllipsis) {
  const TextMeasure chars = [](std::string_view s) { return static_cast<double>(s.size()); };
  std::string text;
  for (int k = 0; k < 60; ++k) text += "word" + std::to_string(k) + " ";
  const TextSummary s = summarize_text(text, 24, 3, chars);
  ASSERT_EQ(s.lines.size(), 3u);
  EXPECT_TRUE(s.cut);
  for (const auto& line : s.lines) EXPECT_LE(line.size(), 24u) << line;
  EXPECT_TRUE(s.lines.back().ends_with("...")) << s.lines.back();
  EXPECT_EQ(s.lines.front().rfind("word0 word1", 0), 0u);

  const TextSummary shorter = summarize_text("Gradient noise on a lattice.", 24, 3, chars);
  EXPECT_FALSE(shorter.cut);
  EXPECT_EQ(shorter.lines, (std::vector<std::string>{"Gradient noise on a", "lattice."}));
}

TEST(PlacePopup, StaysInsideTheWindowNearEveryEdge) {
  const Rect window{{0, 0}, {1600, 900}};
  const glm::dvec2 size{320, 420};
  EXPECT_EQ(place_popup({100, 100}, size, window), glm::dvec2(100, 100));                // fits: at the anchor
  EXPECT_EQ(place_popup({1500, 100}, size, window), glm::dvec2(1180, 100));              // right edge: flipped left
  EXPECT_EQ(place_popup({100, 850}, size, window), glm::dvec2(100, 430));                // bottom: flipped up
  EXPECT_EQ(place_popup({1590, 890}, size, window), glm::dvec2(1270, 470));              // corner
  EXPECT_EQ(place_popup({100, 300}, size, {{0, 0}, {1600, 500}}), glm::dvec2(100, 80));  // neither side fits
  EXPECT_EQ(place_popup({-20, -5}, size, window), glm::dvec2(0, 0));
  EXPECT_EQ(place_popup({50, 50}, {2000, 1000}, window), glm::dvec2(0, 0));  // too large: top-left inside
  for (double x = -50; x <= 1650; x += 37)
    for (double y = -50; y <= 950; y += 41) {
      const glm::dvec2 p = place_popup({x, y}, size, window);
      EXPECT_TRUE(window.contains(p) && window.contains(p + size)) << x << "," << y;
    }
}

}  // namespace
}  // namespace orogen::editor
