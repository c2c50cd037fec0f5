#include "editor/model/text_summary.h"

namespace orogen::editor {

std::vector<std::string> wrap_text(std::string_view text, double width, const TextMeasure& measure) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view paragraph = text.substr(start, end - start);
    std::string line;
    std::size_t p = 0;
    while (p < paragraph.size()) {
      const std::size_t word_end = std::min(paragraph.find(' ', p), paragraph.size());
      const std::string_view word = paragraph.substr(p, word_end - p);
      if (!word.empty()) {
        const std::string candidate = line.empty() ? std::string(word) : line + " " + std::string(word);
        if (line.empty() || measure(candidate) <= width) {
          line = candidate;
        } else {
          lines.push_back(std::move(line));
          line = std::string(word);
        }
      }
      p = word_end + 1;
    }
    lines.push_back(std::move(line));
    if (end == text.size()) break;
    start = end + 1;
  }
  return lines;
}

TextSummary summarize_text(std::string_view text, double width, int max_lines, const TextMeasure& measure) {
  TextSummary s;
  s.lines = wrap_text(text, width, measure);
  if (max_lines < 1 || static_cast<int>(s.lines.size()) <= max_lines) return s;
  s.lines.resize(static_cast<std::size_t>(max_lines));
  s.cut = true;
  // Words come off the last line until "..." fits after it.
  std::string& last = s.lines.back();
  while (!last.empty() && measure(last + "...") > width) {
    const std::size_t space = last.rfind(' ');
    last.erase(space == std::string::npos ? 0 : space);
  }
  last += "...";
  return s;
}

}  // namespace orogen::editor
