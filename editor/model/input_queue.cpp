#include "editor/model/input_queue.h"

namespace orogen::editor {

void InputQueue::push(const RawInput& e) {
  if (e.kind == RawInput::Kind::Key && e.code >= 0 && e.code < InputFrame::kKeys)
    after_.keys[static_cast<std::size_t>(e.code)] = e.down;
  if (e.kind == RawInput::Kind::Button && e.code >= 0 && e.code < InputFrame::kButtons)
    after_.buttons[static_cast<std::size_t>(e.code)] = e.down;
  // Consecutive moves collapse into the last one (a fast mouse makes hundreds between frames).
  if (e.kind == RawInput::Kind::Move && !events_.empty() && events_.back().kind == RawInput::Kind::Move) {
    events_.back() = e;
    return;
  }
  events_.push_back(e);
}

void InputQueue::release_all() {
  for (int k = 0; k < InputFrame::kKeys; ++k)
    if (after_.keys[static_cast<std::size_t>(k)]) push({RawInput::Kind::Key, k, false, {}});
  for (int b = 0; b < InputFrame::kButtons; ++b)
    if (after_.buttons[static_cast<std::size_t>(b)]) push({RawInput::Kind::Button, b, false, {}});
}

std::size_t InputQueue::next_frame(InputFrame& state, bool typing) {
  state.wheel = glm::dvec2(0.0);
  state.chars.clear();
  std::size_t applied = 0;
  std::array<bool, InputFrame::kKeys> key_changed{};
  std::array<bool, InputFrame::kButtons> button_changed{};
  while (!events_.empty()) {
    const RawInput e = events_.front();
    const bool key = e.kind == RawInput::Kind::Key && e.code >= 0 && e.code < InputFrame::kKeys;
    const auto code = static_cast<std::size_t>(key ? e.code : 0);
    // While typing, a press followed by its character is text, and so is its release: neither counts as a
    // change of the key (a frame takes "aa" whole) nor ends the frame.
    const bool text_press = key && typing && e.down && events_.size() > 1 && events_[1].kind == RawInput::Kind::Char;
    const bool text_release = key && !e.down && text_keys_[code];
    const bool text = text_press || text_release;
    // A key or button changes at most once a frame (else a release and a press cancel out).
    if (key && !text) {
      if (key_changed[code]) break;
      key_changed[code] = true;
    }
    if (e.kind == RawInput::Kind::Button && e.code >= 0 && e.code < InputFrame::kButtons) {
      if (button_changed[static_cast<std::size_t>(e.code)]) break;
      button_changed[static_cast<std::size_t>(e.code)] = true;
    }
    events_.pop_front();
    ++applied;
    bool press = false;
    switch (e.kind) {
      case RawInput::Kind::Key:
        if (key) {
          press = e.down && !state.keys[code] && !text;
          state.keys[code] = e.down;
          text_keys_[code] = e.down && text;
        }
        break;
      case RawInput::Kind::Button:
        if (e.code >= 0 && e.code < InputFrame::kButtons) {
          press = e.down && !state.buttons[static_cast<std::size_t>(e.code)];
          state.buttons[static_cast<std::size_t>(e.code)] = e.down;
        }
        break;
      case RawInput::Kind::Move:
        state.pointer = e.xy;
        state.has_pointer = true;
        break;
      case RawInput::Kind::Scroll:
        state.wheel += e.xy;
        break;
      case RawInput::Kind::Char:
        state.chars.push_back(static_cast<unsigned>(e.code));
        break;
    }
    if (press) break;  // a press ends its frame
  }
  return applied;
}

}  // namespace orogen::editor
