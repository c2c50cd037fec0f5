// Graph format version 7: WriteMesh.up_axis defaults to `auto` (y-up OBJ, z-up PLY and STL). An older OBJ
// writer that relied on the old default gets up_axis Z written out, so the file it writes keeps its axes; every
// other writer is left as it was, and a file that names its axis keeps it.
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// The params of a version-6 WriteMesh node after migration (null params: the node has none).
json migrated_writer_params(const json& params) {
  json file = {
      {"format", "orogen-graph"}, {"version", 6}, {"nodes", json::array({{{"id", "w"}, {"type", "WriteMesh"}}})}};
  if (!params.is_null()) file["nodes"][0]["params"] = params;
  EXPECT_EQ(migrate_graph_document(file), 6);
  EXPECT_EQ(file["version"], kGraphFormatVersion);
  return file["nodes"][0].value("params", json());
}

TEST(GraphMigrationV7, ObjWritersKeepZUpOthersAreLeftAlone) {
  EXPECT_EQ(migrated_writer_params({{"path", "t.obj"}}), json({{"path", "t.obj"}, {"up_axis", "Z"}}));
  EXPECT_EQ(migrated_writer_params({{"path", "dir/T.OBJ"}}), json({{"path", "dir/T.OBJ"}, {"up_axis", "Z"}}));
  // No path: the default, terrain.obj.
  EXPECT_EQ(migrated_writer_params(json()), json({{"up_axis", "Z"}}));
  EXPECT_EQ(migrated_writer_params({{"path", "t.ply"}}), json({{"path", "t.ply"}}));
  EXPECT_EQ(migrated_writer_params({{"path", "t.stl"}}), json({{"path", "t.stl"}}));
  EXPECT_EQ(migrated_writer_params({{"path", "t.glb"}}), json({{"path", "t.glb"}}));
  EXPECT_EQ(migrated_writer_params({{"path", "t.obj"}, {"up_axis", "Y"}}), json({{"path", "t.obj"}, {"up_axis", "Y"}}));
  // Malformed parts are left for the loader to report.
  EXPECT_EQ(migrated_writer_params({{"path", 3}}), json({{"path", 3}}));
}

// End to end: a version-6 file evaluated by today's orogen writes its OBJ z-up, as version 6 did, and the same
// graph saved at version 7 without up_axis writes it y-up.
TEST(GraphMigrationV7, OldFileWritesTheSameAxesNewFileGetsYUp) {
  const fs::path dir = test::scratch_dir("migration-v7");
  auto graph = [](int version) {
    return json{{"format", "orogen-graph"},
                {"version", version},
                {"domain", {{"size", {100, 100}}, {"resolution", {3, 3}}}},
                {"nodes",
                 {{{"id", "slope"}, {"type", "LinearGradient"}, {"params", {{"from", 0}, {"to", 50}, {"length", 100}}}},
                  {{"id", "mesh"}, {"type", "HeightfieldToMesh"}, {"inputs", {{"in", "slope.out"}}}},
                  {{"id", "save"},
                   {"type", "WriteMesh"},
                   {"inputs", {{"in", "mesh.out"}}},
                   {"params", {{"path", "t.obj"}, {"normals", false}, {"uvs", false}}}}}}};
  };
  // The range of each axis over the OBJ's vertices. The heights (0..50 m) span the third axis z-up and the
  // second y-up; the domain's 100 m north-south extent the second z-up and the third, negated, y-up.
  struct Range {
    double lo = 1e30, hi = -1e30;
  };
  auto axis_ranges = [](const fs::path& obj) {
    std::ifstream in(obj);
    std::array<Range, 3> r;
    for (std::string line; std::getline(in, line);) {
      if (!line.starts_with("v ")) continue;
      double p[3];
      std::istringstream(line.substr(2)) >> p[0] >> p[1] >> p[2];
      for (int k = 0; k < 3; ++k) r[k] = {std::min(r[k].lo, p[k]), std::max(r[k].hi, p[k])};
    }
    return r;
  };
  for (const int version : {6, kGraphFormatVersion}) {
    const fs::path file = dir / ("v" + std::to_string(version) + ".json");
    test::write_text(file, graph(version).dump());
    const fs::path out = dir / ("out" + std::to_string(version));
    const auto r = test::run_process(test::cli_binary(), {"eval", file.string(), "-o", out.string(), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto range = axis_ranges(out / "t.obj");
    const int up = version == 6 ? 2 : 1, north = version == 6 ? 1 : 2;
    const double sign = version == 6 ? 1.0 : -1.0;  // y-up stores north as -z
    EXPECT_GE(range[up].lo, -1e-3) << "version " << version;
    EXPECT_LE(range[up].hi, 50.0 + 1e-3) << "version " << version;
    EXPECT_GT(range[up].hi, 25.0) << "version " << version;
    EXPECT_GT(sign * (range[north].hi + range[north].lo) / 2, 25.0) << "version " << version << ": north";
  }
}

}  // namespace
}  // namespace orogen
