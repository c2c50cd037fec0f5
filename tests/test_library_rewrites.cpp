// Seed graphs rewritten to use library assets (graphs/library, support/library_rewrites.h): every output file
// byte-identical to the graph before the rewrite (tests/fixtures/before_library), and the same graph once
// expanded.
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "graph/graph_file.h"
#include "graph/subgraph.h"
#include "support/library_rewrites.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).generic_string()] = read_text(e.path());
  return out;
}

TEST(LibraryRewrites, SeedGraphsUseTheLibraryWithOutputsByteIdentical) {
  std::set<std::string> assets;
  for (const auto& name : kLibraryRewrites) {
    SCOPED_TRACE(name);
    const fs::path before = source_dir() / "tests/fixtures/before_library" / name;
    const fs::path after = source_dir() / "graphs" / name;
    const auto old_graph = load_graph_file(before);
    const auto new_graph = load_graph_file(after);
    ASSERT_TRUE(old_graph.ok()) << old_graph.error_text();
    ASSERT_TRUE(new_graph.ok()) << new_graph.error_text();
    EXPECT_FALSE(has_subgraphs(*old_graph.graph));
    // Library assets, by name; the rest of the graph as it was.
    int instances = 0;
    for (const auto& n : new_graph.graph->nodes()) {
      if (!n.type->subgraph) continue;
      ++instances;
      EXPECT_EQ(n.asset.find('/'), std::string::npos) << n.id << ": a library name, not a path";
      assets.insert(n.asset);
    }
    EXPECT_GE(instances, 1);
    EXPECT_LT(new_graph.graph->nodes().size(), old_graph.graph->nodes().size());
    EXPECT_EQ(canonical_graph_text(*new_graph.graph), canonical_graph_text(*old_graph.graph));

    const fs::path dir = scratch_dir("library-rewrite-" + fs::path(name).stem().string());
    for (const auto& [graph, out] : {std::pair{before, dir / "before"}, std::pair{after, dir / "after"}}) {
      const auto r =
          run_process(cli_binary(), {"eval", graph.string(), "--resolution", "64", "-q", "-o", out.string()});
      ASSERT_EQ(r.exit_code, 0) << graph << ": " << r.err;
    }
    const auto a = files_under(dir / "before"), b = files_under(dir / "after");
    ASSERT_GE(a.size(), 3u);
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [file, bytes] : a) {
      ASSERT_TRUE(b.count(file)) << file;
      EXPECT_TRUE(b.at(file) == bytes) << file << " differs with the library asset";
    }
  }
  EXPECT_EQ(assets, (std::set<std::string>{"eroded_mountain_range", "forest_cover", "island", "river_valley"}));
}

}  // namespace
}  // namespace orogen::test
