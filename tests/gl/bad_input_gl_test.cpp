// Bad input at the GL integration's boundary: impossible framebuffer sizes, unknown
// depth set-ups and context requests end in a logrid::Error that names the value and
// says what to do, and leave the current context untouched. (Sizes are unsigned
// integers: a NaN or negative float reaches them only through the caller's own cast, so
// the cases here are 0, the unsigned image of -1, and sizes beyond every limit.)
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "expect_error.hpp"
#include "gl_test_context.hpp"
#include "logrid/gl/framebuffer.hpp"

namespace logrid {
namespace {

using test::expectError;

std::string size(std::uint32_t w, std::uint32_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

TEST(BadInputGlTest, ImpossibleFramebufferSizesAreClearErrors) {
  LOGRID_REQUIRE_GL();
  GLint max_texture = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  const std::uint32_t beyond_driver = std::uint32_t(max_texture) + 1;
  const std::uint32_t minus_one = static_cast<std::uint32_t>(-1);
  const DepthSetup depth;
  for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{0, 0}, {0, 16}, {16, 0}}) {
    expectError(
        [&] {
          gl::Framebuffer fb({w, h, depth, false});
        },
        ErrorCode::InvalidArgument,
        {"framebuffer: size " + size(w, h) + " is not possible", "at least 1x1"});
  }
  for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{100000, 100000},
                      {minus_one, 16},
                      {16, minus_one},
                      {beyond_driver, 1},
                      {kMaxViewportSide + 1, 1}}) {
    expectError(
        [&] {
          gl::Framebuffer fb({w, h, depth, false});
        },
        ErrorCode::InvalidArgument,
        {"framebuffer: size " + size(w, h) + " is not possible", "Choose a smaller size"});
  }
  DepthSetup unknown;
  unknown.format = static_cast<DepthFormat>(7);
  expectError(
      [&] {
        gl::Framebuffer fb({16, 16, unknown, false});
      },
      ErrorCode::InvalidArgument, {"unknown depth set-up (format 7", "DepthFormat"});
  gl::checkGlErrors("ImpossibleFramebufferSizesAreClearErrors");
  // Nothing was left half-made: a valid framebuffer still works.
  gl::Framebuffer fb({16, 16, depth, false});
  EXPECT_NE(fb.handle(), 0u);
}

TEST(BadInputGlTest, ImpossibleContextRequestsAreClearErrorsAndKeepTheCurrentContext) {
  LOGRID_REQUIRE_GL();
  const EGLContext before = eglGetCurrentContext();
  gl::ContextDesc desc;
  desc.device_index = 99;
  expectError([&] { gl::Context c(desc); }, ErrorCode::InvalidArgument,
              {"device index 99 requested but", "use an index below that"});
  desc.device_index = -5;
  expectError([&] { gl::Context c(desc); }, ErrorCode::InvalidArgument,
              {"device index -5 is invalid", "use -1"});
  desc = {};
  desc.platform = static_cast<gl::Platform>(9);
  expectError([&] { gl::Context c(desc); }, ErrorCode::InvalidArgument,
              {"unknown platform 9", "use auto, surfaceless or device"});
  EXPECT_EQ(eglGetCurrentContext(), before);
}

}  // namespace
}  // namespace logrid
