// Table parameters (graph/table_value.h): the JSON form, validation with the row and column in every error,
// the graph file round trip, cache keys and declarations.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "evaluator/cache_key.h"
#include "graph/graph_file.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/table_json.h"

namespace orogen {
namespace {

using nlohmann::json;

// A schema with every column type.
TableSchema every_type() {
  TableSchema s;
  s.max_rows = 3;
  s.add("name", ColumnType::Text).describe("a name");
  s.add_enum("kind", {"tree", "rock"}).describe("a choice");
  s.add("height", ColumnType::Number).range(0, 100).unit_of(Unit::Metre).describe("a number");
  s.add("class", ColumnType::Integer).range(0, 9).describe("an integer");
  s.add("band", ColumnType::Range).range(-90, 90).unit_of(Unit::Degree).optional().describe("a range");
  s.add("open", ColumnType::Range).allow_open_ends().optional().describe("a range with open ends");
  s.add("color", ColumnType::Color).describe("a color");
  return s;
}

const char* kGood = R"([
  {"name": "oak", "kind": "tree", "height": 12.5, "class": 0, "band": [0, 35], "open": [null, 4], "color": "#2F5d3a"},
  {"name": "scree", "kind": "rock", "height": 0, "class": 9, "color": "#808080"}])";

std::string problem_of(const std::string& text, const TableSchema& schema = every_type()) {
  TableProblem problem;
  const auto value = table_from_json(json::parse(text), schema, problem);
  EXPECT_FALSE(value.has_value()) << text;
  return problem.str("t") + " @" + problem.pointer();
}

TEST(TableParam, ReadsEveryColumnType) {
  TableProblem problem;
  const auto t = table_from_json(json::parse(kGood), every_type(), problem);
  ASSERT_TRUE(t.has_value()) << problem.str("t");
  EXPECT_EQ(t->columns, every_type().names());
  ASSERT_EQ(t->rows.size(), 2u);
  const auto& oak = t->rows[0];
  EXPECT_EQ(std::get<std::string>(oak[0]), "oak");
  EXPECT_EQ(std::get<std::string>(oak[1]), "tree");
  EXPECT_EQ(std::get<double>(oak[2]), 12.5);
  EXPECT_EQ(std::get<std::int64_t>(oak[3]), 0);
  EXPECT_EQ(std::get<glm::dvec2>(oak[4]), glm::dvec2(0, 35));
  EXPECT_EQ(std::get<glm::dvec2>(oak[5]).x, -INFINITY) << "null opens the lower end";
  EXPECT_EQ(std::get<Srgb8>(oak[6]), (Srgb8{0x2f, 0x5d, 0x3a})) << "either case";
  EXPECT_TRUE(std::holds_alternative<std::monostate>(t->rows[1][4])) << "optional cells may be left out";
  // Written back: empty cells left out, open ends as null, colors lowercase.
  EXPECT_EQ(table_to_json(*t)[0]["open"], json::parse("[null, 4.0]"));
  EXPECT_EQ(table_to_json(*t)[0]["color"], "#2f5d3a");
  EXPECT_FALSE(table_to_json(*t)[1].contains("band"));
  EXPECT_EQ(table_from_json(table_to_json(*t), every_type(), problem), t) << "JSON round trip";
}

TEST(TableParam, EveryMalformedCaseNamesItsRowAndColumn) {
  EXPECT_EQ(problem_of(R"({"name": "oak"})"),
            "t: expected a table: an array of rows {\"column\": value, ...}, found an object @");
  EXPECT_EQ(problem_of(R"([3])"), "t[0]: expected a row object {\"column\": value, ...}, found the number 3 @/0");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "color": "#000000"},
                          {"name": "b", "kind": "tree", "height": 1, "class": 1, "colour": "#000000"}])"),
            "t[1].colour: unknown column 'colour' (did you mean 'color'?) @/1/colour");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1}])"),
            "t[0].color: the column 'color' is required @/0/color");
  EXPECT_EQ(problem_of(R"([{"name": 3, "kind": "tree", "height": 1, "class": 1, "color": "#000000"}])"),
            "t[0].name: expected text, found the number 3 @/0/name");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "bush", "height": 1, "class": 1, "color": "#000000"}])"),
            "t[0].kind: 'bush' is not one of: tree, rock @/0/kind");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 101, "class": 1, "color": "#000000"}])"),
            "t[0].height: 101 is above the maximum 100 @/0/height");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": "1", "class": 1, "color": "#000000"}])"),
            "t[0].height: expected a number, found the string \"1\" @/0/height");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1.5, "color": "#000000"}])"),
            "t[0].class: expected an integer, found the number 1.5 @/0/class");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": -1, "color": "#000000"}])"),
            "t[0].class: -1 is below the minimum 0 @/0/class");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "band": [5], "color": "#000000"}])"),
            "t[0].band: expected a range [min, max], found an array of 1 element @/0/band");
  EXPECT_EQ(
      problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "band": [50, 5], "color": "#000000"}])"),
      "t[0].band: the range [50, 5] has min > max @/0/band");
  EXPECT_EQ(
      problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "band": [0, 95], "color": "#000000"}])"),
      "t[0].band: maximum 95 is above the maximum 90 @/0/band");
  EXPECT_EQ(
      problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "band": [null, 5], "color": "#000000"}])"),
      "t[0].band: minimum: expected a number, found null @/0/band");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "color": "#12"}])"),
            "t[0].color: '#12' is not a #rrggbb color @/0/color");
  EXPECT_EQ(problem_of(R"([{"name": "a", "kind": "tree", "height": 1, "class": 1, "color": "#12345g"}])"),
            "t[0].color: '#12345g' is not a #rrggbb color @/0/color");
  const std::string row = R"({"name": "a", "kind": "tree", "height": 1, "class": 1, "color": "#000000"})";
  EXPECT_EQ(problem_of("[" + row + "," + row + "," + row + "," + row + "]"), "t: at most 3 rows allowed, found 4 @");
}

TEST(TableParam, CheckRefusesValuesThatBreakTheSchema) {
  const TableSchema schema = every_type();
  TableProblem problem;
  TableValue t = *table_from_json(json::parse(kGood), schema, problem);
  EXPECT_FALSE(check_table(schema, t).has_value());
  auto wrong = t;
  wrong.rows[1][2] = std::string("tall");  // a string in a number column
  ASSERT_TRUE(check_table(schema, wrong).has_value());
  EXPECT_EQ(check_table(schema, wrong)->str("t"), "t[1].height: expected a number");
  wrong = t;
  wrong.rows[0][4] = glm::dvec2(-INFINITY, 3);  // an open end where the column has none
  EXPECT_EQ(check_table(schema, wrong)->str("t"), "t[0].band: range bounds must be finite");
  wrong = t;
  wrong.rows[0][5] = glm::dvec2(INFINITY, INFINITY);  // +inf as a minimum
  EXPECT_EQ(check_table(schema, wrong)->str("t"),
            "t[0].open: an open range end is -inf for the minimum, +inf for the maximum");
  wrong = t;
  wrong.rows[0].pop_back();
  EXPECT_EQ(check_table(schema, wrong)->str("t"), "t[0]: the row has 6 cells, expected 7");
  wrong = t;
  wrong.columns[0] = "label";
  EXPECT_EQ(check_table(schema, wrong)->str("t"), "t: the columns differ from the declared ones");
}

TEST(TableParam, HexColors) {
  EXPECT_EQ(parse_srgb8("#00ff80"), (Srgb8{0, 255, 128}));
  EXPECT_EQ(parse_srgb8("#00FF80"), (Srgb8{0, 255, 128}));
  for (const char* bad : {"", "00ff80", "#00ff8", "#00ff800", "#0gff80", "# 0ff80"})
    EXPECT_FALSE(parse_srgb8(bad).has_value()) << bad;
  EXPECT_EQ((Srgb8{0, 255, 128}).hex(), "#00ff80");
  const glm::vec4 linear = Srgb8{255, 0, 188}.linear();
  EXPECT_EQ(linear.r, 1.0f);
  EXPECT_EQ(linear.g, 0.0f);
  EXPECT_NEAR(linear.b, std::pow((188 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
  EXPECT_EQ(linear.a, 1.0f);
}

// Biomes' custom_table (open ends), ColorByLayers' colors and ScatterRules' ecosystems (optional cells).
const char* kGraph = R"({
  "format": "orogen-graph", "version": 6,
  "domain": {"size": [100, 100], "resolution": [9, 9]},
  "nodes": [
    {"id": "t", "type": "Constant", "params": {"value": 10}},
    {"id": "m", "type": "Constant", "params": {"value": 0.5}},
    {"id": "biomes", "type": "Biomes", "inputs": {"in": "t.out", "moisture": "m.out"},
     "params": {"table": "custom", "custom_table": [
       {"name": "cold", "temperature": [null, 0], "moisture": [null, null], "color": "#0000FF"},
       {"color": "#ff0000", "name": "warm", "temperature": [0, null], "moisture": [0, 1.5]}]}},
    {"id": "rules", "type": "ScatterRules", "inputs": {"in": "t.out"},
     "params": {"ecosystems": [{"name": "flat", "slope": [0, 10]}, {"name": "any"}],
                "plants": [{"ecosystem": "any", "class": 3, "density": 0.01, "scale": [1, 2]}]}}
  ]
})";

TEST(TableParam, RoundTripsThroughSaveAndLoad) {
  const auto first = parse_graph(kGraph);
  ASSERT_TRUE(first.ok()) << first.error_text();
  const std::string text = serialize_graph(*first.graph);
  // One row per line, cells in column order, empty cells left out, open ends null, colors lowercase.
  EXPECT_NE(text.find(R"({"name": "warm", "temperature": [0, null], "moisture": [0, 1.5], "color": "#ff0000"})"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(R"({"name": "flat", "slope": [0, 10]},)"), std::string::npos) << text;
  const auto second = parse_graph(text);
  ASSERT_TRUE(second.ok()) << second.error_text() << "\n" << text;
  EXPECT_EQ(second.graph->param("biomes", "custom_table"), first.graph->param("biomes", "custom_table"));
  EXPECT_EQ(second.graph->param("rules", "ecosystems"), first.graph->param("rules", "ecosystems"));
  EXPECT_EQ(serialize_graph(*second.graph), text) << "stable";
  const auto& rows = std::get<TableValue>(first.graph->param("biomes", "custom_table")).rows;
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(std::get<glm::dvec2>(rows[1][1]), glm::dvec2(0, INFINITY));
}

TEST(TableParam, LoaderReportsTheRowAndColumnPath) {
  std::string text = kGraph;
  text.replace(text.find("\"#ff0000\""), 9, "\"#12\"");
  text.replace(text.find("\"class\": 3"), 10, "\"clas\": 3");
  const auto r = parse_graph(text);
  ASSERT_EQ(r.diagnostics.size(), 2u) << r.error_text();
  EXPECT_EQ(r.diagnostics[0].path, "/nodes/2/params/custom_table/1/color");
  EXPECT_EQ(r.diagnostics[0].node, "biomes");
  EXPECT_EQ(r.diagnostics[0].message, "params.custom_table[1].color: '#12' is not a #rrggbb color");
  EXPECT_EQ(r.diagnostics[1].path, "/nodes/3/params/plants/0/clas");
  EXPECT_EQ(r.diagnostics[1].message, "params.plants[0].clas: unknown column 'clas' (did you mean 'class'?)");
  // --set uses the same reader.
  const ParamDecl* decl = NodeRegistry::instance().find("ColorByLayers")->find_param("colors");
  std::string error;
  EXPECT_FALSE(param_from_text(R"([{"name": "rock", "color": "gray"}])", *decl, error));
  EXPECT_EQ(error, "colors[0].color: 'gray' is not a #rrggbb color");
  EXPECT_TRUE(param_from_text(R"([{"name": "rock", "color": "#808080"}])", *decl, error)) << error;
}

CacheKey key_of(const ParamValue& v) {
  KeyHasher h;
  h.add(v);
  return h.finish();
}

TEST(TableParam, CacheKeyIsTheCanonicalValue) {
  TableProblem problem;
  const TableValue t = *table_from_json(json::parse(kGood), every_type(), problem);
  // The same value read from differently written JSON (key order, hex case) has the same key.
  const TableValue same = *table_from_json(json::parse(R"([
    {"color": "#2f5d3a", "open": [null, 4], "band": [0, 35], "class": 0, "height": 12.5, "kind": "tree", "name": "oak"},
    {"name": "scree", "kind": "rock", "height": 0.0, "class": 9, "color": "#808080"}])"),
                                           every_type(), problem);
  EXPECT_EQ(key_of(t), key_of(same));
  // Every change of a cell, a row's presence or order, or an empty optional cell changes it.
  std::vector<TableValue> changed;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    auto v = t;
    auto& cell = v.rows[0][c];
    if (auto* s = std::get_if<std::string>(&cell))
      *s = *s == "tree" ? "rock" : *s + "x";
    else if (auto* x = std::get_if<double>(&cell))
      *x += 0.5;
    else if (auto* i = std::get_if<std::int64_t>(&cell))
      *i += 1;
    else if (auto* r = std::get_if<glm::dvec2>(&cell))
      r->y += 1;
    else if (auto* k = std::get_if<Srgb8>(&cell))
      k->b ^= 1;
    changed.push_back(v);
  }
  auto without_band = t;
  without_band.rows[0][4] = std::monostate{};
  changed.push_back(without_band);
  auto swapped = t;
  std::swap(swapped.rows[0], swapped.rows[1]);
  changed.push_back(swapped);
  auto fewer = t;
  fewer.rows.pop_back();
  changed.push_back(fewer);
  for (std::size_t k = 0; k < changed.size(); ++k) EXPECT_NE(key_of(changed[k]), key_of(t)) << "change " << k;
}

TEST(TableParam, DeclarationsAreChecked) {
  NodeType type;
  type.name = "TableTest";
  type.category = "test";
  type.description = "A node with a table.";
  type.reach = Reach::pointwise();
  type.execute = [](ExecContext&) {};
  type.outputs.push_back({"out", PortType::Heightfield});
  NodeBuilder b(type);
  TableSchema schema;
  schema.min_rows = 1;
  schema.add("name", ColumnType::Text).describe("a name");
  b.param_table("rows", schema, empty_table(schema)).description("rows");
  try {
    check_declaration(type);
    ADD_FAILURE() << "a default breaking the schema was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "node type 'TableTest': default of 'rows': rows: at least 1 row(s) needed, found 0");
  }
  type.params.back().default_value = table_from_json_text(R"([{"name": "a"}])", schema);
  EXPECT_NO_THROW(check_declaration(type));
  type.params.back().table.columns.push_back(type.params.back().table.columns.back());
  type.params.back().default_value = TableValue{{"name", "name"}, {}};
  type.params.back().table.min_rows = 0;
  EXPECT_THROW(check_declaration(type), std::logic_error) << "duplicate column names";
  EXPECT_THROW(table_from_json_text("[{\"name\": 3}]", schema), std::logic_error);
}

TEST(TableParam, EveryRegisteredTableDefaultIsValid) {
  int tables = 0;
  for (const auto* type : NodeRegistry::instance().all())
    for (const auto& p : type->params) {
      if (p.type != ParamType::Table) continue;
      ++tables;
      EXPECT_EQ(p.check(p.default_value), "") << type->name << "." << p.name;
      for (const auto& c : p.table.columns) EXPECT_FALSE(c.description.empty()) << type->name << "." << c.name;
    }
  EXPECT_GE(tables, 9) << "Biomes 1, BiomeScatter 2, ScatterRules 2, SplatWeights 2, ColorByLayers 1, Instance 1";
}

}  // namespace
}  // namespace orogen
