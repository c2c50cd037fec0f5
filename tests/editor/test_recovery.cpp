// Never lose work: autosave to a recovery file, found and restored after a crash; recent files; the state
// directory.
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "editor/model/document.h"
#include "editor/model/recent_files.h"
#include "editor/model/recovery.h"
#include "editor/model/state_dir.h"
#include "graph/graph_file.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

using namespace std::chrono_literals;

TEST(Autosaver, WritesWhileDirtyAndRemovesWhenSaved) {
  const auto dir = test::scratch_dir("autosave");
  RecoveryStore store(dir / "recovery");
  Autosaver autosaver(store, 10s);
  Document doc(test::chain_graph());
  doc.save_as(dir / "g.json");
  auto t = std::chrono::steady_clock::now();
  EXPECT_FALSE(autosaver.tick(doc, t));
  EXPECT_FALSE(store.has_file()) << "nothing unsaved, nothing to recover";

  doc.set_param("src", "height", 5.0);
  EXPECT_TRUE(autosaver.tick(doc, t));
  EXPECT_TRUE(store.has_file());
  doc.set_param("src", "height", 6.0);
  EXPECT_FALSE(autosaver.tick(doc, t + 5s)) << "not before the interval";
  EXPECT_TRUE(autosaver.tick(doc, t + 11s));
  EXPECT_FALSE(autosaver.tick(doc, t + 30s)) << "nothing new since the last write";

  doc.save();
  autosaver.tick(doc, t + 31s);
  EXPECT_FALSE(store.has_file());
}

TEST(Recovery, ARunningSessionsFileIsNotOffered) {
  const auto dir = test::scratch_dir("running");
  RecoveryStore running(dir);
  running.write(test::chain_graph(), {});
  RecoveryStore next(dir);
  EXPECT_TRUE(next.orphans().empty());
}

// A child process edits, autosaves and dies without cleaning up; the next session finds and restores it.
TEST(Recovery, CrashRecoveryFileIsFoundAndRestored) {
  const auto dir = test::scratch_dir("crash");
  Document doc(test::chain_graph());
  doc.save_as(dir / "work.json");
  doc.set_param("mid", "weight", 0.125);
  doc.add_node("EdBlend", {900, 100});
  const std::string expected = serialize_graph(doc.graph());

  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    RecoveryStore store(dir / "recovery");
    Autosaver autosaver(store);
    autosaver.tick(doc, std::chrono::steady_clock::now());
    std::abort();  // crash: no destructor, no discard
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status));

  RecoveryStore next(dir / "recovery");
  const auto found = next.orphans();
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].original, dir / "work.json");
  EXPECT_FALSE(found[0].saved_at.empty());
  const Graph restored = RecoveryStore::load(found[0]);
  EXPECT_EQ(serialize_graph(restored), expected);
  RecoveryStore::remove(found[0]);
  EXPECT_TRUE(next.orphans().empty());
}

TEST(Recovery, CleanExitLeavesNothingBehind) {
  const auto dir = test::scratch_dir("clean");
  {
    RecoveryStore store(dir);
    store.write(test::chain_graph(), {});
    store.discard();
  }
  RecoveryStore next(dir);
  EXPECT_TRUE(next.orphans().empty());
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u) << "only the new session's lock";
}

std::string name_of(int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "g%d.json", k);
  return buf;
}

TEST(RecentFiles, NewestFirstDeduplicatedBoundedAndPersistent) {
  const auto dir = test::scratch_dir("recent");
  {
    RecentFiles recent(dir / "recent.json");
    for (int k = 0; k < 15; ++k) recent.add(dir / name_of(k));
    recent.add(dir / "g12.json");
    ASSERT_EQ(recent.paths().size(), RecentFiles::kMax);
    EXPECT_EQ(recent.paths()[0], dir / "g12.json");
    EXPECT_EQ(recent.paths()[1], dir / "g14.json");
  }
  RecentFiles again(dir / "recent.json");
  ASSERT_EQ(again.paths().size(), RecentFiles::kMax);
  EXPECT_EQ(again.paths()[0], dir / "g12.json");
  again.remove(dir / "g12.json");
  EXPECT_EQ(again.paths()[0], dir / "g14.json");
}

TEST(StateDir, FollowsXdgStateHome) {
  const char* old = std::getenv("XDG_STATE_HOME");
  const std::string saved = old ? old : "";
  ::setenv("XDG_STATE_HOME", "/tmp/some-state", 1);
  EXPECT_EQ(default_state_dir(), std::filesystem::path("/tmp/some-state/orogen"));
  ::setenv("XDG_STATE_HOME", "relative/ignored", 1);
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(default_state_dir(), std::filesystem::path("/home/someone/.local/state/orogen"));
  if (old)
    ::setenv("XDG_STATE_HOME", saved.c_str(), 1);
  else
    ::unsetenv("XDG_STATE_HOME");
}

}  // namespace
}  // namespace orogen::editor
