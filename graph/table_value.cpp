#include "graph/table_value.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "nodes/common/hex_color.h"

namespace orogen {
namespace {

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string check_bounds(const TableColumn& c, double x) {
  if (!std::isfinite(x)) return "must be a finite number";
  if (c.min && x < *c.min) return format_number(x) + " is below the minimum " + format_number(*c.min);
  if (c.max && x > *c.max) return format_number(x) + " is above the maximum " + format_number(*c.max);
  return {};
}

// Empty if `cell` is a valid value of column `c`, else why not.
std::string check_cell(const TableColumn& c, const TableCell& cell) {
  if (std::holds_alternative<std::monostate>(cell))
    return c.required ? "the column '" + c.name + "' is required" : std::string();
  switch (c.type) {
    case ColumnType::Text:
      if (!std::holds_alternative<std::string>(cell)) return "expected text";
      return {};
    case ColumnType::Enum: {
      if (!std::holds_alternative<std::string>(cell)) return "expected one of the column's choices";
      const auto& s = std::get<std::string>(cell);
      for (const auto& choice : c.choices)
        if (choice == s) return {};
      std::string all;
      for (const auto& choice : c.choices) all += (all.empty() ? "" : ", ") + choice;
      return "'" + s + "' is not one of: " + all;
    }
    case ColumnType::Number:
      if (!std::holds_alternative<double>(cell)) return "expected a number";
      return check_bounds(c, std::get<double>(cell));
    case ColumnType::Integer:
      if (!std::holds_alternative<std::int64_t>(cell)) return "expected an integer";
      return check_bounds(c, static_cast<double>(std::get<std::int64_t>(cell)));
    case ColumnType::Range: {
      if (!std::holds_alternative<glm::dvec2>(cell)) return "expected a range [min, max]";
      const auto r = std::get<glm::dvec2>(cell);
      for (int k = 0; k < 2; ++k) {
        if (std::isnan(r[k])) return "range bounds must be numbers";
        if (std::isinf(r[k])) {
          if (!c.open_ends) return "range bounds must be finite";
          if ((k == 0) != (r[k] < 0)) return "an open range end is -inf for the minimum, +inf for the maximum";
          continue;
        }
        if (auto why = check_bounds(c, r[k]); !why.empty()) return (k == 0 ? "minimum " : "maximum ") + why;
      }
      if (r.x > r.y) return "the range [" + format_number(r.x) + ", " + format_number(r.y) + "] has min > max";
      return {};
    }
    case ColumnType::Color:
      if (!std::holds_alternative<Srgb8>(cell)) return "expected a #rrggbb color";
      return {};
  }
  return "unknown column type";
}

}  // namespace

std::string_view to_string(ColumnType t) {
  switch (t) {
    case ColumnType::Text:
      return "text";
    case ColumnType::Enum:
      return "enum";
    case ColumnType::Number:
      return "number";
    case ColumnType::Integer:
      return "integer";
    case ColumnType::Range:
      return "range";
    case ColumnType::Color:
      return "color";
  }
  return "?";
}

glm::vec4 Srgb8::linear() const {
  return hex_to_linear(static_cast<std::uint32_t>(r) << 16 | static_cast<std::uint32_t>(g) << 8 | b);
}

std::string Srgb8::hex() const {
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", r, g, b);
  return text;
}

std::optional<Srgb8> parse_srgb8(std::string_view text) {
  const auto rgb = parse_hex_color(text);
  if (!rgb) return std::nullopt;
  return Srgb8{static_cast<std::uint8_t>(*rgb >> 16), static_cast<std::uint8_t>(*rgb >> 8),
               static_cast<std::uint8_t>(*rgb)};
}

TableColumn& TableColumn::range(double lo, double hi) {
  min = lo;
  max = hi;
  return *this;
}
TableColumn& TableColumn::unit_of(Unit u) {
  unit = u;
  return *this;
}
TableColumn& TableColumn::describe(std::string text) {
  description = std::move(text);
  return *this;
}
TableColumn& TableColumn::optional() {
  required = false;
  return *this;
}
TableColumn& TableColumn::allow_open_ends() {
  open_ends = true;
  return *this;
}

TableColumn& TableSchema::add(std::string name, ColumnType type) {
  columns.push_back({});
  columns.back().name = std::move(name);
  columns.back().type = type;
  return columns.back();
}

TableColumn& TableSchema::add_enum(std::string name, std::vector<std::string> choices) {
  TableColumn& c = add(std::move(name), ColumnType::Enum);
  c.choices = std::move(choices);
  return c;
}

int TableSchema::index(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> TableSchema::names() const {
  std::vector<std::string> out;
  for (const auto& c : columns) out.push_back(c.name);
  return out;
}

std::string TableProblem::str(std::string_view param) const {
  std::string out(param);
  if (row >= 0) out += "[" + std::to_string(row) + "]";
  if (!column.empty()) out += "." + column;
  return out + ": " + message;
}

std::string TableProblem::pointer() const {
  std::string out;
  if (row >= 0) out += "/" + std::to_string(row);
  if (!column.empty()) {
    // JSON-pointer escaping of the column name ("~" -> "~0", "/" -> "~1").
    out += '/';
    for (char ch : column) {
      if (ch == '~')
        out += "~0";
      else if (ch == '/')
        out += "~1";
      else
        out += ch;
    }
  }
  return out;
}

std::optional<TableProblem> check_table(const TableSchema& schema, const TableValue& value) {
  if (value.columns != schema.names()) return TableProblem{-1, "", "the columns differ from the declared ones"};
  if (value.rows.size() < schema.min_rows)
    return TableProblem{
        -1, "",
        "at least " + std::to_string(schema.min_rows) + " row(s) needed, found " + std::to_string(value.rows.size())};
  if (value.rows.size() > schema.max_rows)
    return TableProblem{
        -1, "",
        "at most " + std::to_string(schema.max_rows) + " rows allowed, found " + std::to_string(value.rows.size())};
  for (std::size_t r = 0; r < value.rows.size(); ++r) {
    const auto& row = value.rows[r];
    if (row.size() != schema.columns.size())
      return TableProblem{
          static_cast<int>(r), "",
          "the row has " + std::to_string(row.size()) + " cells, expected " + std::to_string(schema.columns.size())};
    for (std::size_t c = 0; c < row.size(); ++c)
      if (auto why = check_cell(schema.columns[c], row[c]); !why.empty())
        return TableProblem{static_cast<int>(r), schema.columns[c].name, why};
  }
  return std::nullopt;
}

TableValue empty_table(const TableSchema& schema) { return {schema.names(), {}}; }

}  // namespace orogen
