#pragma once
// Window-system input queued between frames and released to the UI a frame at a time, so that short key
// presses and clicks survive slow frames.
//
// Dear ImGui 1.86 (Debian's) reads input as state: a key counts as pressed in a frame when it is down at
// the frame's start and was up at the previous one. A key pressed and released between two frames (a quick
// Ctrl+Z tap during a 100 ms frame) is never seen down, and a modifier released in the same interval changes
// what the press meant. The GLFW callbacks push raw events here instead; each frame takes events in order up
// to and including the first press (of a key or a mouse button), and never two changes of one key or button:
// a press is always seen down for a whole frame, with the modifiers and pointer position it happened with,
// and releases, moves, wheel and text before it arrive in the same frame. Held keys (repeats) are left to ImGui's own
// repeat.
//
// Typing is the exception: while a text field has the keyboard, a press that types a character (the window system
// sends the key, then its character) is text, not a shortcut. Its character is all the field reads, so neither
// that press nor its release ends a frame: every character typed during a slow frame arrives in the next one, in
// order, up to the first key that edits (Backspace, Enter, arrows, a Ctrl shortcut: no character follows those).
#include <array>
#include <cstddef>
#include <deque>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::editor {

struct RawInput {
  enum class Kind { Key, Button, Move, Scroll, Char };
  Kind kind = Kind::Key;
  int code = 0;        // Key: GLFW key code; Button: GLFW mouse button; Char: Unicode code point
  bool down = false;   // Key, Button
  glm::dvec2 xy{0.0};  // Move: position in window pixels; Scroll: offsets
};

// The input state the UI sees in one frame.
struct InputFrame {
  static constexpr int kKeys = 512, kButtons = 5;
  std::array<bool, kKeys> keys{};
  std::array<bool, kButtons> buttons{};
  bool has_pointer = false;  // a Move has been seen (else the window system's position stands)
  glm::dvec2 pointer{0.0};
  glm::dvec2 wheel{0.0};        // this frame's scrolling
  std::vector<unsigned> chars;  // this frame's text input
};

class InputQueue {
 public:
  void push(const RawInput& e);
  // Updates `state` (keys, buttons, pointer persist; wheel and chars are this frame's) with the events of the
  // next frame and removes them. Returns how many were applied. `typing`: a text field has the keyboard
  // (ImGui's WantTextInput), so the keys that type characters do not end the frame.
  std::size_t next_frame(InputFrame& state, bool typing = false);
  bool empty() const { return events_.empty(); }
  // Queues the release of every key and button that is down after the queued events (focus lost).
  void release_all();
  std::size_t size() const { return events_.size(); }

 private:
  std::deque<RawInput> events_;
  InputFrame after_;                                 // the state once every queued event is applied
  std::array<bool, InputFrame::kKeys> text_keys_{};  // keys whose press was taken as text (until released)
};

}  // namespace orogen::editor
