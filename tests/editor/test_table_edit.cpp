// The inspector's table widget logic (editor/model/table_edit.h), headless: adding, removing, moving rows and
// setting cells of a real table parameter through the document, with undo like any other parameter, and
// refusals that leave the document unchanged.
#include <gtest/gtest.h>

#include "editor/model/document.h"
#include "editor/model/table_edit.h"
#include "graph/graph_file.h"
#include "graph/registry.h"

namespace orogen::editor {
namespace {

// Loader options with unconnected inputs accepted (a designated initializer would leave later fields to
// -Wmissing-field-initializers).
LoadOptions unconnected_inputs_allowed() {
  LoadOptions options;
  options.allow_unconnected_inputs = true;
  return options;
}

// A ColorByLayers node: its `colors` table is (name: text, color: color).
Graph color_graph() {
  const auto r = parse_graph(R"({"format": "orogen-graph", "version": 6,
    "domain": {"size": [100, 100], "resolution": [9, 9]},
    "nodes": [{"id": "color", "type": "ColorByLayers", "params": {"colors": [
      {"name": "grass", "color": "#5b7f32"}, {"name": "rock", "color": "#80786f"}]}}]})",
                             unconnected_inputs_allowed());
  EXPECT_TRUE(r.ok()) << r.error_text();
  return *r.graph;
}

const TableSchema& colors_schema() {
  return NodeRegistry::instance().find("ColorByLayers")->find_param("colors")->table;
}

TableValue colors(const Document& doc) { return std::get<TableValue>(doc.graph().param("color", "colors")); }

std::string name_at(const TableValue& t, std::size_t row) { return std::get<std::string>(t.rows.at(row)[0]); }

TEST(TableEdit, NewCellsFollowTheColumn) {
  TableSchema s;
  s.add("t", ColumnType::Text).describe("text");
  s.add_enum("e", {"b", "a"}).describe("enum");
  s.add("n", ColumnType::Number).range(5, 10).describe("number above 0");
  s.add("i", ColumnType::Integer).range(-3, -1).describe("negative integer");
  s.add("r", ColumnType::Range).range(0.25, 0.5).describe("narrow range");
  s.add("c", ColumnType::Color).describe("color");
  s.add("o", ColumnType::Number).optional().describe("optional");
  std::vector<TableCell> row;
  for (const auto& c : s.columns) row.push_back(new_cell(c));
  EXPECT_EQ(std::get<std::string>(row[0]), "");
  EXPECT_EQ(std::get<std::string>(row[1]), "b");
  EXPECT_EQ(std::get<double>(row[2]), 5.0);
  EXPECT_EQ(std::get<std::int64_t>(row[3]), -1);
  EXPECT_EQ(std::get<glm::dvec2>(row[4]), glm::dvec2(0.25, 0.5));
  EXPECT_EQ(std::get<Srgb8>(row[5]), (Srgb8{128, 128, 128}));
  EXPECT_TRUE(std::holds_alternative<std::monostate>(row[6]));
  // Every new cell is valid in its column: a first row added to an empty table passes the check.
  const TableValue added = insert_row(s, empty_table(s), 0);
  EXPECT_FALSE(check_table(s, added).has_value()) << check_table(s, added)->str("t");
}

TEST(TableEdit, AddRemoveMoveAndSetAreEachOneUndoStep) {
  Document doc(color_graph());
  const std::string original = serialize_graph(doc.graph());
  // Add: a copy of the last row, appended.
  doc.set_param("color", "colors", insert_row(colors_schema(), colors(doc), colors(doc).rows.size()));
  ASSERT_EQ(colors(doc).rows.size(), 3u);
  EXPECT_EQ(colors(doc).rows[2], colors(doc).rows[1]);
  // Set a cell: rename the new row.
  doc.set_param("color", "colors", set_cell(colors(doc), 2, 0, std::string("snow")));
  doc.set_param("color", "colors", set_cell(colors(doc), 2, 1, Srgb8{244, 246, 248}));
  // Move it to the top, then remove the middle one.
  doc.set_param("color", "colors", move_row(colors(doc), 2, 0));
  EXPECT_EQ(name_at(colors(doc), 0), "snow");
  EXPECT_EQ(name_at(colors(doc), 1), "grass");
  doc.set_param("color", "colors", remove_row(colors(doc), 1));
  ASSERT_EQ(colors(doc).rows.size(), 2u);
  EXPECT_EQ(name_at(colors(doc), 1), "rock");
  EXPECT_EQ(doc.history().undo_size(), 5u);
  // The saved file has the rows in their new order.
  const std::string text = serialize_graph(doc.graph());
  EXPECT_NE(text.find(R"({"name": "snow", "color": "#f4f6f8"},)"), std::string::npos) << text;
  // Undo walks back one operation at a time.
  doc.undo();
  EXPECT_EQ(colors(doc).rows.size(), 3u);
  doc.undo();
  EXPECT_EQ(name_at(colors(doc), 2), "snow");
  for (int k = 0; k < 3; ++k) doc.undo();
  EXPECT_EQ(serialize_graph(doc.graph()), original);
  EXPECT_FALSE(doc.history().can_undo());
}

TEST(TableEdit, DraggingACellMergesIntoOneStep) {
  TableSchema s = NodeRegistry::instance().find("SplatWeights")->find_param("rules")->table;
  const auto r =
      parse_graph(R"({"format": "orogen-graph", "version": 6, "nodes": [{"id": "s", "type": "SplatWeights"}]})",
                  unconnected_inputs_allowed());
  ASSERT_TRUE(r.ok()) << r.error_text();
  Document doc(*r.graph);
  const int threshold = s.index("threshold");
  for (int k = 1; k <= 20; ++k) {
    auto rules = std::get<TableValue>(doc.graph().param("s", "rules"));
    doc.set_param("s", "rules", set_cell(rules, 0, static_cast<std::size_t>(threshold), 30.0 + k), /*gesture=*/true);
  }
  doc.end_gesture();
  EXPECT_EQ(doc.history().undo_size(), 1u);
  EXPECT_EQ(std::get<double>(std::get<TableValue>(doc.graph().param("s", "rules")).rows[0][threshold]), 50.0);
}

TEST(TableEdit, InvalidEditsAreRefusedWithRowAndColumn) {
  Document doc(color_graph());
  const Graph before = doc.graph();
  // A text in the color column, a number out of its column's range in another table.
  try {
    doc.set_param("color", "colors", set_cell(colors(doc), 1, 1, std::string("#80786f")));
    ADD_FAILURE() << "accepted";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("colors[1].color: expected a #rrggbb color"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(doc.graph() == before);
  EXPECT_FALSE(doc.history().can_undo());
  // Removing below the minimum row count (SplatWeights needs a layer) is refused too.
  const auto r = parse_graph(R"({"format": "orogen-graph", "version": 6, "nodes": [{"id": "s", "type": "SplatWeights",
    "params": {"layers": [{"name": "only", "weight": 1}], "rules": []}}]})",
                             unconnected_inputs_allowed());
  ASSERT_TRUE(r.ok()) << r.error_text();
  Document splat(*r.graph);
  EXPECT_THROW(splat.set_param("s", "layers", remove_row(std::get<TableValue>(splat.graph().param("s", "layers")), 0)),
               GraphError);
  // Out-of-range operations change nothing.
  const TableValue t = colors(doc);
  EXPECT_EQ(remove_row(t, 7), t);
  EXPECT_EQ(set_cell(t, 0, 9, std::string("x")), t);
  EXPECT_EQ(move_row(t, 5, 0).rows[0], t.rows[1]) << "indices clamp to the last row";
}

}  // namespace
}  // namespace orogen::editor
