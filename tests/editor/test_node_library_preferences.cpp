// The editor's list of node libraries to load at every start (editor/model/node_library_preferences.h).
#include <gtest/gtest.h>

#include <fstream>

#include "editor/model/node_library_preferences.h"

namespace orogen::editor {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::path(OROGEN_EDITOR_TEST_SCRATCH) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(NodeLibraryPreferences, KeepsTheListAcrossSessions) {
  const auto file = scratch("node-library-prefs") / "node_libraries.json";
  {
    NodeLibraryPreferences prefs(file);
    EXPECT_TRUE(prefs.files().empty());
    prefs.add("/opt/nodes/libcanyon_nodes.so");
    prefs.add("/opt/nodes/../nodes/libcanyon_nodes.so");  // the same file: listed once
    prefs.add("/opt/nodes/libscatter_nodes.so");
  }
  NodeLibraryPreferences again(file);
  EXPECT_EQ(again.files(),
            (std::vector<std::filesystem::path>{"/opt/nodes/libcanyon_nodes.so", "/opt/nodes/libscatter_nodes.so"}));
  again.remove("/opt/nodes/libcanyon_nodes.so");
  EXPECT_EQ(NodeLibraryPreferences(file).files(),
            (std::vector<std::filesystem::path>{"/opt/nodes/libscatter_nodes.so"}));
}

TEST(NodeLibraryPreferences, ADamagedListIsEmptyAndALibraryThatFailsIsReported) {
  const auto dir = scratch("node-library-prefs-damaged");
  std::ofstream(dir / "node_libraries.json") << "{ not json";
  NodeLibraryPreferences prefs(dir / "node_libraries.json");
  EXPECT_TRUE(prefs.files().empty());
  prefs.add(dir / "missing.so");
  const auto errors = load_editor_node_libraries(prefs, {(dir / "also_missing.so").string()});
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_NE(errors[0].find("missing.so"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("also_missing.so': cannot be read"), std::string::npos) << errors[1];
}

}  // namespace
}  // namespace orogen::editor
