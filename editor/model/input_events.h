#pragma once
// Mouse and keyboard events in a form independent of ImGui and GLFW. The UI translates its frame's input
// into these; tests feed them directly, so interaction is tested without a window.
#include <string>
#include <variant>

#include <glm/vec2.hpp>

namespace orogen::editor {

enum class MouseButton { Left, Right, Middle };

// Only the keys the editor binds.
enum class Key { Tab, Enter, Escape, Up, Down, Backspace, Delete, Space, A, C, D, F, G, V, X, Y, Z, Home };

struct Modifiers {
  bool ctrl = false, shift = false, alt = false;
};

struct MouseMove {
  glm::dvec2 pos{0.0};  // screen pixels
};
struct MouseDown {
  MouseButton button = MouseButton::Left;
  glm::dvec2 pos{0.0};
  Modifiers mods;
};
struct MouseUp {
  MouseButton button = MouseButton::Left;
  glm::dvec2 pos{0.0};
  Modifiers mods;
};
struct Wheel {
  glm::dvec2 pos{0.0};
  double notches = 0.0;  // positive: away from the user (zoom in)
};
struct KeyDown {
  Key key = Key::Escape;
  Modifiers mods;
};
struct KeyUp {
  Key key = Key::Escape;
};
struct TextInput {
  std::string text;  // UTF-8
};

using InputEvent = std::variant<MouseMove, MouseDown, MouseUp, Wheel, KeyDown, KeyUp, TextInput>;

}  // namespace orogen::editor
