// graphs/terrain.json, the example island: it loads, evaluates, and produces an island (sea on the border,
// mountains inside, coloured by height) plus its four files.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/mesh.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

Graph load_terrain() {
  const auto result = load_graph_file(test::source_dir() / "graphs" / "terrain.json");
  EXPECT_TRUE(result.ok()) << result.error_text();
  return *result.graph;
}

TEST(TerrainGraph, IsAnIslandWithMountainsAndAColourMap) {
  const Graph graph = load_terrain();
  const Domain d = Domain::from_extent({0, 0}, {4096, 4096}, {257, 257});  // half the file's resolution
  Evaluator evaluator;
  EvalRequest request;
  request.domain = d;
  request.nodes = {"elevation", "color", "mesh"};
  const EvalResult result = evaluator.evaluate(graph, request);
  ASSERT_TRUE(result.ok());
  const auto height = std::get<HeightfieldPtr>(result.output("elevation", "out", graph));
  const auto colour = std::get<ImagePtr>(result.output("color", "out", graph));
  const auto mesh = std::get<MeshPtr>(result.output("mesh", "out", graph));
  ASSERT_TRUE(height && colour && mesh);

  // Sea all around the border, land in the middle, high mountains somewhere.
  const int n = d.width();
  for (int k = 0; k < n; ++k) {
    EXPECT_LT(height->at(k, 0), 0.0f);
    EXPECT_LT(height->at(k, n - 1), 0.0f);
    EXPECT_LT(height->at(0, k), 0.0f);
    EXPECT_LT(height->at(n - 1, k), 0.0f);
  }
  EXPECT_EQ(height->at(0, 0), -95.0f);  // corners lie beyond the island's radius: the sea floor
  const auto land = std::count_if(height->data.begin(), height->data.end(), [](float h) { return h > 0.0f; });
  const double land_fraction = static_cast<double>(land) / static_cast<double>(height->data.size());
  EXPECT_GT(land_fraction, 0.3);
  EXPECT_LT(land_fraction, 0.8);
  EXPECT_GT(*std::max_element(height->data.begin(), height->data.end()), 500.0f);

  // Water is blue, the highest point is rock or snow (grey: similar channels).
  ASSERT_EQ(colour->channels, 4);
  const float* sea = colour->pixel(0, 0);
  EXPECT_GT(sea[2], 2 * sea[0]);
  const auto top = std::max_element(height->data.begin(), height->data.end()) - height->data.begin();
  const float* peak = colour->data.data() + static_cast<std::size_t>(top) * 4;
  EXPECT_LT(std::abs(peak[0] - peak[2]), 0.25f);

  // The mesh is decimated and spans the domain.
  EXPECT_GT(mesh->face_count(), 1000u);
  EXPECT_LT(mesh->face_count(), 2u * 128u * 128u);  // fewer than the 32 m grid's triangles
}

TEST(TerrainGraph, WritesItsFourFiles) {
  const Graph graph = load_terrain();
  const auto dir = test::scratch_dir("terrain-graph");
  EvaluatorOptions options;
  options.output.output_dir = dir;
  Evaluator evaluator(options);
  EvalRequest request;
  request.domain = Domain::from_extent({0, 0}, {4096, 4096}, {129, 129});
  const EvalResult result = evaluator.evaluate(graph, request);
  ASSERT_TRUE(result.ok());
  for (const char* file : {"terrain/height.exr", "terrain/height.png", "terrain/color.png", "terrain/terrain.obj"}) {
    const auto p = dir / file;
    ASSERT_TRUE(std::filesystem::exists(p)) << p;
    EXPECT_GT(std::filesystem::file_size(p), 1000u) << p;
  }
  std::ifstream obj(dir / "terrain/terrain.obj");
  std::string line;
  std::size_t faces = 0;
  while (std::getline(obj, line)) faces += line.rfind("f ", 0) == 0;
  EXPECT_GT(faces, 1000u);
}

}  // namespace
}  // namespace orogen
