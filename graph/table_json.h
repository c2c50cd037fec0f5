#pragma once
// Table parameters <-> JSON: an array of row objects keyed by column name,
//   [{"name": "rock", "color": "#7f7f7f", "slope": [36, 90]}]
// Text and enum cells are strings, numbers and integers are numbers, ranges are [min, max] (null for an open
// end where the column allows it), colors are "#rrggbb". Optional columns may be left out of a row.
#include <optional>

#include <nlohmann/json_fwd.hpp>

#include "graph/table_value.h"

namespace orogen {

// Reads and checks a table; on failure returns nullopt and sets `problem` (with the row and column).
std::optional<TableValue> table_from_json(const nlohmann::json& j, const TableSchema& schema, TableProblem& problem);
// For declarations: a default written as JSON text. Throws std::logic_error naming the problem.
TableValue table_from_json_text(const char* text, const TableSchema& schema);

nlohmann::json table_cell_to_json(const TableCell& cell);
// The rows as objects (empty cells left out). The object's keys are sorted: the graph writer writes rows
// itself, in column order.
nlohmann::json table_to_json(const TableValue& value);

}  // namespace orogen
