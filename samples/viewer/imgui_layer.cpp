#include "viewer/imgui_layer.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>

#include "logrid/error.hpp"

namespace logrid::viewer {

ImGuiLayer::ImGuiLayer() {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the user's folder
  io.LogFilename = nullptr;
  io.BackendPlatformName = "logrid_viewer_input";
  // ImGui 1.86 reads keys from io.KeysDown[], indexed by our codes (GLFW's).
  io.KeyMap[ImGuiKey_Tab] = GLFW_KEY_TAB;
  io.KeyMap[ImGuiKey_LeftArrow] = GLFW_KEY_LEFT;
  io.KeyMap[ImGuiKey_RightArrow] = GLFW_KEY_RIGHT;
  io.KeyMap[ImGuiKey_UpArrow] = GLFW_KEY_UP;
  io.KeyMap[ImGuiKey_DownArrow] = GLFW_KEY_DOWN;
  io.KeyMap[ImGuiKey_PageUp] = GLFW_KEY_PAGE_UP;
  io.KeyMap[ImGuiKey_PageDown] = GLFW_KEY_PAGE_DOWN;
  io.KeyMap[ImGuiKey_Home] = GLFW_KEY_HOME;
  io.KeyMap[ImGuiKey_End] = GLFW_KEY_END;
  io.KeyMap[ImGuiKey_Insert] = GLFW_KEY_INSERT;
  io.KeyMap[ImGuiKey_Delete] = GLFW_KEY_DELETE;
  io.KeyMap[ImGuiKey_Backspace] = GLFW_KEY_BACKSPACE;
  io.KeyMap[ImGuiKey_Space] = GLFW_KEY_SPACE;
  io.KeyMap[ImGuiKey_Enter] = GLFW_KEY_ENTER;
  io.KeyMap[ImGuiKey_Escape] = GLFW_KEY_ESCAPE;
  io.KeyMap[ImGuiKey_KeyPadEnter] = GLFW_KEY_KP_ENTER;
  io.KeyMap[ImGuiKey_A] = GLFW_KEY_A;
  io.KeyMap[ImGuiKey_C] = GLFW_KEY_C;
  io.KeyMap[ImGuiKey_V] = GLFW_KEY_V;
  io.KeyMap[ImGuiKey_X] = GLFW_KEY_X;
  io.KeyMap[ImGuiKey_Y] = GLFW_KEY_Y;
  io.KeyMap[ImGuiKey_Z] = GLFW_KEY_Z;
  ImGui::StyleColorsDark();
  ImGui::GetStyle().Alpha = 0.92f;
  if (!ImGui_ImplOpenGL3_Init("#version 450 core")) {
    ImGui::DestroyContext();
    throw Error(ErrorCode::Runtime,
                "view: Dear ImGui's OpenGL 3 renderer could not start (it loads libGL.so.1: "
                "apt-get install libgl1)");
  }
}

ImGuiLayer::~ImGuiLayer() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui::DestroyContext();
}

void ImGuiLayer::newFrame(std::uint32_t window_w, std::uint32_t window_h, std::uint32_t pixels_w,
                          std::uint32_t pixels_h, const InputState& input, double seconds) {
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(float(window_w), float(window_h));
  if (window_w > 0 && window_h > 0) {
    io.DisplayFramebufferScale =
        ImVec2(float(pixels_w) / float(window_w), float(pixels_h) / float(window_h));
  }
  io.DeltaTime = float(std::max(seconds, 1e-4));
  io.MousePos = input.mouseKnown() ? ImVec2(float(input.mouseX()), float(input.mouseY()))
                                   : ImVec2(-FLT_MAX, -FLT_MAX);
  // A button pressed and released within one frame still counts as down for it.
  for (int b = 0; b < IM_ARRAYSIZE(io.MouseDown); ++b) {
    io.MouseDown[b] = input.buttonDown(b) || input.buttonPressed(b);
  }
  io.MouseWheel = float(input.scroll());
  for (int k = 0; k < IM_ARRAYSIZE(io.KeysDown); ++k) {
    io.KeysDown[k] = input.down(k) || input.pressed(k);
  }
  io.KeyShift = input.shift();
  io.KeyCtrl = input.control();
  io.KeyAlt = input.alt();
  io.KeySuper = input.super();
  for (std::uint32_t c : input.text()) io.AddInputCharacter(c);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui::NewFrame();
}

bool ImGuiLayer::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool ImGuiLayer::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

void ImGuiLayer::render() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace logrid::viewer
