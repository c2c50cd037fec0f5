#pragma once
// Table parameters: rows of typed cells under a declared column schema (biome rectangles, splat layers,
// ecosystems, class names, ...). The schema is part of the parameter's declaration, so the loader, the
// registry, `orogen nodes`, the cache key and the editor all read the same columns.
//
// JSON form in a graph file: an array of row objects keyed by column name, e.g.
//   [{"name": "rock", "color": "#7f7f7f", "slope": [36, 90]}]
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "graph/units.h"

namespace orogen {

// What a column holds:
//   Text    - a string (names); Enum - one of the column's choices;
//   Number  - a finite double; Integer - a whole number (ids, class references);
//   Range   - [min, max] with min <= max (JSON null for an open end when the column allows it: -inf / +inf);
//   Color   - an sRGB color written "#rrggbb".
enum class ColumnType { Text, Enum, Number, Integer, Range, Color };
std::string_view to_string(ColumnType t);

// An sRGB color with 8 bits per channel, exactly as "#rrggbb" writes it.
struct Srgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Srgb8&) const = default;
  // Linear RGBA (alpha 1) by the sRGB transfer function, in float as the nodes compute it.
  glm::vec4 linear() const;
  std::string hex() const;  // "#rrggbb", lowercase
};
// Parses "#rrggbb" (either case; nodes/common/hex_color.h); nullopt for anything else.
std::optional<Srgb8> parse_srgb8(std::string_view text);

// One cell: empty (an optional column left out), or the alternative its column type uses.
//   Text / Enum -> std::string, Number -> double, Integer -> int64_t, Range -> dvec2, Color -> Srgb8.
using TableCell = std::variant<std::monostate, std::string, double, std::int64_t, glm::dvec2, Srgb8>;

struct TableColumn {
  std::string name;
  ColumnType type = ColumnType::Number;
  Unit unit = Unit::None;  // numbers, integers and ranges: every one has a unit
  std::string description;
  std::optional<double> min, max;    // Number / Integer / Range: hard bounds of each value
  std::vector<std::string> choices;  // Enum: allowed values
  bool required = true;              // false: a row may leave the cell out (empty)
  bool open_ends = false;            // Range: null bounds allowed (read as -inf / +inf)

  TableColumn& range(double lo, double hi);
  TableColumn& unit_of(Unit u);
  TableColumn& describe(std::string text);
  TableColumn& optional();
  TableColumn& allow_open_ends();
};

// The columns of a table parameter and how many rows it may have.
struct TableSchema {
  std::vector<TableColumn> columns;
  std::size_t min_rows = 0;
  std::size_t max_rows = 100000;

  TableColumn& add(std::string name, ColumnType type);
  TableColumn& add_enum(std::string name, std::vector<std::string> choices);
  int index(std::string_view name) const;  // -1 if absent
  std::vector<std::string> names() const;
};

// A table value: the column names (the schema's, in its order) and the rows, one cell per column.
struct TableValue {
  std::vector<std::string> columns;
  std::vector<std::vector<TableCell>> rows;
  bool operator==(const TableValue&) const = default;
};

// A table's problem, at a row and column when it has one (row -1: the table as a whole; column "": the row).
struct TableProblem {
  int row = -1;
  std::string column;
  std::string message;
  // "name[3].color: message", "name[3]: message" or "name: message".
  std::string str(std::string_view param) const;
  // The JSON pointer below the parameter: "/3/color", "/3" or "".
  std::string pointer() const;
};

// Checks `value` against `schema`: the columns match the schema's, required cells are present, every cell
// holds its column's type within its bounds and choices, the row count is allowed. Returns the first
// problem, or nullopt when the value is valid.
std::optional<TableProblem> check_table(const TableSchema& schema, const TableValue& value);

// An empty table with the schema's columns.
TableValue empty_table(const TableSchema& schema);

}  // namespace orogen
