#include "editor/model/fuzzy_match.h"

#include <cctype>
#include <limits>

namespace orogen::editor {

namespace {

constexpr double kMatch = 1.0;
constexpr double kStartBonus = 3.0;     // first character of the text
constexpr double kBoundaryBonus = 2.0;  // start of a word or camel-case hump
constexpr double kConsecutiveBonus = 2.0;
constexpr double kGapPenalty = 0.1;    // per skipped character between matches
constexpr double kLeadPenalty = 0.05;  // per character skipped before the first match
constexpr double kNone = -std::numeric_limits<double>::infinity();

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

bool is_boundary(std::string_view text, std::size_t j) {
  if (j == 0) return true;
  const auto prev = static_cast<unsigned char>(text[j - 1]);
  const auto cur = static_cast<unsigned char>(text[j]);
  if (!std::isalnum(prev)) return true;
  if (std::islower(prev) && std::isupper(cur)) return true;
  return std::isdigit(prev) != std::isdigit(cur);
}

}  // namespace

std::optional<FuzzyMatch> fuzzy_match(std::string_view pattern, std::string_view text) {
  const std::size_t n = pattern.size(), m = text.size();
  if (n == 0) return FuzzyMatch{};
  if (n > m) return std::nullopt;

  // best[i][j]: best score with pattern[i] matched at text[j]; from[i][j]: where pattern[i-1] was.
  std::vector<double> best(n * m, kNone);
  std::vector<int> from(n * m, -1);
  auto at = [m](std::size_t i, std::size_t j) { return i * m + j; };
  auto char_score = [&](std::size_t j) {
    return kMatch + (j == 0 ? kStartBonus : 0.0) + (is_boundary(text, j) ? kBoundaryBonus : 0.0);
  };

  for (std::size_t j = 0; j < m; ++j)
    if (lower(text[j]) == lower(pattern[0])) best[at(0, j)] = char_score(j) - kLeadPenalty * static_cast<double>(j);

  for (std::size_t i = 1; i < n; ++i) {
    // Running maximum of best[i-1][k] + gap * k over k < j - 1, for matches after a gap.
    double run = kNone;
    int run_k = -1;
    for (std::size_t j = i; j < m; ++j) {
      if (j >= 2) {
        const std::size_t k = j - 2;
        const double v = best[at(i - 1, k)] + kGapPenalty * static_cast<double>(k);
        if (v > run) {
          run = v;
          run_k = static_cast<int>(k);
        }
      }
      if (lower(text[j]) != lower(pattern[i])) continue;
      double s = kNone;
      int f = -1;
      if (const double prev = best[at(i - 1, j - 1)]; prev != kNone) {
        s = prev + kConsecutiveBonus;
        f = static_cast<int>(j - 1);
      }
      if (run != kNone) {
        const double gap = run - kGapPenalty * static_cast<double>(j - 1);
        if (gap > s) {
          s = gap;
          f = run_k;
        }
      }
      if (f < 0) continue;
      best[at(i, j)] = s + char_score(j);
      from[at(i, j)] = f;
    }
  }

  double top = kNone;
  int end = -1;
  for (std::size_t j = n - 1; j < m; ++j)
    if (best[at(n - 1, j)] > top) {
      top = best[at(n - 1, j)];
      end = static_cast<int>(j);
    }
  if (end < 0) return std::nullopt;

  FuzzyMatch match;
  match.score = top;
  match.positions.resize(n);
  for (std::size_t i = n; i-- > 0;) {
    match.positions[i] = end;
    end = from[at(i, static_cast<std::size_t>(end))];
  }
  return match;
}

}  // namespace orogen::editor
