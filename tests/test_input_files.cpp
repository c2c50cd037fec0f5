// Files a graph reads are part of its cache keys: a file changed by another tool is read again, never
// served stale from the cache.
#include <gtest/gtest.h>

#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

void write_constant_exr(const std::filesystem::path& dir, const std::string& name, float value, int resolution) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {resolution, resolution});
  auto flat = run_node("Constant", d, {{"value", double{value}}});
  run_node("WriteHeightfield", d, {{"path", std::string(name)}}, {{"in", flat.outputs[0]}},
           OutputPolicy{dir, false});
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

}  // namespace
}  // namespace orogen::test
