// The input queue: a key tapped between two frames is seen pressed in exactly one frame, with the modifiers
// it was pressed with, however slow the frames; releases and moves are not delayed behind nothing.
#include <cctype>
#include <string>

#include <gtest/gtest.h>

#include "editor/model/input_queue.h"

namespace orogen::editor {
namespace {

constexpr int kCtrl = 341, kShift = 340, kZ = 90;  // GLFW_KEY_LEFT_CONTROL, GLFW_KEY_LEFT_SHIFT, GLFW_KEY_Z

RawInput key(int code, bool down) { return {RawInput::Kind::Key, code, down, {}}; }
RawInput button(int b, bool down) { return {RawInput::Kind::Button, b, down, {}}; }
RawInput move(double x, double y) { return {RawInput::Kind::Move, 0, false, {x, y}}; }
RawInput chr(unsigned c) { return {RawInput::Kind::Char, static_cast<int>(c), false, {}}; }

// What GLFW sends for a typed letter: the key (GLFW_KEY_A.. are the upper-case ASCII codes), then its character.
void type(InputQueue& q, const std::string& text) {
  for (char c : text) {
    const int code = std::toupper(static_cast<unsigned char>(c));
    q.push(key(code, true));
    q.push(chr(static_cast<unsigned char>(c)));
    q.push(key(code, false));
  }
}
std::string text_of(const InputFrame& f) { return std::string(f.chars.begin(), f.chars.end()); }
constexpr int kBackspace = 259, kA = 65;  // GLFW_KEY_BACKSPACE, GLFW_KEY_A

// What ImGui 1.86 does with the state it is given each frame: a key is "pressed" in a frame when it is down
// and was not at the previous frame; Ctrl+Z undoes when Z is pressed while Ctrl is down.
struct PollingUi {
  InputFrame previous;
  int undos = 0, redos = 0, clicks = 0;
  glm::dvec2 click_at{0.0};
  void frame(const InputFrame& now) {
    const bool z = now.keys[kZ] && !previous.keys[kZ];
    if (z && now.keys[kCtrl]) (now.keys[kShift] ? redos : undos)++;
    if (now.buttons[0] && !previous.buttons[0]) {
      ++clicks;
      click_at = now.pointer;
    }
    previous = now;
  }
};

// Runs frames until the queue is empty (plus one), as the editor does while input is pending.
void drain(InputQueue& q, InputFrame& state, PollingUi& ui) {
  do {
    q.next_frame(state);
    ui.frame(state);
  } while (!q.empty());
  q.next_frame(state);
  ui.frame(state);
}

TEST(InputQueue, TappedCtrlZBetweenTwoFramesUndoesOnce) {
  InputQueue q;
  InputFrame state;
  PollingUi ui;
  for (auto e : {key(kCtrl, true), key(kZ, true), key(kZ, false), key(kCtrl, false)}) q.push(e);
  drain(q, state, ui);
  EXPECT_EQ(ui.undos, 1);
  EXPECT_EQ(ui.redos, 0);
  EXPECT_FALSE(state.keys[kZ]);
  EXPECT_FALSE(state.keys[kCtrl]);
}

TEST(InputQueue, WithoutTheQueueTheTapIsLost) {
  // The failure the queue fixes: polling only the state at frame start sees nothing of a tap.
  InputFrame state;
  PollingUi ui;
  for (auto e : {key(kCtrl, true), key(kZ, true), key(kZ, false), key(kCtrl, false)}) {
    InputQueue one;  // every event applied before the same frame
    one.push(e);
    one.next_frame(state);
  }
  ui.frame(state);
  EXPECT_EQ(ui.undos, 0);
}

TEST(InputQueue, ThreeTapsInOneSlowFrameUndoThreeTimes) {
  InputQueue q;
  InputFrame state;
  PollingUi ui;
  q.push(key(kCtrl, true));
  for (int k = 0; k < 3; ++k) {
    q.push(key(kZ, true));
    q.push(key(kZ, false));
  }
  q.push(key(kShift, true));  // then Ctrl+Shift+Z: a redo, not a fourth undo
  q.push(key(kZ, true));
  q.push(key(kZ, false));
  q.push(key(kShift, false));
  q.push(key(kCtrl, false));
  drain(q, state, ui);
  EXPECT_EQ(ui.undos, 3);
  EXPECT_EQ(ui.redos, 1);
}

TEST(InputQueue, ModifierReleasedRightAfterThePressStillCounts) {
  // Ctrl held, Z pressed, Ctrl released before Z within one frame: the press happened with Ctrl.
  InputQueue q;
  InputFrame state;
  PollingUi ui;
  q.push(key(kCtrl, true));
  q.next_frame(state);
  ui.frame(state);
  for (auto e : {key(kZ, true), key(kCtrl, false), key(kZ, false)}) q.push(e);
  drain(q, state, ui);
  EXPECT_EQ(ui.undos, 1);
}

TEST(InputQueue, AClickIsSeenWhereItHappenedAndReleasesDoNotWait) {
  InputQueue q;
  InputFrame state;
  PollingUi ui;
  for (auto e : {move(10, 10), move(20, 30), button(0, true), move(50, 50), button(0, false), move(60, 70)}) q.push(e);
  EXPECT_EQ(q.size(), 5u);             // the first two moves collapse
  EXPECT_EQ(q.next_frame(state), 2u);  // up to and including the press
  ui.frame(state);
  EXPECT_EQ(ui.clicks, 1);
  EXPECT_EQ(ui.click_at, glm::dvec2(20, 30));
  EXPECT_EQ(q.next_frame(state), 3u);  // the rest has no press: one frame
  ui.frame(state);
  EXPECT_FALSE(state.buttons[0]);
  EXPECT_EQ(state.pointer, glm::dvec2(60, 70));
  EXPECT_TRUE(q.empty());
}

TEST(InputQueue, FocusLostReleasesWhatIsHeld) {
  InputQueue q;
  InputFrame state;
  q.push(key(kCtrl, true));
  q.push(button(0, true));
  q.next_frame(state);
  q.next_frame(state);
  q.push(key(kZ, true));  // still queued when the focus goes
  q.release_all();
  while (!q.empty()) q.next_frame(state);
  EXPECT_FALSE(state.keys[kCtrl]);
  EXPECT_FALSE(state.keys[kZ]);
  EXPECT_FALSE(state.buttons[0]);
}

TEST(InputQueue, WheelAndTextAreThisFramesOnly) {
  InputQueue q;
  InputFrame state;
  q.push({RawInput::Kind::Scroll, 0, false, {0, 1}});
  q.push({RawInput::Kind::Scroll, 0, false, {0, 2}});
  q.push({RawInput::Kind::Char, 'a', false, {}});
  q.next_frame(state);
  EXPECT_EQ(state.wheel, glm::dvec2(0, 3));
  ASSERT_EQ(state.chars.size(), 1u);
  q.next_frame(state);
  EXPECT_EQ(state.wheel, glm::dvec2(0, 0));
  EXPECT_TRUE(state.chars.empty());
}

TEST(InputQueue, SixteenCharactersTypedDuringOneFrameArriveInTheNext) {
  // A text field has the keyboard: typing must not take a frame per character (16 frames of a slow UI are seconds).
  InputQueue q;
  InputFrame state;
  type(q, "ridges aa valley");  // 16 characters, a letter twice in a row among them
  EXPECT_EQ(q.next_frame(state, /*typing=*/true), 48u);
  EXPECT_EQ(text_of(state), "ridges aa valley");
  EXPECT_TRUE(q.empty());
  for (bool down : state.keys) EXPECT_FALSE(down);
}

TEST(InputQueue, AnEditingKeyWhileTypingStillEndsItsFrameInOrder) {
  // "ab", Backspace, "c": the field must see a, b, then the Backspace, then c (not c before the Backspace).
  InputQueue q;
  InputFrame state;
  type(q, "ab");
  q.push(key(kBackspace, true));
  q.push(key(kBackspace, false));
  type(q, "c");
  q.next_frame(state, true);
  EXPECT_EQ(text_of(state), "ab");
  EXPECT_TRUE(state.keys[kBackspace]) << "the Backspace press is seen down for a whole frame";
  q.next_frame(state, true);
  EXPECT_EQ(text_of(state), "c");
  EXPECT_FALSE(state.keys[kBackspace]);
  EXPECT_TRUE(q.empty());
}

TEST(InputQueue, ShortcutsWhileTypingAndLettersOnTheCanvasArePresses) {
  // Ctrl+A in a field sends no character: a press like any other. On the canvas (not typing) a letter is a
  // shortcut (F frames, X deletes): it must be seen pressed, so it still ends its frame.
  InputQueue q;
  InputFrame state;
  q.push(key(kCtrl, true));
  q.push(key(kA, true));
  q.push(key(kA, false));
  q.push(key(kCtrl, false));
  q.next_frame(state, true);  // Ctrl
  q.next_frame(state, true);
  EXPECT_TRUE(state.keys[kA] && state.keys[kCtrl]);
  while (!q.empty()) q.next_frame(state, true);

  type(q, "fx");
  q.next_frame(state, /*typing=*/false);
  EXPECT_TRUE(state.keys['F']);
  EXPECT_TRUE(state.chars.empty()) << "its character comes with the next frame";
  q.next_frame(state, false);
  EXPECT_EQ(text_of(state), "f");
  EXPECT_TRUE(state.keys['X']);
}

}  // namespace
}  // namespace orogen::editor
