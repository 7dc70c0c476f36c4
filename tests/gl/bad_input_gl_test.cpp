// Bad input at the GL integration's boundary: impossible framebuffer sizes, unknown
// depth set-ups and context requests end in a logrid::Error that names the value and
// says what to do, and leave the current context untouched; the result forms return the
// same code and message. (Sizes are unsigned
// integers: a NaN or negative float reaches them only through the caller's own cast, so
// the cases here are 0, the unsigned image of -1, and sizes beyond every limit.)
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "expect_error.hpp"
#include "expect_status.hpp"
#include "gl_test_context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/gl/object_id_oracle.hpp"

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

// The result forms (logrid/error.hpp) of the GL integration return the error the
// throwing forms throw, with the same code and message, and leave no GL error behind.
TEST(BadInputGlTest, ResultFormsReturnWhatTheThrowingFormsThrow) {
  LOGRID_REQUIRE_GL();
  const DepthSetup depth;
  // Framebuffers.
  test::expectBothForms(
      [&] {
        return gl::Framebuffer::create({0, 16, depth, false});
      },
      [&] {
        gl::Framebuffer fb({0, 16, depth, false});
      },
      ErrorCode::InvalidArgument, {"framebuffer: size 0x16 is not possible", "at least 1x1"});
  DepthSetup unknown;
  unknown.convention = static_cast<DepthConvention>(5);
  test::expectBothForms(
      [&] {
        return gl::Framebuffer::create({16, 16, unknown, false});
      },
      [&] {
        gl::Framebuffer fb({16, 16, unknown, false});
      },
      ErrorCode::InvalidArgument, {"unknown depth set-up", "convention 5"});
  test::expectBothForms(
      [&] {
        return gl::Framebuffer::create({16, 16, depth, false, 1u << 20});
      },
      [&] {
        gl::Framebuffer fb({16, 16, depth, false, 1u << 20});
      },
      ErrorCode::Unsupported,
      {"framebuffer: 1048576 samples per pixel requested", "ask for fewer"});
  Result<std::unique_ptr<gl::Framebuffer>> plain = gl::Framebuffer::create({16, 16, depth, false});
  ASSERT_TRUE(plain.ok()) << plain.status().message();
  const gl::Framebuffer& fb = *plain.value();
  test::expectBothForms(
      [&] { return fb.tryReadObjectIds(); }, [&] { fb.readObjectIds(); },
      ErrorCode::InvalidArgument,
      {"Framebuffer::readObjectIds: the framebuffer has no object-ID attachment"});
  const Result<std::vector<float>> cleared = fb.tryReadDepth();
  ASSERT_TRUE(cleared.ok()) << cleared.status().message();
  EXPECT_EQ(cleared->size(), 16u * 16u);

  // Renderers: a draw outside the arrays, colours that do not match the vertices, and a
  // transform of an object that does not exist.
  gl::RenderMesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.indices32 = {0, 1, 2};
  mesh.draws = {{0, 3, 0}, {0, 6, 0}};
  test::expectBothForms([&] { return gl::MeshRenderer::create(mesh); },
                        [&] { gl::MeshRenderer renderer(mesh); }, ErrorCode::InvalidArgument,
                        {"MeshRenderer: draw 1 (indices 0+6, base vertex 0) lies outside the "
                         "mesh (3 indices, 3 vertices)"});
  mesh.draws.pop_back();
  mesh.colors = {0xFFFFFFFFu, 0xFF0000FFu};
  test::expectBothForms([&] { return gl::MeshRenderer::create(mesh); },
                        [&] { gl::MeshRenderer renderer(mesh); }, ErrorCode::InvalidArgument,
                        {"MeshRenderer: 2 colours for 3 vertices"});
  mesh.colors.clear();
  Result<std::unique_ptr<gl::MeshRenderer>> renderer = gl::MeshRenderer::create(mesh);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  gl::MeshRenderer& r = *renderer.value();
  test::expectBothForms([&] { return r.trySetTransform(1, {}); }, [&] { r.setTransform(1, {}); },
                        ErrorCode::InvalidArgument,
                        {"MeshRenderer::setTransform: object 1 does not exist (1 objects)"});
  EXPECT_TRUE(r.trySetTransform(0, {}).ok());
  EXPECT_TRUE(r.hasTransform(0));

  // The oracle: a framebuffer without IDs, and an invalid camera.
  Camera camera;
  camera.width = camera.height = 16;
  const std::vector<Aabb> boxes;
  test::expectBothForms([&] { return gl::tryObjectIdOracle(fb, camera, boxes, [] {}); },
                        [&] { gl::objectIdOracle(fb, camera, boxes, [] {}); },
                        ErrorCode::InvalidArgument,
                        {"objectIdOracle: the framebuffer has no object-ID attachment"});
  Result<std::unique_ptr<gl::Framebuffer>> ids = gl::Framebuffer::create({16, 16, depth, true});
  ASSERT_TRUE(ids.ok()) << ids.status().message();
  camera.view_projection.m[5] = std::numeric_limits<double>::quiet_NaN();
  test::expectBothForms([&] { return gl::tryObjectIdOracle(*ids.value(), camera, boxes, [] {}); },
                        [&] { gl::objectIdOracle(*ids.value(), camera, boxes, [] {}); },
                        ErrorCode::InvalidArgument,
                        {"camera: view_projection element 5 (row 1, column 1) is nan"});
  EXPECT_TRUE(gl::tryCheckGlErrors("ResultFormsReturnWhatTheThrowingFormsThrow").ok());
}

TEST(BadInputGlTest, ContextCreateReturnsWhatTheConstructorThrows) {
  LOGRID_REQUIRE_GL();
  const EGLContext before = eglGetCurrentContext();
  gl::ContextDesc desc;
  desc.device_index = 99;
  test::expectBothForms([&] { return gl::Context::create(desc); }, [&] { gl::Context c(desc); },
                        ErrorCode::InvalidArgument, {"EGL: device index 99 requested but"});
  desc.device_index = -5;
  test::expectBothForms([&] { return gl::Context::create(desc); }, [&] { gl::Context c(desc); },
                        ErrorCode::InvalidArgument,
                        {"EGL: device index -5 is invalid; use -1 (the first GPU) or an index "
                         "from 0"});
  EXPECT_EQ(eglGetCurrentContext(), before);
  EXPECT_TRUE(test::sharedContext()->tryMakeCurrent().ok());
  EXPECT_TRUE(test::sharedContext()->tryCheck("ContextCreateReturnsWhatTheConstructorThrows").ok());
}

}  // namespace
}  // namespace logrid
