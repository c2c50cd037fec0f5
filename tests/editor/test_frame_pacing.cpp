// When the main loop draws: an idle editor blocks until an event (no timer at all), and wakes on a timer only
// for what changes by itself: a running evaluation, a held key, the hover tooltip after input, the autosave.
#include <gtest/gtest.h>

#include "editor/model/document.h"
#include "editor/model/frame_pacing.h"
#include "editor/model/recovery.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(FramePacing, IdleBlocksWithoutATimer) {
  LoopState s;
  s.now = Clock::now();
  s.last_input = s.now - 10s;  // input long ago, frames drawn since
  s.last_frame = s.now - 5s;
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::WaitForever);
}

TEST(FramePacing, InputAndPendingRedrawsDrawAtOnce) {
  LoopState s;
  s.now = Clock::now();
  s.input_pending = true;
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::Draw);
  s.input_pending = false;
  s.redraw_frames = 2;
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::Draw);
  s.redraw_frames = 0;
  s.held = true;  // a held key repeats
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::Draw);
}

TEST(FramePacing, ARunningEvaluationRedrawsAtThirtyHertzNotFlatOut) {
  LoopState s;
  s.now = Clock::now();
  s.busy = true;
  const FrameWait w = next_frame_wait(s);
  EXPECT_EQ(w.mode, FrameWait::Mode::WaitTimeout);
  EXPECT_NEAR(w.seconds, 0.033, 1e-9);
}

TEST(FramePacing, OneWakeForTheHoverTooltipAfterInputThenNone) {
  LoopState s;
  s.now = Clock::now();
  s.last_input = s.now - 100ms;
  const FrameWait w = next_frame_wait(s);
  EXPECT_EQ(w.mode, FrameWait::Mode::WaitTimeout);
  EXPECT_NEAR(w.seconds, 0.3, 1e-6) << "at last input + 0.4 s, after the canvas tooltips' 0.35 s";
  s.last_frame = s.now;
  s.now = *s.last_input + kHoverSettle + 1ms;
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::Draw)
      << "slow frames after the input passed the moment without drawing after it: draw now";
  s.last_frame = s.now;  // that frame is drawn
  s.now += 1ms;
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::WaitForever);
}

TEST(FramePacing, TheEarliestTimerWins) {
  LoopState s;
  s.now = Clock::now();
  s.autosave_due = s.now + 5s;
  FrameWait w = next_frame_wait(s);
  EXPECT_EQ(w.mode, FrameWait::Mode::WaitTimeout);
  EXPECT_NEAR(w.seconds, 5.0, 1e-6);
  s.busy = true;
  EXPECT_NEAR(next_frame_wait(s).seconds, 0.033, 1e-9);
  s.busy = false;
  s.autosave_due = s.now - 1s;  // overdue: draw (the frame's tick writes it)
  EXPECT_EQ(next_frame_wait(s).mode, FrameWait::Mode::Draw);
}

TEST(FramePacing, TheAutosaverIsDueOnlyWithSomethingToWrite) {
  const auto dir = test::scratch_dir("frame_pacing_autosave");
  RecoveryStore store(dir / "recovery");
  Autosaver autosaver(store, 20s);
  Document doc(test::chain_graph());
  doc.save_as(dir / "g.json");
  const auto t = Clock::now();
  EXPECT_FALSE(autosaver.next_due(doc)) << "saved: nothing to do, no timer";

  doc.set_param("src", "height", 5.0);
  ASSERT_TRUE(autosaver.next_due(doc));
  EXPECT_LE(*autosaver.next_due(doc), t) << "unsaved and never written: at once";
  EXPECT_TRUE(autosaver.tick(doc, t));
  EXPECT_FALSE(autosaver.next_due(doc)) << "written: nothing new to write";

  doc.set_param("src", "height", 6.0);
  ASSERT_TRUE(autosaver.next_due(doc));
  EXPECT_EQ(*autosaver.next_due(doc), t + 20s) << "a new edit: at the next interval";
  EXPECT_FALSE(autosaver.tick(doc, t + 19s));
  EXPECT_TRUE(autosaver.tick(doc, *autosaver.next_due(doc)));

  doc.save();
  ASSERT_TRUE(autosaver.next_due(doc)) << "saved: the recovery file is to be removed";
  autosaver.tick(doc, t + 21s);
  EXPECT_FALSE(store.has_file());
  EXPECT_FALSE(autosaver.next_due(doc));
}

}  // namespace
}  // namespace orogen::editor
