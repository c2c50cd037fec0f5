// Files a graph reads are part of its cache keys: a file changed by another tool is read again, never
// served stale from the cache.
#include <filesystem>

#include <gtest/gtest.h>

#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "graph/graph_file.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

void write_constant_exr(const std::filesystem::path& dir, const std::string& name, float value, int resolution) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {resolution, resolution});
  auto flat = run_node("Constant", d, {{"value", double{value}}});
  run_node("WriteHeightfield", d, {{"path", std::string(name)}}, {{"in", flat.outputs[0]}}, OutputPolicy{dir, false});
}

TEST(InputFiles, ChangedFileIsReadAgain) {
  const auto dir = scratch_dir("input-files");
  write_constant_exr(dir, "h.exr", 5.0f, 8);

  Graph g;
  g.domain.size = {100, 100};
  g.domain.resolution = {8, 8};
  g.add_node("ReadHeightfield", "read");
  g.set_param("read", "path", std::string((dir / "h.exr").string()));
  Evaluator evaluator;
  EvalRequest request;
  request.domain = g.domain.to_domain();
  request.nodes = {"read"};

  auto first = evaluator.evaluate(g, request);
  ASSERT_TRUE(first.ok()) << first.nodes["read"].message;
  auto height = std::get<HeightfieldPtr>(first.outputs.at("read").at(0));
  EXPECT_FLOAT_EQ(height->at(3, 3), 5.0f);

  auto again = evaluator.evaluate(g, request);
  EXPECT_EQ(again.nodes["read"].status, NodeStatus::Cached);

  write_constant_exr(dir, "h.exr", 7.0f, 16);  // new contents, new size and modification time
  auto changed = evaluator.evaluate(g, request);
  ASSERT_TRUE(changed.ok());
  EXPECT_EQ(changed.nodes["read"].status, NodeStatus::Computed);
  EXPECT_NE(changed.nodes["read"].key, first.nodes["read"].key);
  EXPECT_FLOAT_EQ(std::get<HeightfieldPtr>(changed.outputs.at("read").at(0))->at(3, 3), 7.0f);
}

TEST(InputFiles, MissingFileFailsAndIsNotCached) {
  const auto dir = scratch_dir("input-files-missing");
  Graph g;
  g.add_node("ReadHeightfield", "read");
  g.set_param("read", "path", std::string((dir / "later.exr").string()));
  Evaluator evaluator;
  EvalRequest request;
  request.domain = Domain::from_extent({0, 0}, {100, 100}, {8, 8});
  request.nodes = {"read"};
  EXPECT_EQ(evaluator.evaluate(g, request).nodes["read"].status, NodeStatus::Failed);
  write_constant_exr(dir, "later.exr", 3.0f, 8);
  auto now = evaluator.evaluate(g, request);
  EXPECT_EQ(now.nodes["read"].status, NodeStatus::Computed);
}

// A heightfield whose value encodes its sample: 1000 j + i.
void write_index_exr(const std::filesystem::path& dir, const std::string& name, const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(1000 * j + i);
  run_node("WriteHeightfield", d, {{"path", std::string(name)}}, {{"in", HeightfieldPtr(h)}}, OutputPolicy{dir, false});
}

TEST(InputFiles, ReadHeightfieldCoversTheRequestedDomainByDefault) {
  const auto dir = scratch_dir("input-files-domain");
  write_index_exr(dir, "h.exr", Domain::from_extent({0, 0}, {100, 100}, {16, 16}));
  const std::string path = (dir / "h.exr").string();
  // A domain elsewhere and larger than the 1024 m of old: the image spans it edge to edge.
  const Domain d = Domain::from_extent({5000, -3000}, {3000, 3000}, {16, 16});
  const auto h = run_node("ReadHeightfield", d, {{"path", path}}).get<Heightfield>();
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) ASSERT_NEAR(h->at(i, j), 1000 * j + i, 1e-2) << i << ", " << j;
  // size and origin place it explicitly: here on the western half only, the east repeating its edge.
  const auto placed = run_node("ReadHeightfield", d,
                               {{"path", path}, {"origin", glm::dvec2(5000, -3000)}, {"size", glm::dvec2(1500, 3000)}})
                          .get<Heightfield>();
  EXPECT_NEAR(placed->at(0, 5), 5000.0f, 1e-2);
  EXPECT_NEAR(placed->at(15, 5), 5015.0f, 1e-2);  // beyond the rectangle: its eastern column
  EXPECT_NEAR(placed->at(14, 5), 5015.0f, 1e-2);
  EXPECT_THROW(run_node("ReadHeightfield", d, {{"path", path}, {"size", glm::dvec2(0, 100)}}), NodeError);
}

TEST(InputFiles, OlderFilesKeepTheirImageRectangle) {
  // Before format version 3 the rectangle defaulted to [0, 1024]^2; such files get it written out.
  for (int version : {1, 2}) {
    const auto r = parse_graph(R"({"format": "orogen-graph", "version": )" + std::to_string(version) + R"(, "nodes": [
      {"id": "read", "type": "ReadHeightfield", "params": {"path": "h.exr"}},
      {"id": "placed", "type": "ReadHeightfield", "params": {"path": "h.exr", "size": [10, 20]}}]})");
    ASSERT_TRUE(r.ok()) << r.error_text();
    EXPECT_EQ(std::get<glm::dvec2>(r.graph->param("read", "size")), glm::dvec2(1024, 1024)) << version;
    EXPECT_EQ(std::get<glm::dvec2>(r.graph->param("placed", "size")), glm::dvec2(10, 20)) << version;
  }
  const auto now = parse_graph(R"({"format": "orogen-graph", "version": 6, "nodes": [
    {"id": "read", "type": "ReadHeightfield", "params": {"path": "h.exr"}}]})");
  ASSERT_TRUE(now.ok());
  EXPECT_EQ(std::get<glm::dvec2>(now.graph->param("read", "size")), glm::dvec2(0, 0));
}

TEST(InputFiles, RelativePathsResolveAgainstTheGraphFile) {
  const auto dir = scratch_dir("input-files-relative");
  std::filesystem::create_directories(dir / "a" / "maps");
  std::filesystem::create_directories(dir / "b" / "maps");
  write_constant_exr(dir / "a" / "maps", "h.exr", 1.0f, 8);
  write_constant_exr(dir / "b" / "maps", "h.exr", 2.0f, 8);
  const std::string text =
      R"({"format": "orogen-graph", "version": 6, "domain": {"size": [100, 100], "resolution": [8, 8]},
    "nodes": [{"id": "read", "type": "ReadHeightfield", "params": {"path": "maps/h.exr"}}]})";
  write_text(dir / "a" / "g.json", text);
  write_text(dir / "b" / "g.json", text);
  Evaluator evaluator;
  EvalRequest request;
  request.domain = Domain::from_extent({0, 0}, {100, 100}, {8, 8});
  request.nodes = {"read"};
  std::vector<CacheKey> keys;
  for (const char* sub : {"a", "b"}) {
    auto loaded = load_graph_file(dir / sub / "g.json");
    ASSERT_TRUE(loaded.ok()) << loaded.error_text();
    EXPECT_EQ(loaded.graph->directory, (dir / sub).lexically_normal());
    auto result = evaluator.evaluate(*loaded.graph, request);
    ASSERT_TRUE(result.ok()) << result.nodes["read"].message;
    EXPECT_EQ(std::get<HeightfieldPtr>(result.outputs.at("read").at(0))->at(2, 2), sub[0] == 'a' ? 1.0f : 2.0f);
    keys.push_back(result.nodes["read"].key);
  }
  EXPECT_NE(keys[0], keys[1]) << "two files of the same size and time must not share a cache entry";
}

}  // namespace
}  // namespace orogen::test
