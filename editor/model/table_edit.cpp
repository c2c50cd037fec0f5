#include "editor/model/table_edit.h"

#include <algorithm>
#include <cmath>

namespace orogen::editor {

TableCell new_cell(const TableColumn& c) {
  if (!c.required) return {};
  auto clamp = [&](double v) { return std::clamp(v, c.min.value_or(-INFINITY), c.max.value_or(INFINITY)); };
  switch (c.type) {
    case ColumnType::Text:
      return std::string();
    case ColumnType::Enum:
      return c.choices.empty() ? std::string() : c.choices.front();
    case ColumnType::Number:
      return clamp(0.0);
    case ColumnType::Integer:
      return static_cast<std::int64_t>(std::ceil(clamp(0.0)));
    case ColumnType::Range: {
      const double lo = clamp(0.0);
      return glm::dvec2(lo, std::max(lo, clamp(1.0)));
    }
    case ColumnType::Color:
      return Srgb8{128, 128, 128};
  }
  return {};
}

TableValue insert_row(const TableSchema& schema, const TableValue& table, std::size_t at) {
  TableValue out = table;
  at = std::min(at, out.rows.size());
  std::vector<TableCell> row;
  if (at > 0) {
    row = out.rows[at - 1];
  } else {
    for (const auto& c : schema.columns) row.push_back(new_cell(c));
  }
  out.rows.insert(out.rows.begin() + static_cast<std::ptrdiff_t>(at), std::move(row));
  return out;
}

TableValue remove_row(const TableValue& table, std::size_t row) {
  TableValue out = table;
  if (row < out.rows.size()) out.rows.erase(out.rows.begin() + static_cast<std::ptrdiff_t>(row));
  return out;
}

TableValue move_row(const TableValue& table, std::size_t from, std::size_t to) {
  TableValue out = table;
  if (out.rows.empty()) return out;
  from = std::min(from, out.rows.size() - 1);
  to = std::min(to, out.rows.size() - 1);
  auto row = std::move(out.rows[from]);
  out.rows.erase(out.rows.begin() + static_cast<std::ptrdiff_t>(from));
  out.rows.insert(out.rows.begin() + static_cast<std::ptrdiff_t>(to), std::move(row));
  return out;
}

TableValue set_cell(const TableValue& table, std::size_t row, std::size_t column, TableCell cell) {
  TableValue out = table;
  if (row < out.rows.size() && column < out.rows[row].size()) out.rows[row][column] = std::move(cell);
  return out;
}

}  // namespace orogen::editor
