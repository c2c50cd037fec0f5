// Graph format version 6: one name per quantity (the glossary of docs/conventions.md). Every older copy of an
// example graph (tests/fixtures/v1 .. v5, taken from the repository's history) loads as the current graph in
// graphs/; the two parameters whose unit
// changed are converted so the outputs stay the same; `orogen migrate` rewrites a file as the loader reads it.
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "graph/angles.h"
#include "graph/calendar.h"
#include "graph/graph_file.h"
#include "graph/graph_migrations.h"
#include "graph/registry.h"
#include "support/rename_checks.h"
#include "support/run_process.h"
#include "support/later_text_edits.h"
#include "support/library_rewrites.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

TEST(GraphMigrationV6, RenamesMatchTheRegistry) {
  test::expect_renames_match_registry(format_v5_renames());
  const auto& registry = NodeRegistry::instance();
  for (const auto& c : format_v5_converted_params()) {
    const NodeType* t = registry.find(c.type);
    ASSERT_NE(t, nullptr) << c.type;
    EXPECT_NE(t->find_param(c.param), nullptr) << c.type << "." << c.param;
  }
}

// Every fixture of an older version loads (migrated) as exactly the example graph of the same name.
TEST(GraphMigrationV6, OlderFixturesLoadAsTheExampleGraphs) {
  std::map<int, int> compared;
  std::map<std::string, int> edited;
  for (const int version : {1, 2, 3, 4, 5}) {
    const fs::path dir = test::source_dir() / "tests/fixtures" / ("v" + std::to_string(version));
    for (const auto& entry : fs::directory_iterator(dir)) {
      const auto name = entry.path().filename();
      const std::string text = test::read_text(entry.path());
      EXPECT_EQ(json::parse(text)["version"], version) << name;
      ASSERT_TRUE(load_graph_file(entry.path()).ok()) << "v" << version << " " << name << " loads unedited";
      const auto old_file = parse_graph(test::with_later_text_edits(text, edited));
      ASSERT_TRUE(old_file.ok()) << name << ": " << old_file.error_text();
      const auto current = load_graph_file(test::source_dir() / "graphs" / name);
      ASSERT_TRUE(current.ok()) << name << ": " << current.error_text();
      if (test::kLibraryRewrites.count(name.string())) {
        EXPECT_EQ(test::canonical_graph_text(*old_file.graph), test::canonical_graph_text(*current.graph))
            << "v" << version << " " << name;
      } else {
        EXPECT_TRUE(*old_file.graph == *current.graph) << "v" << version << " " << name;
        EXPECT_EQ(serialize_graph(*old_file.graph), serialize_graph(*current.graph)) << "v" << version << " " << name;
      }
      ++compared[version];
    }
  }
  // The copies whose content matches today's graph at each version (others changed beyond migrations).
  EXPECT_EQ(compared[1], 3);
  EXPECT_EQ(compared[2], 5);
  EXPECT_EQ(compared[3], 8);
  // Examples written at version 6 have no older copy.
  const std::set<std::string> written_at_v6 = {"landforms.json"};
  int examples = 0;
  for (const auto& entry : fs::directory_iterator(test::source_dir() / "graphs"))
    examples += entry.path().extension() == ".json" && !written_at_v6.count(entry.path().filename().string()) ? 1 : 0;
  // distributed_hydrology.json was written at version 5.
  EXPECT_EQ(compared[4], examples - 1) << "every example graph of format 4's time has its version-4 copy";
  EXPECT_EQ(compared[5], examples) << "every example graph has its version-5 copy";
  for (const auto& edit : test::kLaterTextEdits) EXPECT_EQ(edited[edit.from], edit.fixtures) << edit.from;
}

json migrated_v5_node(const std::string& type, const json& params) {
  json file = {{"format", "orogen-graph"}, {"version", 5}, {"nodes", json::array({{{"id", "n"}, {"type", type}}})}};
  if (!params.is_null()) file["nodes"][0]["params"] = params;
  EXPECT_EQ(migrate_graph_document(file), 5);
  EXPECT_EQ(file["version"], kGraphFormatVersion);
  return file["nodes"][0];
}

TEST(GraphMigrationV6, MonthBecomesADayOfThatMonth) {
  for (int month = 1; month <= 12; ++month) {
    const json node = migrated_v5_node("SunIllumination", {{"month", month}});
    ASSERT_TRUE(node["params"].contains("day_of_year"));
    EXPECT_FALSE(node["params"].contains("month"));
    const int day = node["params"]["day_of_year"].get<int>();
    EXPECT_EQ(calendar::month_of_day(day), month) << day;
  }
  // The old default (June) and the new one name the same month.
  const NodeType* sun = NodeRegistry::instance().find("SunIllumination");
  ASSERT_NE(sun, nullptr);
  EXPECT_EQ(
      calendar::month_of_day(static_cast<int>(std::get<std::int64_t>(sun->find_param("day_of_year")->default_value))),
      6);
  // A month that was out of range stays refused.
  const json bad = {{"format", "orogen-graph"},
                    {"version", 5},
                    {"nodes", json::array({{{"id", "n"}, {"type", "SunIllumination"}, {"params", {{"month", 13}}}}})}};
  EXPECT_FALSE(parse_graph(bad.dump()).ok());
}

TEST(GraphMigrationV6, MonthStartsAndEnds) {
  EXPECT_EQ(calendar::month_of_day(1), 1);
  EXPECT_EQ(calendar::month_of_day(31), 1);
  EXPECT_EQ(calendar::month_of_day(32), 2);
  EXPECT_EQ(calendar::month_of_day(59), 2);
  EXPECT_EQ(calendar::month_of_day(60), 3);
  EXPECT_EQ(calendar::month_of_day(181), 6);
  EXPECT_EQ(calendar::month_of_day(182), 7);
  EXPECT_EQ(calendar::month_of_day(334), 11);
  EXPECT_EQ(calendar::month_of_day(365), 12);
  EXPECT_EQ(calendar::month_of_day(366), 12);
}

TEST(GraphMigrationV6, TropismRadiansBecomeDegreesThatConvertBackExactly) {
  for (const double radians : {0.05, 0.2, -0.3, 1.0, 1e-3, 0.123456789, -1.0}) {
    const json node = migrated_v5_node("Turtle3D", {{"tropism_strength", radians}});
    const double degrees = node["params"]["tropism_strength"].get<double>();
    EXPECT_NEAR(degrees, radians * 180.0 / 3.14159265358979323846, 1e-12 * std::abs(degrees) + 1e-15);
    EXPECT_EQ(radians_from_degrees(degrees), radians) << radians;
    // And through the file's text.
    EXPECT_EQ(radians_from_degrees(json::parse(json(degrees).dump()).get<double>()), radians) << radians;
  }
  EXPECT_EQ(migrated_v5_node("Turtle3D", {{"tropism_strength", 0}})["params"]["tropism_strength"], 0);
}

TEST(GraphMigrationV6, LinksFollowRenamedOutputsOfTheirSourceTypeOnly) {
  json file = json::parse(R"({"format": "orogen-graph", "version": 5, "nodes": [
    {"id": "lakes", "type": "Lakes"},
    {"id": "fill", "type": "FloodFill", "params": {"seed": [10, 20]}},
    {"id": "shade", "type": "Hillshade", "params": {"azimuth": 200, "altitude": 30}},
    {"id": "blend", "type": "Blend", "inputs": {"a": "lakes.depth", "b": "fill.depth", "mask": "fill.mask"}},
    {"id": "other", "type": "Blend", "inputs": {"a": "blend.out", "b": "blend.out", "mask": "blend.mask"}},
    {"id": "w", "type": "WriteImage", "inputs": {"in": "shade.image"}}]})");
  migrate_graph_document(file);
  const json& n = file["nodes"];
  EXPECT_EQ(n[1]["params"], json::parse(R"({"position": [10, 20]})"));
  EXPECT_EQ(n[2]["params"], json::parse(R"({"sun_azimuth": 200, "sun_elevation": 30})"));
  EXPECT_EQ(n[3]["inputs"],
            json::parse(R"({"a": "lakes.water_depth", "b": "fill.water_depth", "mask": "fill.lake_mask"})"));
  EXPECT_EQ(n[4]["inputs"]["mask"], "blend.mask") << "Blend has no renamed output";
  EXPECT_EQ(n[5]["inputs"]["in"], "shade.color");
}

// `orogen migrate` writes what the loader reads, keeps the file's layout, and --check tells older files apart.
TEST(GraphMigrationV6, MigrateCommandRewritesAFileInPlace) {
  const auto dir = test::scratch_dir("migrate-command");
  const auto v5 = test::source_dir() / "tests/fixtures/v5/hydrology.json";
  fs::copy_file(v5, dir / "hydrology.json");
  auto check = test::run_process(test::cli_binary(), {"migrate", "--check", (dir / "hydrology.json").string()});
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  EXPECT_EQ(test::read_text(dir / "hydrology.json"), test::read_text(v5)) << "--check writes nothing";
  const auto run = test::run_process(test::cli_binary(), {"migrate", (dir / "hydrology.json").string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_THAT(run.out, ::testing::HasSubstr("version 5 -> " + std::to_string(kGraphFormatVersion)));
  // The example graph is what the command made of its version-5 copy: only the renamed lines differ.
  EXPECT_EQ(test::read_text(dir / "hydrology.json"), test::read_text(test::source_dir() / "graphs/hydrology.json"));
  check = test::run_process(test::cli_binary(), {"migrate", "--check", (dir / "hydrology.json").string()});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  test::write_text(dir / "newer.json", R"({"format": "orogen-graph", "version": 99, "nodes": []})");
  EXPECT_EQ(test::run_process(test::cli_binary(), {"migrate", (dir / "newer.json").string()}).exit_code, 2);
}

// A structural migration (version 3 -> 4 inserts Instance nodes) lays the file out anew; it still loads as the
// example graph.
TEST(GraphMigrationV6, MigrateCommandLaysOutStructuralChanges) {
  const auto dir = test::scratch_dir("migrate-command-v4");
  fs::copy_file(test::source_dir() / "tests/fixtures/v4/scene.json", dir / "scene.json");
  const auto run = test::run_process(test::cli_binary(), {"migrate", (dir / "scene.json").string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const auto migrated = load_graph_file(dir / "scene.json");
  ASSERT_TRUE(migrated.ok()) << migrated.error_text();
  const auto current = load_graph_file(test::source_dir() / "graphs/scene.json");
  ASSERT_TRUE(current.ok());
  EXPECT_EQ(serialize_graph(*migrated.graph), serialize_graph(*current.graph));
}

}  // namespace
}  // namespace orogen
