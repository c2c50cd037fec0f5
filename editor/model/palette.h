#pragma once
// The node palette (Tab or right-click on the canvas): ranked fuzzy search over the registered node types'
// names, categories and descriptions.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "graph/node_type.h"

#include <glm/vec2.hpp>

#include "editor/model/rect.h"

namespace orogen::editor {

struct PaletteMatch {
  const NodeType* type = nullptr;
  double score = 0.0;
  std::vector<int> name_positions;  // matched characters of the name, for highlighting
};

// Every word of the query must match the name (fuzzy, strongest), the category (fuzzy) or a word of the
// description (prefix). Best first; ties by shorter name, then alphabetically. An empty query lists every
// type by category, then name.
std::vector<PaletteMatch> search_palette(std::string_view query, const std::vector<const NodeType*>& types);

// The palette's state while it is open: the query typed so far, the ranked results and the highlighted
// row. Where the chosen node goes (and what it connects to) is the canvas's business.
class PaletteState {
 public:
  // The palette keeps one size whatever the results (it must not jump under the pointer as they shrink):
  // this many rows of results, and the highlighted type's description in at most this many lines.
  static constexpr int kVisibleRows = 14;
  static constexpr int kDescriptionLines = 5;

  explicit PaletteState(std::vector<const NodeType*> types = {});
  void set_types(std::vector<const NodeType*> types);

  const std::string& query() const { return query_; }
  void set_query(std::string query);
  void type_text(std::string_view text) { set_query(query_ + std::string(text)); }
  void backspace();

  const std::vector<PaletteMatch>& results() const { return results_; }
  // The highlighted row: the best match, or the type the user moved the highlight to (arrows, pointer) for as
  // long as further typing still matches it.
  int highlighted() const { return highlighted_; }
  void move_highlight(int delta);
  void set_highlight(int index);
  // The highlighted type, if any result.
  const NodeType* choice() const;

 private:
  std::vector<const NodeType*> types_;
  std::string query_;
  std::vector<PaletteMatch> results_;
  int highlighted_ = 0;
  const NodeType* kept_ = nullptr;  // the type the user highlighted
};

// Where a popup of `size` opened at `anchor` goes so that it stays inside `bounds` (the window): at the
// anchor when it fits, else flipped to the anchor's other side (like a context menu), else pushed inside;
// a popup larger than the bounds keeps its top-left corner inside.
glm::dvec2 place_popup(glm::dvec2 anchor, glm::dvec2 size, const Rect& bounds);

}  // namespace orogen::editor
