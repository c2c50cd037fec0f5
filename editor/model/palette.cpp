#include "editor/model/palette.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "editor/model/fuzzy_match.h"

namespace orogen::editor {

namespace {

constexpr double kCategoryWeight = 0.6;
constexpr double kDescriptionPrefix = 1.2;  // per character of a word-prefix match in the description
constexpr double kExactNameBonus = 20.0;
constexpr double kNamePrefixBonus = 6.0;

std::string lowered(std::string_view s) {
  std::string out(s);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::vector<std::string> words(std::string_view text) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c))) {
      cur += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!cur.empty()) {
      out.push_back(std::move(cur));
      cur.clear();
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

std::optional<PaletteMatch> score_type(const std::vector<std::string>& tokens, const std::string& joined,
                                       const NodeType& type) {
  PaletteMatch match;
  match.type = &type;
  const auto description_words = words(type.description);
  for (const auto& token : tokens) {
    double best = -1.0;
    if (auto m = fuzzy_match(token, type.name)) {
      best = m->score;
      match.name_positions.insert(match.name_positions.end(), m->positions.begin(), m->positions.end());
    }
    if (auto m = fuzzy_match(token, type.category)) best = std::max(best, kCategoryWeight * m->score);
    for (const auto& w : description_words)
      if (w.starts_with(token)) {
        best = std::max(best, kDescriptionPrefix * static_cast<double>(token.size()));
        break;
      }
    if (best < 0.0) return std::nullopt;
    match.score += best;
  }
  const auto name = lowered(type.name);
  if (name == joined)
    match.score += kExactNameBonus;
  else if (name.starts_with(joined))
    match.score += kNamePrefixBonus;
  std::sort(match.name_positions.begin(), match.name_positions.end());
  match.name_positions.erase(std::unique(match.name_positions.begin(), match.name_positions.end()),
                             match.name_positions.end());
  return match;
}

}  // namespace

std::vector<PaletteMatch> search_palette(std::string_view query, const std::vector<const NodeType*>& types) {
  std::vector<std::string> tokens;
  {
    std::istringstream in{std::string(query)};
    for (std::string t; in >> t;) tokens.push_back(lowered(t));
  }
  std::string joined;
  for (const auto& t : tokens) joined += t;

  std::vector<PaletteMatch> out;
  for (const NodeType* type : types) {
    if (tokens.empty()) {
      out.push_back({type, 0.0, {}});
      continue;
    }
    if (auto m = score_type(tokens, joined, *type)) out.push_back(std::move(*m));
  }
  std::stable_sort(out.begin(), out.end(), [&](const PaletteMatch& a, const PaletteMatch& b) {
    if (tokens.empty()) {
      if (a.type->category != b.type->category) return a.type->category < b.type->category;
      return a.type->name < b.type->name;
    }
    if (a.score != b.score) return a.score > b.score;
    if (a.type->name.size() != b.type->name.size()) return a.type->name.size() < b.type->name.size();
    return a.type->name < b.type->name;
  });
  return out;
}

PaletteState::PaletteState(std::vector<const NodeType*> types) : types_(std::move(types)) { set_query({}); }

void PaletteState::set_types(std::vector<const NodeType*> types) {
  types_ = std::move(types);
  kept_ = nullptr;  // a new search
  set_query(query_);
}

void PaletteState::set_query(std::string query) {
  query_ = std::move(query);
  results_ = search_palette(query_, types_);
  highlighted_ = 0;
  for (std::size_t k = 0; kept_ && k < results_.size(); ++k)
    if (results_[k].type == kept_) highlighted_ = static_cast<int>(k);
  if (!results_.empty() && results_[static_cast<std::size_t>(highlighted_)].type != kept_) kept_ = nullptr;
}

void PaletteState::backspace() {
  if (query_.empty()) return;
  // Drop one UTF-8 character.
  auto n = query_.size() - 1;
  while (n > 0 && (static_cast<unsigned char>(query_[n]) & 0xC0) == 0x80) --n;
  set_query(query_.substr(0, n));
}

void PaletteState::move_highlight(int delta) { set_highlight(highlighted_ + delta); }

void PaletteState::set_highlight(int index) {
  if (results_.empty()) {
    highlighted_ = 0;
    return;
  }
  highlighted_ = std::clamp(index, 0, static_cast<int>(results_.size()) - 1);
  kept_ = results_[static_cast<std::size_t>(highlighted_)].type;
}

const NodeType* PaletteState::choice() const {
  if (results_.empty()) return nullptr;
  return results_[static_cast<std::size_t>(highlighted_)].type;
}

glm::dvec2 place_popup(glm::dvec2 anchor, glm::dvec2 size, const Rect& bounds) {
  glm::dvec2 at = anchor;
  for (int axis = 0; axis < 2; ++axis) {
    if (at[axis] + size[axis] > bounds.max[axis] && anchor[axis] - size[axis] >= bounds.min[axis])
      at[axis] = anchor[axis] - size[axis];  // flip to the other side of the anchor
    at[axis] = std::min(at[axis], bounds.max[axis] - size[axis]);
    at[axis] = std::max(at[axis], bounds.min[axis]);
  }
  return at;
}

}  // namespace orogen::editor
