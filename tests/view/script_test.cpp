// The script format of `logrid view --script` and the input state it drives
// (samples/viewer/script.hpp, input.hpp): what a person does, frame by frame.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <string>

#include "expect_error.hpp"
#include "viewer/input.hpp"
#include "viewer/script.hpp"

namespace {

using logrid::ErrorCode;
using logrid::test::expectError;
using logrid::viewer::EventType;
using logrid::viewer::InputEvent;
using logrid::viewer::InputState;
using logrid::viewer::Script;

TEST(ViewScriptTest, KeyPressesLastOneFrame) {
  const Script s = Script::fromText("# comment\n\n3 key W   # forward\n3 key F12\n");
  const auto at3 = s.eventsAt(3);
  ASSERT_EQ(at3.size(), 2u);
  EXPECT_EQ(at3[0].type, EventType::KeyDown);
  EXPECT_EQ(at3[0].code, GLFW_KEY_W);
  EXPECT_EQ(at3[1].code, GLFW_KEY_F12);
  const auto at4 = s.eventsAt(4);
  ASSERT_EQ(at4.size(), 2u);
  EXPECT_EQ(at4[0].type, EventType::KeyUp);
  EXPECT_TRUE(s.eventsAt(2).empty());
  EXPECT_EQ(s.lastFrame(), 4u);
}

TEST(ViewScriptTest, EveryEventKind) {
  const Script s = Script::fromText(
      "0 key-down LeftShift\n"
      "1 mouse-move 10.5 20\n"
      "1 mouse-down right\n"
      "2 mouse-up right\n"
      "2 click left 5 6\n"
      "4 drag left 30 -12 3\n"
      "9 scroll -2\n"
      "9 text \"a#b\"\n"
      "10 resize 320 200\n"
      "11 key-up leftshift\n");
  auto e = s.eventsAt(1);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].type, EventType::MouseMove);
  EXPECT_EQ(e[0].x, 10.5);
  EXPECT_EQ(e[1].type, EventType::MouseDown);
  EXPECT_EQ(e[1].code, GLFW_MOUSE_BUTTON_RIGHT);
  e = s.eventsAt(2);  // mouse-up, then the click's move and press
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[2].type, EventType::MouseDown);
  // The drag: press at 4, a third of the motion at 5, 6 and 7, release at 8.
  EXPECT_EQ(s.eventsAt(4).back().type, EventType::MouseDown);
  for (std::size_t f = 5; f <= 7; ++f) {
    ASSERT_EQ(s.eventsAt(f).size(), 1u);
    EXPECT_EQ(s.eventsAt(f)[0].type, EventType::MouseMoveBy);
    EXPECT_EQ(s.eventsAt(f)[0].x, 10.0);
    EXPECT_EQ(s.eventsAt(f)[0].y, -4.0);
  }
  EXPECT_EQ(s.eventsAt(8)[0].type, EventType::MouseUp);
  e = s.eventsAt(9);  // the wheel, then "a#b" ('#' inside quotes is text)
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0].y, -2.0);
  EXPECT_EQ(e[2].codepoint, std::uint32_t('#'));
  EXPECT_EQ(s.eventsAt(10)[0].type, EventType::Resize);
  EXPECT_EQ(s.eventsAt(11)[0].code, GLFW_KEY_LEFT_SHIFT);
}

TEST(ViewScriptTest, ErrorsNameTheLineAndWhatToWrite) {
  expectError([] { Script::fromText("0 key W\n1 key NoSuchKey\n", "s.txt"); }, ErrorCode::BadInput,
              {"script s.txt line 2", "unknown key 'NoSuchKey'", "Escape"});
  expectError([] { Script::fromText("5 key W\n4 key W\n"); }, ErrorCode::BadInput,
              {"line 2", "must not decrease"});
  expectError([] { Script::fromText("x key W\n"); }, ErrorCode::BadInput, {"line 1", "frame"});
  expectError([] { Script::fromText("0 jump\n"); }, ErrorCode::BadInput,
              {"unknown event 'jump'", "mouse-move"});
  expectError([] { Script::fromText("0 mouse-move 1 nan\n"); }, ErrorCode::BadInput,
              {"y 'nan' is invalid"});
  expectError([] { Script::fromText("0 mouse-down thumb\n"); }, ErrorCode::BadInput,
              {"left, right or middle"});
  expectError([] { Script::fromText("0 key W extra\n"); }, ErrorCode::BadInput,
              {"unexpected 'extra'"});
  expectError([] { Script::fromText("0 resize 0 10\n"); }, ErrorCode::BadInput, {"width"});
  expectError([] { Script::fromText("0 text abc\n"); }, ErrorCode::BadInput, {"double quotes"});
  expectError([] { Script::fromText("0 drag left 1 1 0\n"); }, ErrorCode::BadInput,
              {"at least 1 frame"});
  expectError([] { Script::fromText("# nothing\n"); }, ErrorCode::BadInput, {"no events"});
  expectError([] { Script::fromFile("/nonexistent/script.txt"); }, ErrorCode::Environment,
              {"/nonexistent/script.txt", "cannot be read"});
}

TEST(ViewInputTest, PressesMotionAndWheelLastOneFrame) {
  InputState in;
  auto event = [](EventType t, int code = 0, double x = 0, double y = 0) {
    InputEvent e;
    e.type = t;
    e.code = code;
    e.x = x;
    e.y = y;
    return e;
  };
  in.beginFrame();
  in.apply(event(EventType::KeyDown, GLFW_KEY_W));
  in.apply(event(EventType::MouseMove, 0, 100, 50));  // the first position: no motion
  in.apply(event(EventType::MouseMove, 0, 110, 45));
  in.apply(event(EventType::Scroll, 0, 0, 1));
  in.apply(event(EventType::MouseDown, GLFW_MOUSE_BUTTON_LEFT));
  in.apply(event(EventType::MouseUp, GLFW_MOUSE_BUTTON_LEFT));
  EXPECT_TRUE(in.down(GLFW_KEY_W));
  EXPECT_TRUE(in.pressed(GLFW_KEY_W));
  EXPECT_EQ(in.motionX(), 10);
  EXPECT_EQ(in.motionY(), -5);
  EXPECT_EQ(in.scroll(), 1);
  EXPECT_TRUE(in.buttonPressed(GLFW_MOUSE_BUTTON_LEFT));  // a click within one frame counts
  EXPECT_FALSE(in.buttonDown(GLFW_MOUSE_BUTTON_LEFT));
  in.beginFrame();
  EXPECT_TRUE(in.down(GLFW_KEY_W));  // still held
  EXPECT_FALSE(in.pressed(GLFW_KEY_W));
  EXPECT_EQ(in.motionX(), 0);
  EXPECT_EQ(in.scroll(), 0);
  EXPECT_FALSE(in.buttonPressed(GLFW_MOUSE_BUTTON_LEFT));
  in.apply(event(EventType::MouseMoveBy, 0, -3, 4));
  EXPECT_EQ(in.mouseX(), 107);
  EXPECT_EQ(in.motionY(), 4);
  in.apply(event(EventType::KeyDown, 100000));  // out of range: ignored, not a crash
  EXPECT_FALSE(in.down(100000));
}

TEST(ViewInputTest, KeyNames) {
  EXPECT_EQ(logrid::viewer::keyFromName("escape"), GLFW_KEY_ESCAPE);
  EXPECT_EQ(logrid::viewer::keyFromName("f12"), GLFW_KEY_F12);
  EXPECT_EQ(logrid::viewer::keyFromName("Period"), GLFW_KEY_PERIOD);
  EXPECT_EQ(logrid::viewer::keyFromName("q"), GLFW_KEY_Q);
  EXPECT_EQ(logrid::viewer::keyFromName("7"), GLFW_KEY_7);
  EXPECT_FALSE(logrid::viewer::keyFromName("F13"));
  EXPECT_FALSE(logrid::viewer::keyFromName("F0"));
  EXPECT_FALSE(logrid::viewer::keyFromName("Hyper"));
  EXPECT_FALSE(logrid::viewer::keyFromName(""));
}

}  // namespace
