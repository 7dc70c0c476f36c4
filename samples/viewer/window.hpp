// The viewer's window: GLFW with an OpenGL 4.5 core context (GLX on X11, also under
// Xvfb), whose events become InputEvents. logrid's framebuffers, renderer and depth
// sources run on this context as they do on the headless EGL one; frames are blitted
// into the window.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "viewer/input.hpp"

namespace logrid::viewer {

struct WindowDesc {
  std::uint32_t width = 640;  // window size in screen coordinates
  std::uint32_t height = 480;
  std::string title = "logrid view";
  bool debug = false;  // a debug context (GL errors caught by gl::checkGlErrors)
  bool vsync = true;   // swap with the display's refresh
};

class Window {
 public:
  // Opens the window and makes its context current. Throws logrid::Error:
  // Environment when there is no display to open it on (with what to do: run on a
  // desktop or under xvfb-run), Unsupported when no OpenGL 4.5 core context is available.
  explicit Window(const WindowDesc& desc);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Processes the window system's events; appends those of the user to `events`.
  void poll(std::vector<InputEvent>& events);
  bool closeRequested() const;

  // Size of the drawable in pixels, and of the window in screen coordinates (they
  // differ on high-DPI displays).
  std::pair<std::uint32_t, std::uint32_t> framebufferSize() const;
  std::pair<std::uint32_t, std::uint32_t> windowSize() const;
  void requestSize(int width, int height);
  // Hides and captures the cursor (mouse look) or gives it back.
  void captureCursor(bool capture);

  // The drawn back buffer, RGBA8, bottom-up rows (for screenshots, before swap()).
  std::vector<std::uint8_t> readBackBuffer() const;
  void swap();
  std::string glRenderer() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace logrid::viewer
