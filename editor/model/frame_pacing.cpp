#include "editor/model/frame_pacing.h"

#include <algorithm>

namespace orogen::editor {

FrameWait next_frame_wait(const LoopState& s) {
  if (s.input_pending || s.redraw_frames > 0) return {FrameWait::Mode::Draw, 0.0};
  // A held key repeats and a held button drags: frames follow at the display rate.
  if (s.held) return {FrameWait::Mode::Draw, 0.0};
  std::optional<LoopState::Clock::time_point> wake;
  const auto earliest = [&wake](LoopState::Clock::time_point t) { wake = wake ? std::min(*wake, t) : t; };
  if (s.busy) earliest(s.now + kBusyFrameInterval);
  if (s.last_input && (!s.last_frame || *s.last_frame < *s.last_input + kHoverSettle))
    earliest(*s.last_input + kHoverSettle);
  if (s.autosave_due) earliest(*s.autosave_due);
  if (!wake) return {FrameWait::Mode::WaitForever, 0.0};
  const double seconds = std::chrono::duration<double>(*wake - s.now).count();
  if (seconds <= 0.0) return {FrameWait::Mode::Draw, 0.0};
  return {FrameWait::Mode::WaitTimeout, seconds};
}

}  // namespace orogen::editor
