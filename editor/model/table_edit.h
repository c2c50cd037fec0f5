#pragma once
// The editing operations of the inspector's table widget, without any UI: each makes a new TableValue from
// the current one, so the inspector applies it as one parameter edit (one undo step, or one merged gesture
// for a drag) and the document refuses a value that breaks the schema.
#include <cstddef>

#include "graph/table_value.h"

namespace orogen::editor {

// The cell a new row starts with in column `c`: empty for an optional column, else "" for text, the first
// choice, 0 (or the nearest bound) for numbers, [0, 1] clamped into the bounds for ranges, mid gray.
TableCell new_cell(const TableColumn& c);

// A copy of `table` with a new row inserted before `at` (at >= rows appends). The new row copies the row
// before it when there is one (the usual "one more like this"), else starts from new_cell.
TableValue insert_row(const TableSchema& schema, const TableValue& table, std::size_t at);
// A copy without row `row` (unchanged when out of range).
TableValue remove_row(const TableValue& table, std::size_t row);
// A copy with row `from` moved to position `to` (both clamped; the others keep their order).
TableValue move_row(const TableValue& table, std::size_t from, std::size_t to);
// A copy with one cell replaced (unchanged when out of range).
TableValue set_cell(const TableValue& table, std::size_t row, std::size_t column, TableCell cell);

}  // namespace orogen::editor
