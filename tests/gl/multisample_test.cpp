// MultisampleResolver (zread/multisample.hpp): on multisampled depth buffers of every
// format, as a texture or a renderbuffer, in both conventions, the resolved key of each
// pixel is exactly its farthest sample (read per sample with texelFetch by
// Framebuffer::readDepth), under any application state, which is restored; and a
// multisampled buffer is refused when the camera does not say it is multisampled.
#include "logrid/zread/multisample.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "gl_state_probe.hpp"
#include "gl_test_context.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/zread/gl_sources.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/program.hpp"
#include "logrid/zread/reduction_source.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kWidth = 61, kHeight = 37, kSamples = 4;

enum class Attachment { Texture, Renderbuffer, Texture24Stencil8, Renderbuffer24Stencil8 };

struct Case {
  DepthFormat format;
  Attachment attachment;
  DepthConvention convention;
};

std::string caseName(const testing::TestParamInfo<Case>& info) {
  const Case& c = info.param;
  std::string n = toString(c.format);
  n += c.attachment == Attachment::Texture             ? "_texture"
       : c.attachment == Attachment::Renderbuffer      ? "_renderbuffer"
       : c.attachment == Attachment::Texture24Stencil8 ? "_texture_d24s8"
                                                       : "_renderbuffer_d24s8";
  n += c.convention == DepthConvention::Standard ? "_standard" : "_reversed";
  return n;
}

// Random triangles with depth varying across them, so that pixels on their edges hold
// samples of different depths.
struct Triangles {
  zread::Program program{"multisample_test",
                         "#version 450 core\n"
                         "layout(location = 0) in vec4 a_position;\n"
                         "void main() { gl_Position = a_position; }\n",
                         "#version 450 core\n"
                         "out vec4 color;\n"
                         "void main() { color = vec4(1.0); }\n"};
  GLuint vao = 0, buffer = 0;
  GLsizei vertices = 0;
  explicit Triangles(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> xy(-1.2f, 1.2f), z(-0.9f, 0.9f);
    std::vector<float> data;
    for (int t = 0; t < 60; ++t) {
      for (int v = 0; v < 3; ++v) data.insert(data.end(), {xy(rng), xy(rng), z(rng), 1.0f});
    }
    vertices = GLsizei(data.size() / 4);
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(data.size() * 4), data.data(), 0);
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, buffer, 0, 16);
    glVertexArrayAttribFormat(vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    glEnableVertexArrayAttrib(vao, 0);
  }
  ~Triangles() {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &buffer);
  }
  // Clears `fbo`'s depth to the convention's far value and draws with the test keeping
  // the nearer fragment.
  void draw(GLuint fbo, DepthConvention convention) const {
    const bool reversed = convention == DepthConvention::Reversed;
    const float far_depth = reversed ? 0.0f : 1.0f;
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &far_depth);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glViewport(0, 0, kWidth, kHeight);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(reversed ? GL_GREATER : GL_LESS);
    program.use();
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, vertices);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  }
};

// A framebuffer whose only attachment is a multisampled depth texture or renderbuffer.
struct DepthOnlyFramebuffer {
  GLuint fbo = 0, texture = 0, renderbuffer = 0;
  DepthOnlyFramebuffer(Attachment kind, GLenum format) {
    glCreateFramebuffers(1, &fbo);
    if (kind == Attachment::Texture || kind == Attachment::Texture24Stencil8) {
      glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &texture);
      glTextureStorage2DMultisample(texture, kSamples, format, kWidth, kHeight, GL_TRUE);
      glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, texture, 0);
    } else {
      glCreateRenderbuffers(1, &renderbuffer);
      glNamedRenderbufferStorageMultisample(renderbuffer, kSamples, format, kWidth, kHeight);
      glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffer);
    }
    glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    glNamedFramebufferReadBuffer(fbo, GL_NONE);
  }
  ~DepthOnlyFramebuffer() {
    glDeleteFramebuffers(1, &fbo);
    if (texture) glDeleteTextures(1, &texture);
    if (renderbuffer) glDeleteRenderbuffers(1, &renderbuffer);
  }
};

GLenum internalFormat(const Case& c) {
  if (c.attachment == Attachment::Texture24Stencil8 ||
      c.attachment == Attachment::Renderbuffer24Stencil8) {
    return GL_DEPTH24_STENCIL8;
  }
  return gl::depthInternalFormat(c.format);
}

class MultisampleResolveTest : public testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    LOGRID_REQUIRE_GL();
    GLint max_samples = 0;
    glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &max_samples);
    if (max_samples < GLint(kSamples))
      GTEST_SKIP() << "GL_MAX_DEPTH_TEXTURE_SAMPLES " << max_samples;
  }
};

// Reads the resolved depth of `rect` through a guarded read, as a source does.
std::vector<float> readResolved(zread::GlStateGuard::Scope& scope, GLuint fbo, const PixelRect& r) {
  std::vector<float> out(std::size_t(r.area()));
  EXPECT_TRUE(scope.prepareRead(fbo, 0));
  glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, GL_FLOAT, out.data());
  EXPECT_TRUE(scope.check("glReadPixels"));
  return out;
}

TEST_P(MultisampleResolveTest, ResolvedKeyIsTheFarthestSampleOfEachPixel) {
  const Case c = GetParam();
  const bool reversed = c.convention == DepthConvention::Reversed;
  // The reference: the same triangles in a gl::Framebuffer of the same depth bits, read
  // per sample. Rasterisation is deterministic, so both buffers hold the same samples.
  gl::FramebufferDesc desc;
  desc.width = kWidth;
  desc.height = kHeight;
  desc.depth = {c.convention, ClipDepthRange::NegativeOneToOne, c.format};
  desc.samples = kSamples;
  gl::Framebuffer reference(desc);
  ASSERT_EQ(reference.samples(), kSamples);
  DepthOnlyFramebuffer tested(c.attachment, internalFormat(c));
  const Triangles triangles(11);
  triangles.draw(reference.handle(), c.convention);
  triangles.draw(tested.fbo, c.convention);
  const std::vector<float> samples = reference.readDepth();
  ASSERT_EQ(samples.size(), std::size_t(kWidth) * kHeight * kSamples);
  std::vector<float> farthest(std::size_t(kWidth) * kHeight);
  int mixed = 0;
  for (std::size_t p = 0; p < farthest.size(); ++p) {
    const auto first = samples.begin() + std::ptrdiff_t(p * kSamples);
    const auto [lo, hi] = std::minmax_element(first, first + kSamples);
    farthest[p] = reversed ? *lo : *hi;
    mixed += *lo != *hi;
  }
  // Pixels whose samples differ are where a resolve can go wrong: the scene has many.
  ASSERT_GT(mixed, 50);

  zread::GlStateGuard guard;
  zread::MultisampleResolver resolver;
  const zread::DepthAttachment attachment = zread::describeDepthAttachment("test", tested.fbo);
  EXPECT_EQ(attachment.samples, GLint(kSamples));
  EXPECT_EQ(attachment.width, GLint(kWidth));
  std::mt19937 rng(3);
  std::vector<PixelRect> rects = {{0, 0, std::int32_t(kWidth), std::int32_t(kHeight)}};
  for (int i = 0; i < 12; ++i) {
    const std::int32_t x0 = std::int32_t(rng() % kWidth), y0 = std::int32_t(rng() % kHeight);
    rects.push_back({x0, y0, x0 + 1 + std::int32_t(rng() % (kWidth - std::uint32_t(x0))),
                     y0 + 1 + std::int32_t(rng() % (kHeight - std::uint32_t(y0)))});
  }
  for (const PixelRect& r : rects) {
    zread::GlStateGuard::Scope scope(guard, "ResolvedKeyIsTheFarthestSample");
    const GLuint fbo = resolver.resolve(scope, attachment, c.convention, &r, 1).value();
    const std::vector<float> got = readResolved(scope, fbo, r);
    int wrong = 0;
    for (std::int32_t y = r.y0; y < r.y1; ++y) {
      for (std::int32_t x = r.x0; x < r.x1; ++x) {
        const float want = farthest[std::size_t(y) * kWidth + std::size_t(x)];
        const float have =
            got[std::size_t(y - r.y0) * std::size_t(r.x1 - r.x0) + std::size_t(x - r.x0)];
        if (have != want && ++wrong <= 5) {
          ADD_FAILURE() << "pixel (" << x << ", " << y << "): resolved " << have
                        << ", farthest sample " << want;
        }
      }
    }
    EXPECT_EQ(wrong, 0);
  }
  gl::checkGlErrors("ResolvedKeyIsTheFarthestSampleOfEachPixel");
}

// The resolve under random application state: the same answer, and the state restored.
TEST_P(MultisampleResolveTest, ResolvesUnderAnyStateAndRestoresIt) {
  const Case c = GetParam();
  DepthOnlyFramebuffer tested(c.attachment, internalFormat(c));
  DepthOnlyFramebuffer clean(c.attachment, internalFormat(c));
  const Triangles triangles(5);
  triangles.draw(tested.fbo, c.convention);
  triangles.draw(clean.fbo, c.convention);
  zread::GlStateGuard guard;
  zread::MultisampleResolver resolver;
  const PixelRect all{0, 0, std::int32_t(kWidth), std::int32_t(kHeight)};
  std::vector<float> want;
  {
    zread::GlStateGuard::Scope scope(guard, "clean");
    const zread::DepthAttachment a = zread::describeDepthAttachment("test", clean.fbo);
    want = readResolved(scope, resolver.resolve(scope, a, c.convention, &all, 1).value(), all);
  }
  test::AppObjects objects;
  std::mt19937 rng(17);
  for (int round = 0; round < 6; ++round) {
    const std::string what = test::setRandomGlState(rng, objects);
    SCOPED_TRACE(what);
    if (tested.texture) {  // texture parameters an application may have set
      const GLint swizzle[4] = {GL_ZERO, GL_ZERO, GL_ONE, GL_ONE};
      glTextureParameteriv(tested.texture, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
      if (internalFormat(c) == GL_DEPTH24_STENCIL8) {
        glTextureParameteri(tested.texture, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
      }
    }
    const std::vector<GLuint> textures =
        tested.texture ? std::vector<GLuint>{tested.texture} : std::vector<GLuint>{};
    const test::GlSnapshot before = test::snapshotGlState(textures);
    std::vector<float> got;
    {
      zread::GlStateGuard::Scope scope(guard, "hostile");
      const zread::DepthAttachment a = zread::describeDepthAttachment("test", tested.fbo);
      got = readResolved(scope, resolver.resolve(scope, a, c.convention, &all, 1).value(), all);
    }
    EXPECT_EQ(got, want);
    EXPECT_EQ(test::diffGlState(before, test::snapshotGlState(textures)), "");
  }
  gl::checkGlErrors("ResolvesUnderAnyStateAndRestoresIt");
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (DepthConvention v : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (DepthFormat f : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F}) {
      for (Attachment a : {Attachment::Texture, Attachment::Renderbuffer}) out.push_back({f, a, v});
    }
    out.push_back({DepthFormat::D24, Attachment::Texture24Stencil8, v});
    out.push_back({DepthFormat::D24, Attachment::Renderbuffer24Stencil8, v});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Formats, MultisampleResolveTest, testing::ValuesIn(cases()), caseName);

TEST(MultisampleCheck, RefusesAMultisampledBufferUnlessTheCameraSaysSo) {
  LOGRID_REQUIRE_GL();
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_DEPTH_TEXTURE_SAMPLES, &max_samples);
  if (max_samples < GLint(kSamples)) GTEST_SKIP() << "GL_MAX_DEPTH_TEXTURE_SAMPLES " << max_samples;
  DepthOnlyFramebuffer multi(Attachment::Renderbuffer, GL_DEPTH_COMPONENT32F);
  gl::Framebuffer single({kWidth, kHeight, {}, false});
  Camera camera;
  camera.width = kWidth;
  camera.height = kHeight;
  const zread::DepthAttachment a = zread::describeDepthAttachment("ReadPixelsSource", multi.fbo);
  try {
    zread::checkMultisample("ReadPixelsSource", a, camera);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ReadPixelsSource"), std::string::npos) << m;
    EXPECT_NE(m.find("4 depth samples"), std::string::npos) << m;
    EXPECT_NE(m.find("Camera::multisample"), std::string::npos) << m;
  }
  // Every source refuses it in beginFrame(), and accepts it with Camera::multisample.
  camera.depth.format = DepthFormat::D32F;
  zread::ReadPixelsSource readpixels(multi.fbo);
  zread::PboSource pbo(multi.fbo);
  zread::QuerySource query(multi.fbo);
  zread::ReductionSource reduce(multi.fbo);
  for (DepthSource* s : std::initializer_list<DepthSource*>{&readpixels, &pbo, &query, &reduce}) {
    camera.multisample = false;
    const Status refused = s->beginFrame(camera);
    EXPECT_FALSE(refused.ok()) << s->traits().name << " accepted a multisampled buffer";
    EXPECT_NE(refused.message().find("Camera::multisample"), std::string::npos)
        << refused.message();
    camera.multisample = true;
    EXPECT_TRUE(s->beginFrame(camera).ok()) << s->traits().name;
  }
  camera.multisample = true;
  EXPECT_NO_THROW(zread::checkMultisample("ReadPixelsSource", a, camera));
  camera.multisample = false;
  EXPECT_NO_THROW(zread::checkMultisample(
      "ReadPixelsSource", zread::describeDepthAttachment("test", single.handle()), camera));
  gl::checkGlErrors("RefusesAMultisampledBuffer");
}

}  // namespace
}  // namespace logrid
