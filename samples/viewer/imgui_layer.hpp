// Dear ImGui on the viewer's window: Debian's libimgui-dev renders it (its OpenGL 3
// backend, built into libimgui.a); the input comes from InputState, not from GLFW
// callbacks, so that a script drives the panel exactly as a person does.
#pragma once

#include <cstdint>

#include "viewer/input.hpp"

namespace logrid::viewer {

class ImGuiLayer {
 public:
  // Needs the window's context current. Throws logrid::Error(Runtime) when the
  // renderer cannot be set up.
  ImGuiLayer();
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // Starts a UI frame: window size (screen coordinates), drawable size (pixels), the
  // frame's input and its duration in seconds.
  void newFrame(std::uint32_t window_w, std::uint32_t window_h, std::uint32_t pixels_w,
                std::uint32_t pixels_h, const InputState& input, double seconds);
  // Whether the panel uses the mouse or keyboard this frame (then the camera does not).
  bool wantsMouse() const;
  bool wantsKeyboard() const;
  // Draws the UI into the current framebuffer (the window's).
  void render();
};

}  // namespace logrid::viewer
