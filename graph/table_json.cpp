#include "graph/table_json.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "graph/json_util.h"

namespace orogen {
namespace {

using json_util::describe;
using nlohmann::json;

// The cell of column `c` read from `j`; sets `error` and returns monostate on failure.
TableCell read_cell(const json& j, const TableColumn& c, std::string& error) {
  switch (c.type) {
    case ColumnType::Text:
    case ColumnType::Enum:
      if (!j.is_string()) break;
      return j.get<std::string>();
    case ColumnType::Number:
      if (!j.is_number()) break;
      return j.get<double>();
    case ColumnType::Integer:
      if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
        error = "the integer " + j.dump() + " is too large";
        return {};
      }
      if (!j.is_number_integer()) break;
      return j.get<std::int64_t>();
    case ColumnType::Range: {
      if (!j.is_array() || j.size() != 2) break;
      glm::dvec2 r;
      for (int k = 0; k < 2; ++k) {
        const json& e = j[static_cast<std::size_t>(k)];
        if (e.is_null() && c.open_ends) {
          r[k] = k == 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
        } else if (e.is_number()) {
          r[k] = e.get<double>();
        } else {
          error = std::string(k == 0 ? "minimum" : "maximum") + ": expected a number" +
                  (c.open_ends ? " or null (open end)" : "") + ", found " + describe(e);
          return {};
        }
      }
      return r;
    }
    case ColumnType::Color: {
      if (!j.is_string()) break;
      const auto color = parse_srgb8(j.get_ref<const std::string&>());
      if (!color) {
        error = "'" + j.get<std::string>() + "' is not a #rrggbb color";
        return {};
      }
      return *color;
    }
  }
  static const char* const expected[] = {
      "text", "a string (one of the choices)", "a number", "an integer", "a range [min, max]", "a color \"#rrggbb\""};
  error = std::string("expected ") + expected[static_cast<int>(c.type)] + ", found " + describe(j);
  return {};
}

}  // namespace

std::optional<TableValue> table_from_json(const json& j, const TableSchema& schema, TableProblem& problem) {
  problem = {};
  if (!j.is_array()) {
    problem.message = "expected a table: an array of rows {\"column\": value, ...}, found " + describe(j);
    return std::nullopt;
  }
  TableValue value = empty_table(schema);
  const auto names = schema.names();
  for (std::size_t r = 0; r < j.size(); ++r) {
    const json& row = j[r];
    problem.row = static_cast<int>(r);
    if (!row.is_object()) {
      problem.message = "expected a row object {\"column\": value, ...}, found " + describe(row);
      return std::nullopt;
    }
    for (const auto& [key, cell] : row.items()) {
      if (schema.index(key) < 0) {
        problem.column = key;
        problem.message = "unknown column '" + key + "'" + json_util::suggestion(key, names);
        return std::nullopt;
      }
    }
    std::vector<TableCell> cells;
    for (const auto& c : schema.columns) {
      const auto it = row.find(c.name);
      if (it == row.end()) {
        cells.emplace_back();  // the check below refuses it when the column is required
        continue;
      }
      std::string error;
      cells.push_back(read_cell(*it, c, error));
      if (!error.empty()) {
        problem.column = c.name;
        problem.message = error;
        return std::nullopt;
      }
    }
    value.rows.push_back(std::move(cells));
  }
  problem = {};
  if (auto p = check_table(schema, value)) {
    problem = *p;
    return std::nullopt;
  }
  return value;
}

TableValue table_from_json_text(const char* text, const TableSchema& schema) {
  TableProblem problem;
  auto value = table_from_json(json::parse(text), schema, problem);
  if (!value) throw std::logic_error("invalid table default: " + problem.str("default"));
  return *value;
}

json table_cell_to_json(const TableCell& cell) {
  return std::visit(
      [](const auto& x) -> json {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, glm::dvec2>) {
          auto bound = [](double v) { return std::isinf(v) ? json(nullptr) : json(v); };
          return json::array({bound(x.x), bound(x.y)});
        } else if constexpr (std::is_same_v<T, Srgb8>) {
          return x.hex();
        } else {
          return json(x);  // string, double, int64
        }
      },
      cell);
}

json table_to_json(const TableValue& value) {
  json out = json::array();
  for (const auto& row : value.rows) {
    json r = json::object();
    for (std::size_t c = 0; c < row.size() && c < value.columns.size(); ++c)
      if (!std::holds_alternative<std::monostate>(row[c])) r[value.columns[c]] = table_cell_to_json(row[c]);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace orogen
