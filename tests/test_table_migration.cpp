// Graph format version 5: the six string mini-languages of version 4 became table parameters, and
// convert_string_tables_v4 (graph/table_migration.h) converts the strings of older files. The version-4
// copies of the example graphs (tests/fixtures/v4) migrate to exactly the graphs in graphs/.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/table_migration.h"
#include "support/later_text_edits.h"
#include "support/library_rewrites.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

// Loader options with unconnected inputs accepted (a designated initializer would leave later fields to
// -Wmissing-field-initializers).
LoadOptions unconnected_inputs_allowed() {
  LoadOptions options;
  options.allow_unconnected_inputs = true;
  return options;
}

using nlohmann::json;

// A version-4 file with one node of `type` and these params, migrated; returns the node's params.
json migrated_params(const std::string& type, const json& params) {
  json file = {{"format", "orogen-graph"}, {"version", 4}, {"nodes", json::array({{{"id", "n"}, {"type", type}}})}};
  if (!params.is_null()) file["nodes"][0]["params"] = params;
  convert_string_tables_v4(file);
  return file["nodes"][0].value("params", json::object());
}

std::string migration_error(const std::string& type, const json& params) {
  try {
    migrated_params(type, params);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(TableMigration, FixturesMigrateToTheRewrittenGraphs) {
  int compared = 0;
  std::map<std::string, int> edited;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "tests/fixtures/v4")) {
    const auto name = entry.path().filename();
    const std::string text = test::read_text(entry.path());
    EXPECT_EQ(json::parse(text)["version"], 4) << name;
    const auto old_file = parse_graph(test::with_later_text_edits(text, edited));
    ASSERT_TRUE(old_file.ok()) << name << ": " << old_file.error_text();
    const auto rewritten = load_graph_file(test::source_dir() / "graphs" / name);
    ASSERT_TRUE(rewritten.ok()) << name << ": " << rewritten.error_text();
    if (test::kLibraryRewrites.count(name.string()))
      EXPECT_EQ(test::canonical_graph_text(*old_file.graph), test::canonical_graph_text(*rewritten.graph)) << name;
    else
      EXPECT_EQ(serialize_graph(*old_file.graph), serialize_graph(*rewritten.graph)) << name;
    ++compared;
  }
  EXPECT_EQ(compared, 15) << "every example graph has its version-4 copy";
}

TEST(TableMigration, Biomes) {
  const json p = migrated_params(
      "Biomes", {{"table", "custom"},
                 {"custom_table", "cold, -inf, 0, -inf, inf, #0000FF\n\n warm , 0, inf, 2.5, 7, #ff0000\n"}});
  EXPECT_EQ(p["table"], "custom");
  EXPECT_EQ(p["custom_table"], json::parse(R"([
    {"name": "cold", "temperature": [null, 0.0], "moisture": [null, null], "color": "#0000ff"},
    {"name": "warm", "temperature": [0.0, null], "moisture": [2.5, 7.0], "color": "#ff0000"}])"));
  EXPECT_EQ(migrated_params("Biomes", {{"table", "island"}}), json({{"table", "island"}})) << "nothing to convert";
  EXPECT_EQ(migration_error("Biomes", {{"custom_table", "a, 1, x, 3, 4, #ffffff"}}),
            "node 'n' (Biomes): params.custom_table: line 1: 'x' is not a number");
  EXPECT_EQ(migration_error("Biomes", {{"custom_table", "a, 1, 2, 3, 4, #fff"}}),
            "node 'n' (Biomes): params.custom_table: line 1: '#fff' is not a #rrggbb color");
  EXPECT_EQ(
      migration_error("Biomes", {{"custom_table", "ok, 1, 2, 3, 4, #ffffff\na, inf, 2, 3, 4, #ffffff"}}),
      "node 'n' (Biomes): params.custom_table: line 2: an open end must be -inf for a minimum, inf for a maximum");
}

TEST(TableMigration, BiomeScatterKeepsTheLastLineOfABiome) {
  const json p = migrated_params("BiomeScatter",
                                 {{"table", "0 0.0\n1 0.2 | 0 1 | 1 3; 2 0.5 | 2 1\n1 0.4 | 3 2"}, {"factor", 2.0}});
  EXPECT_FALSE(p.contains("table"));
  EXPECT_EQ(p["factor"], 2.0);
  EXPECT_EQ(p["biomes"], json::parse(R"([{"biome": 0, "density": 0.0}, {"biome": 2, "density": 0.5},
                                          {"biome": 1, "density": 0.4}])"));
  EXPECT_EQ(p["species"], json::parse(R"([{"biome": 2, "class": 2, "weight": 1.0},
                                           {"biome": 1, "class": 3, "weight": 2.0}])"));
  EXPECT_EQ(migration_error("BiomeScatter", {{"table", "1 0.2 | 0"}}),
            "node 'n' (BiomeScatter): params.table: biome line 1: expected 2 numbers");
  EXPECT_EQ(migration_error("BiomeScatter", {{"table", "# nothing\n"}}),
            "node 'n' (BiomeScatter): params.table: the biome table is empty");
}

TEST(TableMigration, ScatterRulesSlopesBecomeDegrees) {
  const json p =
      migrated_params("ScatterRules", {{"table",
                                        "low | elevation -10 10 2 | slope 0 1 4 | plant 1 0.02 1 2 # a comment\n"
                                        "low | skew -1 1 3 | relative 0 5 1 | plant 2 0.5 1 1"}});
  ASSERT_EQ(p["ecosystems"].size(), 2u);
  const json& low = p["ecosystems"][0];
  EXPECT_EQ(low["elevation"], json::parse("[-10.0, 10.0]"));
  EXPECT_EQ(low["elevation_sharpness"], 2.0);
  EXPECT_EQ(low["slope"][0], 0.0);
  EXPECT_DOUBLE_EQ(low["slope"][1].get<double>(), 45.0) << "rise/run 1 is 45 degrees";
  EXPECT_EQ(low["slope_sharpness"], 4.0);
  EXPECT_FALSE(low.contains("relative"));
  // A second ecosystem of the same name is renamed so its plants stay its own.
  EXPECT_EQ(p["ecosystems"][1]["name"], "low (2)");
  EXPECT_EQ(p["ecosystems"][1]["skew"], json::parse("[-1.0, 1.0]"));
  EXPECT_EQ(p["plants"], json::parse(R"j([
    {"ecosystem": "low", "class": 1, "density": 0.02, "scale": [1.0, 2.0]},
    {"ecosystem": "low (2)", "class": 2, "density": 0.5, "scale": [1.0, 1.0]}])j"));
  // A node that relied on version 4's default gets it converted (the default changed with the unit).
  const json d = migrated_params("ScatterRules", nullptr);
  ASSERT_EQ(d["ecosystems"].size(), 5u);
  EXPECT_DOUBLE_EQ(d["ecosystems"][0]["slope"][1].get<double>(), std::atan(1.4) * 180.0 / M_PI);
  EXPECT_EQ(d["plants"].size(), 9u);
  EXPECT_EQ(migration_error("ScatterRules", {{"table", "a | height 0 1 1"}}),
            "node 'n' (ScatterRules): params.table: ecosystem 1 ('a'), 'height': unknown field (elevation, relative, "
            "slope, skew or plant)");
  EXPECT_EQ(migration_error("ScatterRules", {{"table", "a | elevation 10 0 1"}}),
            "node 'n' (ScatterRules): params.table: ecosystem 1 ('a'), 'elevation': max below min");
}

TEST(TableMigration, SplatWeights) {
  const json p =
      migrated_params("SplatWeights", {{"layers", "grass: slope < 30 ~ 8, height > 6\n\ndirt: weight = 0.15\n"}});
  EXPECT_EQ(p["layers"], json::parse(R"([{"name": "grass", "weight": 1.0}, {"name": "dirt", "weight": 0.15}])"));
  EXPECT_EQ(p["rules"], json::parse(R"([
    {"layer": "grass", "input": "slope", "compare": "<", "threshold": 30.0, "softness": 8.0},
    {"layer": "grass", "input": "height", "compare": ">", "threshold": 6.0, "softness": 0.0}])"));
  EXPECT_EQ(migration_error("SplatWeights", {{"layers", "a: heigth > 3"}}),
            "node 'n' (SplatWeights): params.layers: layer line 1: unknown input 'heigth'");
  EXPECT_EQ(migration_error("SplatWeights", {{"layers", "a height > 3"}}),
            "node 'n' (SplatWeights): params.layers: layer line 1: expected 'name: term, term, ...'");
  EXPECT_EQ(migration_error("SplatWeights", {{"layers", "a: slope > 3 ~ -1"}}),
            "node 'n' (SplatWeights): params.layers: layer line 1: softness must be >= 0");
}

TEST(TableMigration, ColorByLayersAndInstance) {
  EXPECT_EQ(migrated_params("ColorByLayers", {{"colors", "grass #5B7F32, dirt #7a6248\nrock #80786f"}})["colors"],
            json::parse(R"([{"name": "grass", "color": "#5b7f32"}, {"name": "dirt", "color": "#7a6248"},
                            {"name": "rock", "color": "#80786f"}])"));
  EXPECT_EQ(migration_error("ColorByLayers", {{"colors", "grass #12"}}),
            "node 'n' (ColorByLayers): params.colors: '#12' is not a #rrggbb color");
  EXPECT_EQ(migrated_params("Instance", {{"names", " tree , , rock"}, {"missing_mesh", "skip"}}),
            json::parse(R"({"names": [{"class": 0, "name": "tree"}, {"class": 2, "name": "rock"}],
                            "missing_mesh": "skip"})"));
  EXPECT_EQ(migrated_params("Instance", {{"names", ""}})["names"], json::array());
}

TEST(TableMigration, LeavesWhatItCannotReadToTheLoader) {
  // A table that is not a string is not converted: the loader reports it with its path.
  const json p = migrated_params("ColorByLayers", {{"colors", 3}});
  EXPECT_EQ(p["colors"], 3);
  const auto r = parse_graph(R"({"format": "orogen-graph", "version": 4, "nodes": [
    {"id": "c", "type": "ColorByLayers", "params": {"colors": 3}}]})",
                             unconnected_inputs_allowed());
  ASSERT_EQ(r.diagnostics.size(), 1u) << r.error_text();
  EXPECT_EQ(r.diagnostics[0].path, "/nodes/0/params/colors");
  // A string the old parser refused fails the migration with the node and the line.
  const auto bad = parse_graph(R"({"format": "orogen-graph", "version": 4, "nodes": [
    {"id": "s", "type": "SplatWeights", "params": {"layers": "rock slope > 30"}}]})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error_text().find("node 's' (SplatWeights): params.layers: layer line 1"), std::string::npos)
      << bad.error_text();
}

}  // namespace
}  // namespace orogen
