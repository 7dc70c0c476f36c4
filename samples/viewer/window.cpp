#include "viewer/window.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <unistd.h>
#include <cstdlib>
#include <string>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"

namespace logrid::viewer {
namespace {

// GLFW reports errors through a callback; the last one explains a failed call.
std::string g_last_error;

void errorCallback(int code, const char* description) {
  g_last_error = std::string(description ? description : "unknown error") + " (GLFW error 0x";
  static const char* hex = "0123456789abcdef";
  std::string digits;
  for (unsigned v = unsigned(code); v; v >>= 4) digits.insert(digits.begin(), hex[v & 15]);
  g_last_error += (digits.empty() ? "0" : digits) + ")";
}

bool onPath(const char* program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string dirs = path;
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string file = dirs.substr(start, end - start) + "/" + program;
    if (end > start && access(file.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

std::string noDisplayAdvice() {
  if (onPath("xvfb-run") && onPath("xauth")) {
    return "Run it on a desktop, or under a virtual display: xvfb-run -a logrid view ... "
           "(`logrid walk` renders without any display).";
  }
  // xvfb-run needs xauth, which Debian's xvfb only recommends.
  return "Run it on a desktop, or under a virtual display (Debian: apt-get install xvfb "
         "xauth, then xvfb-run -a logrid view ...); `logrid walk` renders without any "
         "display.";
}

}  // namespace

struct Window::Impl {
  GLFWwindow* window = nullptr;
  std::vector<InputEvent>* sink = nullptr;  // set during poll()

  static Impl& of(GLFWwindow* w) { return *static_cast<Impl*>(glfwGetWindowUserPointer(w)); }
  void push(const InputEvent& e) {
    if (sink) sink->push_back(e);
  }
};

Window::Window(const WindowDesc& desc) : impl_(std::make_unique<Impl>()) {
  glfwSetErrorCallback(errorCallback);
  g_last_error.clear();
  if (!glfwInit()) {
    throw Error(ErrorCode::Environment,
                "view: cannot open a window: " +
                    (g_last_error.empty() ? std::string("no display") : g_last_error) + ". " +
                    noDisplayAdvice());
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, desc.debug ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_DEPTH_BITS, 0);  // frames are drawn off-screen and blitted
  glfwWindowHint(GLFW_STENCIL_BITS, 0);
  g_last_error.clear();
  impl_->window =
      glfwCreateWindow(int(desc.width), int(desc.height), desc.title.c_str(), nullptr, nullptr);
  if (!impl_->window) {
    const std::string why = g_last_error;
    glfwTerminate();
    throw Error(ErrorCode::Unsupported,
                "view: cannot create a window with an OpenGL 4.5 core context: " + why +
                    ". logrid needs OpenGL 4.5 (Mesa >= 20 works without a GPU: apt-get install "
                    "libgl1-mesa-dri libglx-mesa0); under Xvfb the GLX extension must be on.");
  }
  glfwSetWindowUserPointer(impl_->window, impl_.get());
  glfwMakeContextCurrent(impl_->window);
  glfwSwapInterval(desc.vsync ? 1 : 0);
  if (epoxy_gl_version() < 45) {
    const std::string version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    glfwDestroyWindow(impl_->window);
    glfwTerminate();
    throw Error(ErrorCode::Unsupported, "view: the window's context reports OpenGL " + version +
                                            "; logrid needs OpenGL 4.5 core");
  }
  gl::installDebugOutput();

  GLFWwindow* w = impl_->window;
  glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int) {
    if (action == GLFW_REPEAT || key == GLFW_KEY_UNKNOWN) return;
    InputEvent e;
    e.type = action == GLFW_PRESS ? EventType::KeyDown : EventType::KeyUp;
    e.code = key;
    Impl::of(win).push(e);
  });
  glfwSetCharCallback(w, [](GLFWwindow* win, unsigned int codepoint) {
    InputEvent e;
    e.type = EventType::Char;
    e.codepoint = codepoint;
    Impl::of(win).push(e);
  });
  glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
    InputEvent e;
    e.type = EventType::MouseMove;
    e.x = x;
    e.y = y;
    Impl::of(win).push(e);
  });
  glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int button, int action, int) {
    InputEvent e;
    e.type = action == GLFW_PRESS ? EventType::MouseDown : EventType::MouseUp;
    e.code = button;
    Impl::of(win).push(e);
  });
  glfwSetScrollCallback(w, [](GLFWwindow* win, double, double y) {
    InputEvent e;
    e.type = EventType::Scroll;
    e.y = y;
    Impl::of(win).push(e);
  });
  glfwSetWindowCloseCallback(w, [](GLFWwindow* win) {
    InputEvent e;
    e.type = EventType::Quit;
    Impl::of(win).push(e);
  });
}

Window::~Window() {
  if (impl_->window) glfwDestroyWindow(impl_->window);
  glfwTerminate();
}

void Window::poll(std::vector<InputEvent>& events) {
  impl_->sink = &events;
  glfwPollEvents();
  impl_->sink = nullptr;
}

bool Window::closeRequested() const { return glfwWindowShouldClose(impl_->window) != 0; }

std::pair<std::uint32_t, std::uint32_t> Window::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(impl_->window, &w, &h);
  return {std::uint32_t(std::max(w, 0)), std::uint32_t(std::max(h, 0))};
}

std::pair<std::uint32_t, std::uint32_t> Window::windowSize() const {
  int w = 0, h = 0;
  glfwGetWindowSize(impl_->window, &w, &h);
  return {std::uint32_t(std::max(w, 0)), std::uint32_t(std::max(h, 0))};
}

void Window::requestSize(int width, int height) { glfwSetWindowSize(impl_->window, width, height); }

void Window::captureCursor(bool capture) {
  glfwSetInputMode(impl_->window, GLFW_CURSOR, capture ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
}

std::vector<std::uint8_t> Window::readBackBuffer() const {
  const auto [w, h] = framebufferSize();
  std::vector<std::uint8_t> out(std::size_t(w) * h * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, GLsizei(w), GLsizei(h), GL_RGBA, GL_UNSIGNED_BYTE, out.data());
  return out;
}

void Window::swap() { glfwSwapBuffers(impl_->window); }

std::string Window::glRenderer() const {
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(r ? r : "?") + " (" + (v ? v : "?") + ")";
}

}  // namespace logrid::viewer
