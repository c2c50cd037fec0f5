#pragma once
// When the editor's main loop draws its next frame. An idle editor must cost nothing: with nothing changing it
// blocks until an event (input, an evaluation finishing posts one). It wakes on a timer only for what changes
// on its own: a running preview or build (progress, intermediate results), a held key (ImGui's repeat), the
// canvas tooltip that appears after a hover delay, and the autosave of unsaved work. The text caret does not
// blink (io.ConfigInputTextCursorBlink off), so a focused text field needs no timer either.
#include <chrono>
#include <optional>

namespace orogen::editor {

struct LoopState {
  using Clock = std::chrono::steady_clock;
  Clock::time_point now{};
  bool input_pending = false;  // queued window-system events not yet given to the UI
  int redraw_frames = 0;       // frames still to draw after a change (layout settling, the final state)
  bool busy = false;           // a preview or build runs, or a preview request waits to be sent
  bool held = false;           // a key or mouse button is down
  std::optional<Clock::time_point> last_input;    // when the UI last received input
  std::optional<Clock::time_point> last_frame;    // when the last frame was drawn
  std::optional<Clock::time_point> autosave_due;  // when unsaved work is next written, if any
};

struct FrameWait {
  enum class Mode { Draw, WaitTimeout, WaitForever };
  Mode mode = Mode::WaitForever;
  double seconds = 0.0;  // WaitTimeout: at most this long
};

// The wait before the next frame (no wait: Draw).
FrameWait next_frame_wait(const LoopState& s);

// Frame interval while something runs by itself: progress bars and intermediate results at 30 Hz.
inline constexpr std::chrono::milliseconds kBusyFrameInterval{33};
// A frame at least this long after the last input shows what appears after hovering still (the canvas tooltips
// wait 0.35 s): drawn once, unless a frame was drawn that late already (slow frames after the input).
inline constexpr std::chrono::milliseconds kHoverSettle{400};

}  // namespace orogen::editor
