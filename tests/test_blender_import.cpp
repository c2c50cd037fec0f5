// Orogen's scenes in Blender (issue 28, defect 3), with Debian's Blender headless: scripts/blender_import_scene.py
// imports a scene written with EXT_mesh_gpu_instancing (which Blender 3.4's importer does not know) and the
// nodes variant, and every instance ends up on the terrain Blender shows. Skipped where Blender is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <string>

#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

// 30 boulders (PoissonDisk) on an FBM terrain meshed with a 2 m error bound, as a scene with a terrain.
std::string scene_graph(const std::string& instancing) {
  return R"({
  "format": "orogen-graph", "version": 5,
  "domain": {"origin": [0, 0], "size": [400, 400], "resolution": [65, 65]},
  "nodes": [
    {"id": "height", "type": "FBM", "params": {"feature_size": 200, "amplitude": 60, "seed": 2}},
    {"id": "mesh", "type": "HeightfieldToMesh", "inputs": {"in": "height.out"}, "params": {"max_error": 2.0}},
    {"id": "spots", "type": "PoissonDisk", "inputs": {"height": "height.out"}, "params": {"radius_0": 40}},
    {"id": "rock", "type": "HullRock"},
    {"id": "scene", "type": "Instance", "inputs": {"in": "spots.out", "mesh_0": "rock.out"}},
    {"id": "save", "type": "WriteScene", "inputs": {"in": "scene.out", "terrain": "mesh.out"},
     "params": {"path": "scene.glb", "instancing": ")" +
         instancing + R"("}}
  ]
})";
}

TEST(BlenderImport, InstancesArriveOnTheTerrainWithAndWithoutGpuInstancing) {
  if (std::system("command -v blender > /dev/null 2>&1") != 0) GTEST_SKIP() << "blender is not installed";
  for (const std::string instancing : {"gpu_instancing", "nodes"}) {
    SCOPED_TRACE(instancing);
    const auto dir = scratch_dir("blender-" + instancing);
    write_text(dir / "g.json", scene_graph(instancing));
    const auto e = run_process(cli_binary(), {"eval", (dir / "g.json").string(), "-q", "-o", dir.string()});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    const auto b = run_process("/usr/bin/env", {"blender", "-b", "--factory-startup", "--python",
                                                (source_dir() / "scripts" / "blender_import_scene.py").string(), "--",
                                                (dir / "scene.glb").string()});
    ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(b.out, m, std::regex(R"(orogen: (\d+) instances placed, (\d+) mesh objects)")))
        << b.out;
    const int placed = std::stoi(m[1]), meshes = std::stoi(m[2]);
    // gpu_instancing: the script places every instance; nodes: Blender's importer does.
    if (instancing == "gpu_instancing") EXPECT_GT(placed, 10);
    EXPECT_GT(meshes, 10);
    ASSERT_TRUE(
        std::regex_search(b.out, m, std::regex(R"(largest gap from an instance base to the terrain ([0-9.]+) m)")))
        << b.out;
    EXPECT_LT(std::stod(m[1]), 0.05) << "instances float or sink in Blender";
  }
}

}  // namespace
}  // namespace orogen::test
