// The headless context and framebuffers: a known triangle read back exactly in every
// depth format and convention, and clear errors for what cannot work.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cstring>

#include "gl_test_context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/zread/program.hpp"

namespace logrid {
namespace {

constexpr const char* kTriangleVs = R"(#version 450 core
uniform float u_z;
void main() {
  // Lower-left half of the viewport: (-1,-1), (1,-1), (-1,1).
  vec2 p = vec2(gl_VertexID == 1 ? 1.0 : -1.0, gl_VertexID == 2 ? 1.0 : -1.0);
  gl_Position = vec4(p, u_z, 1.0);
}
)";
constexpr const char* kTriangleFs = R"(#version 450 core
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0, 128.0 / 255.0, 0.0, 1.0); }
)";

struct Case {
  DepthFormat format;
  DepthConvention convention;
  ClipDepthRange range;
};

std::string caseName(const testing::TestParamInfo<Case>& info) {
  std::string s = std::string("d") + toString(info.param.format) + "_" +
                  toString(info.param.convention) + "_" + toString(info.param.range);
  for (char& c : s) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return s;
}

class TriangleTest : public testing::TestWithParam<Case> {};

// The triangle is drawn at a clip z whose window depth is exact in every format:
// window depth 0.25 is exact in float for both clip ranges (32F is asserted exactly);
// window depth 0.2 = 13107 / 65535 = 3355443 / 16777215 is exact in D16 and D24 when it
// reaches the rasteriser unchanged, i.e. with the zero-to-one range (z_ndc = 0.2f), and
// within one quantisation step with the -1..1 range (0.5 * -0.6f + 0.5 rounds in float).
TEST_P(TriangleTest, ColourAndDepthReadBackExactly) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  gl::FramebufferDesc desc;
  desc.width = 64;
  desc.height = 48;
  desc.depth = {c.convention, c.range, c.format};
  gl::Framebuffer fb(desc);
  fb.bind();
  const float black[4] = {0, 0, 0, 0};
  fb.clear(black);

  const bool float_depth = c.format == DepthFormat::D32F;
  const double window = float_depth ? 0.25 : 0.2;
  const float z_ndc = c.range == ClipDepthRange::ZeroToOne ? float(window) : float(2 * window - 1);
  zread::Program program("triangle", kTriangleVs, kTriangleFs);
  program.use();
  glUniform1f(program.uniform("u_z"), z_ndc);
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDeleteVertexArrays(1, &vao);
  gl::checkGlErrors("TriangleTest draw");

  const auto color = fb.readColor();
  const auto depth = fb.readDepth();
  const float clear = c.convention == DepthConvention::Reversed ? 0.0f : 1.0f;
  // Pixel (4, 4) is inside the triangle, (60, 44) outside.
  const std::size_t inside = 4 * 64 + 4, outside = 44 * 64 + 60;
  EXPECT_EQ(color[inside * 4 + 0], 255);
  EXPECT_EQ(color[inside * 4 + 1], 128);
  EXPECT_EQ(color[inside * 4 + 2], 0);
  EXPECT_EQ(color[inside * 4 + 3], 255);
  EXPECT_EQ(color[outside * 4 + 0], 0);
  EXPECT_EQ(depth[outside], clear);

  // Native reads: the stored value itself.
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fb.handle());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (float_depth) {
    EXPECT_EQ(depth[inside], 0.25f);
  } else if (c.format == DepthFormat::D16) {
    std::uint16_t v = 0;
    glReadPixels(4, 4, 1, 1, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, &v);
    if (c.range == ClipDepthRange::ZeroToOne) {
      EXPECT_EQ(v, 13107);
    } else {
      EXPECT_NEAR(v, 13107, 1);
    }
  } else {
    std::uint32_t v = 0;  // D24 read as unsigned int: scaled to 2^32 - 1
    glReadPixels(4, 4, 1, 1, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, &v);
    if (c.range == ClipDepthRange::ZeroToOne) {
      EXPECT_EQ(v, 858993459u);  // (2^32 - 1) / 5
    } else {
      EXPECT_NEAR(double(v), 858993459.0, 257.0 * 1.01);  // one D24 step
    }
  }
  gl::checkGlErrors("TriangleTest read");
}

INSTANTIATE_TEST_SUITE_P(
    AllFormatsAndConventions, TriangleTest,
    testing::Values(
        Case{DepthFormat::D16, DepthConvention::Standard, ClipDepthRange::NegativeOneToOne},
        Case{DepthFormat::D16, DepthConvention::Standard, ClipDepthRange::ZeroToOne},
        Case{DepthFormat::D16, DepthConvention::Reversed, ClipDepthRange::ZeroToOne},
        Case{DepthFormat::D24, DepthConvention::Standard, ClipDepthRange::NegativeOneToOne},
        Case{DepthFormat::D24, DepthConvention::Standard, ClipDepthRange::ZeroToOne},
        Case{DepthFormat::D24, DepthConvention::Reversed, ClipDepthRange::ZeroToOne},
        Case{DepthFormat::D32F, DepthConvention::Standard, ClipDepthRange::NegativeOneToOne},
        Case{DepthFormat::D32F, DepthConvention::Standard, ClipDepthRange::ZeroToOne},
        Case{DepthFormat::D32F, DepthConvention::Reversed, ClipDepthRange::ZeroToOne}),
    caseName);

TEST(ContextTest, ReportsA45CoreContext) {
  LOGRID_REQUIRE_GL();
  const gl::ContextInfo& info = test::sharedContext()->info();
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_GE(epoxy_gl_version(), 45);
  EXPECT_TRUE(info.debug);
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
}

TEST(ContextTest, ImpossibleFramebufferSizeIsAClearError) {
  LOGRID_REQUIRE_GL();
  gl::FramebufferDesc desc;
  desc.width = 1u << 20;  // beyond every driver's GL_MAX_TEXTURE_SIZE
  desc.height = 16;
  try {
    gl::Framebuffer fb(desc);
    FAIL() << "a 1048576-pixel-wide framebuffer was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("1048576x16"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("smaller size"), std::string::npos) << e.what();
  }
  desc.width = 0;
  EXPECT_THROW(gl::Framebuffer{desc}, Error);
  gl::checkGlErrors("after the failed framebuffers");  // nothing left behind
}

TEST(ContextTest, DeviceIndexOutOfRangeIsAClearError) {
  LOGRID_REQUIRE_GL();
  gl::ContextDesc desc;
  desc.platform = gl::Platform::Device;
  desc.device_index = 1000;
  try {
    gl::Context context(desc);
    FAIL() << "device index 1000 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("device index 1000"), std::string::npos) << e.what();
  }
  test::sharedContext()->makeCurrent();
}

TEST(ContextTest, ParsesPlatformNames) {
  EXPECT_EQ(gl::parsePlatform("surfaceless"), gl::Platform::Surfaceless);
  EXPECT_EQ(gl::parsePlatform("device"), gl::Platform::Device);
  EXPECT_EQ(gl::parsePlatform("auto"), gl::Platform::Auto);
  EXPECT_FALSE(gl::parsePlatform("x11").has_value());
}

}  // namespace
}  // namespace logrid
