#pragma once
// Fuzzy matching of typed text against names, as in Blender's and Houdini's node search: the pattern's
// characters must appear in order; matches at word starts (after a separator or at a camel-case hump),
// runs of consecutive characters and a match at the very start score higher, gaps cost a little.
#include <optional>
#include <string_view>
#include <vector>

namespace orogen::editor {

struct FuzzyMatch {
  double score = 0.0;
  std::vector<int> positions;  // index in the text of each pattern character (for highlighting)
};

// Case-insensitive. nullopt if the pattern is not a subsequence of the text. An empty pattern matches
// with score 0.
std::optional<FuzzyMatch> fuzzy_match(std::string_view pattern, std::string_view text);

}  // namespace orogen::editor
