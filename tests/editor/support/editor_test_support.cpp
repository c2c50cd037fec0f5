#include "support/editor_test_support.h"

#include <atomic>

#include <unistd.h>

namespace orogen::editor::test {

std::filesystem::path scratch_dir(const std::string& name) {
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::path(OROGEN_EDITOR_TEST_SCRATCH) /
                   ("editor-" + name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1)));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

Graph chain_graph() {
  Graph g;
  g.domain.size = {1000.0, 1000.0};
  g.domain.resolution = {64, 64};
  g.add_node("EdSource", "src");
  g.add_node("EdBlend", "mid");
  g.add_node("EdBlend", "out");
  g.add_node("EdScatter", "scatter");
  g.connect({"src", "out"}, "mid", "a");
  g.connect({"mid", "out"}, "out", "a");
  g.connect({"src", "out"}, "scatter", "height");
  g.editor.positions = {{"src", {0, 0}}, {"mid", {300, 0}}, {"out", {600, 0}}, {"scatter", {300, 200}}};
  return g;
}

}  // namespace orogen::editor::test
