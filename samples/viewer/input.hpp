// The viewer's input, whoever produces it: the window (a person) or a script. Both
// produce the same InputEvents, and the viewer and its panel see only InputState, so a
// scripted session exercises exactly what a person's does.
//
// Keys are GLFW key codes (GLFW_KEY_*), mouse buttons GLFW button numbers (0 left,
// 1 right, 2 middle); mouse positions are window coordinates (origin top-left, y down,
// as the window system reports them).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace logrid::viewer {

enum class EventType : std::uint8_t {
  KeyDown,
  KeyUp,
  MouseMove,    // x, y: the cursor's new position
  MouseMoveBy,  // x, y: the cursor moved by this much (scripts' drags)
  MouseDown,    // button
  MouseUp,      // button
  Scroll,       // y: wheel steps (positive: away from the user)
  Char,         // codepoint: text typed (for the panel's text fields)
  Resize,       // x, y: a window size asked for (scripts; the window's own size is polled)
  Quit,         // the window was closed
};

struct InputEvent {
  EventType type = EventType::KeyDown;
  int code = 0;         // key or mouse button
  double x = 0, y = 0;  // MouseMove, Scroll (y), Resize
  std::uint32_t codepoint = 0;
};

// Key and button names as scripts write them ("W", "F12", "Escape", "Left", ...); the
// code, or nothing for an unknown name. Case-insensitive.
std::optional<int> keyFromName(const std::string& name);
std::optional<int> mouseButtonFromName(const std::string& name);  // left, right, middle
// "A-Z, 0-9, F1-F12, Escape, ..." for messages.
std::string keyNameList();

// What the input is now, and what happened during the current frame.
class InputState {
 public:
  static constexpr int kMaxKey = 512;
  static constexpr int kButtons = 8;

  // Starts a frame: forgets the previous frame's presses, wheel, motion and text.
  void beginFrame();
  void apply(const InputEvent& event);

  bool down(int key) const { return key >= 0 && key < kMaxKey && keys_[key]; }
  // Went down during this frame (also if it went up again in the same frame).
  bool pressed(int key) const;
  bool buttonDown(int button) const { return button >= 0 && button < kButtons && buttons_[button]; }
  bool buttonPressed(int button) const {
    return button >= 0 && button < kButtons && buttons_pressed_[button];
  }
  bool mouseKnown() const { return mouse_known_; }
  double mouseX() const { return mouse_x_; }
  double mouseY() const { return mouse_y_; }
  // Cursor motion during this frame (window coordinates).
  double motionX() const { return motion_x_; }
  double motionY() const { return motion_y_; }
  double scroll() const { return scroll_; }
  const std::vector<std::uint32_t>& text() const { return text_; }
  const std::vector<int>& pressedKeys() const { return pressed_; }
  bool shift() const;
  bool control() const;
  bool alt() const;
  bool super() const;
  bool quit() const { return quit_; }
  // The last size a Resize event asked for during this frame.
  std::optional<std::pair<int, int>> resize() const { return resize_; }

 private:
  bool keys_[kMaxKey] = {};
  bool buttons_[kButtons] = {};
  bool buttons_pressed_[kButtons] = {};
  std::vector<int> pressed_;
  bool mouse_known_ = false;
  double mouse_x_ = 0, mouse_y_ = 0;
  double motion_x_ = 0, motion_y_ = 0;
  double scroll_ = 0;
  std::vector<std::uint32_t> text_;
  bool quit_ = false;
  std::optional<std::pair<int, int>> resize_;
};

}  // namespace logrid::viewer
