#pragma once
// Long text in a fixed space: word wrapping by a measured width, and a summary of at most a few lines ending
// in "..." when cut (node descriptions in the palette and the inspector, which must not push what follows them
// out of view). The measure is the UI's (ImGui's text width), a stub in tests.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace orogen::editor {

using TextMeasure = std::function<double(std::string_view)>;

// The lines of `text` wrapped at spaces to at most `width` (a word wider than a line has a line of its own;
// a newline in the text starts a new line).
std::vector<std::string> wrap_text(std::string_view text, double width, const TextMeasure& measure);

struct TextSummary {
  std::vector<std::string> lines;
  bool cut = false;  // the text goes on beyond the lines
};
// At most `max_lines` wrapped lines; when the text is longer, the last shown line ends in "..." within `width`.
TextSummary summarize_text(std::string_view text, double width, int max_lines, const TextMeasure& measure);

}  // namespace orogen::editor
