#include "viewer/input.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>

namespace logrid::viewer {
namespace {

struct NamedKey {
  const char* name;
  int code;
};

// Keys other than letters, digits and F1-F12 (those are computed).
const NamedKey kKeys[] = {
    {"Escape", GLFW_KEY_ESCAPE},
    {"Enter", GLFW_KEY_ENTER},
    {"Tab", GLFW_KEY_TAB},
    {"Backspace", GLFW_KEY_BACKSPACE},
    {"Delete", GLFW_KEY_DELETE},
    {"Insert", GLFW_KEY_INSERT},
    {"Space", GLFW_KEY_SPACE},
    {"Left", GLFW_KEY_LEFT},
    {"Right", GLFW_KEY_RIGHT},
    {"Up", GLFW_KEY_UP},
    {"Down", GLFW_KEY_DOWN},
    {"PageUp", GLFW_KEY_PAGE_UP},
    {"PageDown", GLFW_KEY_PAGE_DOWN},
    {"Home", GLFW_KEY_HOME},
    {"End", GLFW_KEY_END},
    {"Comma", GLFW_KEY_COMMA},
    {"Period", GLFW_KEY_PERIOD},
    {"Minus", GLFW_KEY_MINUS},
    {"Equal", GLFW_KEY_EQUAL},
    {"Slash", GLFW_KEY_SLASH},
    {"LeftShift", GLFW_KEY_LEFT_SHIFT},
    {"RightShift", GLFW_KEY_RIGHT_SHIFT},
    {"LeftControl", GLFW_KEY_LEFT_CONTROL},
    {"RightControl", GLFW_KEY_RIGHT_CONTROL},
    {"LeftAlt", GLFW_KEY_LEFT_ALT},
    {"RightAlt", GLFW_KEY_RIGHT_ALT},
    {"LeftSuper", GLFW_KEY_LEFT_SUPER},
    {"RightSuper", GLFW_KEY_RIGHT_SUPER},
};

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::optional<int> keyFromName(const std::string& name) {
  const std::string n = lower(name);
  if (n.size() == 1 && n[0] >= 'a' && n[0] <= 'z') return GLFW_KEY_A + (n[0] - 'a');
  if (n.size() == 1 && n[0] >= '0' && n[0] <= '9') return GLFW_KEY_0 + (n[0] - '0');
  if (n.size() >= 2 && n.size() <= 3 && n[0] == 'f' &&
      std::all_of(n.begin() + 1, n.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const int k = std::stoi(n.substr(1));
    if (k >= 1 && k <= 12) return GLFW_KEY_F1 + (k - 1);
  }
  for (const NamedKey& k : kKeys) {
    if (n == lower(k.name)) return k.code;
  }
  return std::nullopt;
}

std::optional<int> mouseButtonFromName(const std::string& name) {
  const std::string n = lower(name);
  if (n == "left") return GLFW_MOUSE_BUTTON_LEFT;
  if (n == "right") return GLFW_MOUSE_BUTTON_RIGHT;
  if (n == "middle") return GLFW_MOUSE_BUTTON_MIDDLE;
  return std::nullopt;
}

std::string keyNameList() {
  std::string out = "A-Z, 0-9, F1-F12";
  for (const NamedKey& k : kKeys) out += std::string(", ") + k.name;
  return out;
}

void InputState::beginFrame() {
  pressed_.clear();
  std::fill(std::begin(buttons_pressed_), std::end(buttons_pressed_), false);
  motion_x_ = motion_y_ = 0;
  scroll_ = 0;
  text_.clear();
  resize_.reset();
}

void InputState::apply(const InputEvent& e) {
  switch (e.type) {
    case EventType::KeyDown:
      if (e.code >= 0 && e.code < kMaxKey) {
        keys_[e.code] = true;
        pressed_.push_back(e.code);
      }
      break;
    case EventType::KeyUp:
      if (e.code >= 0 && e.code < kMaxKey) keys_[e.code] = false;
      break;
    case EventType::MouseMove:
      if (mouse_known_) {
        motion_x_ += e.x - mouse_x_;
        motion_y_ += e.y - mouse_y_;
      }
      mouse_known_ = true;
      mouse_x_ = e.x;
      mouse_y_ = e.y;
      break;
    case EventType::MouseMoveBy:
      motion_x_ += e.x;
      motion_y_ += e.y;
      mouse_x_ += e.x;
      mouse_y_ += e.y;
      mouse_known_ = true;
      break;
    case EventType::MouseDown:
      if (e.code >= 0 && e.code < kButtons) buttons_[e.code] = buttons_pressed_[e.code] = true;
      break;
    case EventType::MouseUp:
      if (e.code >= 0 && e.code < kButtons) buttons_[e.code] = false;
      break;
    case EventType::Scroll: scroll_ += e.y; break;
    case EventType::Char: text_.push_back(e.codepoint); break;
    case EventType::Resize: resize_ = std::make_pair(int(e.x), int(e.y)); break;
    case EventType::Quit: quit_ = true; break;
  }
}

bool InputState::pressed(int key) const {
  return std::find(pressed_.begin(), pressed_.end(), key) != pressed_.end();
}

bool InputState::shift() const { return down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT); }
bool InputState::control() const {
  return down(GLFW_KEY_LEFT_CONTROL) || down(GLFW_KEY_RIGHT_CONTROL);
}
bool InputState::alt() const { return down(GLFW_KEY_LEFT_ALT) || down(GLFW_KEY_RIGHT_ALT); }
bool InputState::super() const { return down(GLFW_KEY_LEFT_SUPER) || down(GLFW_KEY_RIGHT_SUPER); }

}  // namespace logrid::viewer
