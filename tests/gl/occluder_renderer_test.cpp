// OccluderRenderer (logrid/gl/occluder_renderer.hpp) under any GL state an application may
// leave: the DDO occluders land in the depth buffer with the values they get under GL's
// default state, no colour is written, and the application's state is restored exactly.
// Each hostile state is shown to break a plain draw of the same quads (as the renderer
// drew before it used zread::GlStateGuard), so that the test shows something.
#include "logrid/gl/occluder_renderer.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>
#include <vector>

#include "gl_state_probe.hpp"
#include "gl_test_context.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/zread/program.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kWidth = 40, kHeight = 24;
const float kBackground[4] = {0.25f, 0.5f, 0.75f, 1.0f};

DepthSetup standardSetup() {
  return {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D24};
}
DepthSetup reversedSetup() {
  return {DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D32F};
}

// The depth stored for normalized device depth `z` under `setup` (depth range [0, 1]).
float windowDepth(const DepthSetup& setup, double z) {
  return float(setup.clip_range == ClipDepthRange::ZeroToOne ? z : z * 0.5 + 0.5);
}

ddo::Occluder quad(double x0, double y0, double x1, double y1, double z, bool clockwise) {
  ddo::Occluder o;
  const double corners[4][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};  // counter-clockwise
  for (int c = 0; c < 4; ++c) {
    const int from = clockwise ? 3 - c : c;
    o.ndc[c][0] = corners[from][0];
    o.ndc[c][1] = corners[from][1];
    o.ndc[c][2] = z;
  }
  return o;
}

// Three quads: A over the left half, counter-clockwise; B in the upper right, clockwise
// on screen (face culling of either winding removes one of them), asymmetric in y (a
// flipped clip origin moves it); C overlapping A's right half, farther than A there (a
// wrong depth function lets C's depth win), drawn after A.
struct Scene {
  DepthSetup setup;
  Camera camera;
  std::vector<ddo::Occluder> occluders;
  double za, zb, zc;
  explicit Scene(const DepthSetup& s) : setup(s) {
    camera.width = kWidth;
    camera.height = kHeight;
    camera.depth = s;
    const bool reversed = s.convention == DepthConvention::Reversed;
    // Nearer is smaller (standard) or larger (reversed).
    za = reversed ? 0.7 : 0.1;
    zb = reversed ? 0.4 : -0.3;
    zc = reversed ? 0.5 : 0.5;
    occluders = {quad(-1.0, -1.0, 0.0, 1.0, za, false), quad(0.5, 0.0, 1.0, 0.75, zb, true),
                 quad(-0.5, -0.25, 0.25, 0.25, zc, false)};
  }
};

gl::FramebufferDesc framebufferDesc(const DepthSetup& setup) {
  gl::FramebufferDesc d;
  d.width = kWidth;
  d.height = kHeight;
  d.depth = setup;
  return d;
}

// The renderer as it was before the guard: the quads drawn with whatever state is set,
// into whatever framebuffer is bound, colour writes switched off and back.
struct PlainDraw {
  zread::Program program{"occluder_renderer_test",
                         "#version 450 core\n"
                         "layout(location = 0) in vec3 a_ndc;\n"
                         "void main() { gl_Position = vec4(a_ndc, 1.0); }\n",
                         "#version 450 core\nvoid main() {}\n"};
  GLuint vao = 0, buffer = 0;
  PlainDraw() {
    glCreateVertexArrays(1, &vao);
    glCreateBuffers(1, &buffer);
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
  }
  ~PlainDraw() {
    glDeleteBuffers(1, &buffer);
    glDeleteVertexArrays(1, &vao);
  }
  void draw(const std::vector<ddo::Occluder>& occluders) {
    std::vector<float> v;
    for (const ddo::Occluder& o : occluders) {
      for (int c : {0, 1, 2, 0, 2, 3}) {
        for (int k = 0; k < 3; ++k) v.push_back(float(o.ndc[c][k]));
      }
    }
    glNamedBufferData(buffer, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(vao, 0, buffer, 0, 3 * sizeof(float));
    GLboolean mask[4];
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    program.use();
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(v.size() / 3));
    glBindVertexArray(0);
    glColorMask(mask[0], mask[1], mask[2], mask[3]);
  }
};

// GL's defaults, then the framebuffer bound with its convention's state, cleared.
void freshFrame(const gl::Framebuffer& fb) {
  test::setDefaultGlState(int(kWidth), int(kHeight));
  fb.bind();
  fb.clear(kBackground);
}

std::size_t differingPixels(const std::vector<float>& a, const std::vector<float>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

std::vector<test::HostileState> hostileStates(const DepthSetup& setup, GLuint app_framebuffer,
                                              GLuint app_program, GLuint app_vertex_array) {
  const GLenum other_mode =
      setup.clip_range == ClipDepthRange::ZeroToOne ? GL_NEGATIVE_ONE_TO_ONE : GL_ZERO_TO_ONE;
  const GLenum mode =
      setup.clip_range == ClipDepthRange::ZeroToOne ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE;
  return {
      {"cull front faces, clockwise winding",
       [] { glEnable(GL_CULL_FACE), glCullFace(GL_FRONT), glFrontFace(GL_CW); }},
      {"cull back faces", [] { glEnable(GL_CULL_FACE), glCullFace(GL_BACK); }},
      {"polygon mode line", [] { glPolygonMode(GL_FRONT_AND_BACK, GL_LINE); }},
      {"polygon mode point", [] { glPolygonMode(GL_FRONT_AND_BACK, GL_POINT); }},
      {"depth writes off", [] { glDepthMask(GL_FALSE); }},
      {"depth test off", [] { glDisable(GL_DEPTH_TEST); }},
      {"depth function always", [] { glDepthFunc(GL_ALWAYS); }},
      {"depth function never", [] { glDepthFunc(GL_NEVER); }},
      // The plain draw masks colour itself; here the renderer's masks and their
      // restoration are what is checked.
      {"colour writes of the red channel only",
       [] { glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_FALSE); }, true},
      {"scissor box of one pixel", [] { glEnable(GL_SCISSOR_TEST), glScissor(0, 0, 1, 1); }},
      {"stencil test failing everything",
       [] { glEnable(GL_STENCIL_TEST), glStencilFunc(GL_NEVER, 0, 0xFF); },
       true},  // the framebuffer has no stencil buffer: the test passes
      {"rasterizer discard", [] { glEnable(GL_RASTERIZER_DISCARD); }},
      {"viewport of one pixel", [] { glViewportIndexedf(0, 0, 0, 1, 1); }},
      {"narrow depth range", [] { glDepthRangeIndexed(0, 0.0, 0.1); }},
      {"polygon offset", [] { glEnable(GL_POLYGON_OFFSET_FILL), glPolygonOffset(-4, -1e5f); }},
      {"upper-left clip origin", [mode] { glClipControl(GL_UPPER_LEFT, mode); }},
      {"the other clip depth mode", [other_mode] { glClipControl(GL_LOWER_LEFT, other_mode); }},
      {"the application's framebuffer, program and vertex array bound",
       [=] {
         glBindFramebuffer(GL_FRAMEBUFFER, app_framebuffer);
         glUseProgram(app_program);
         glBindVertexArray(app_vertex_array);
       }},
  };
}

class OccluderRendererState : public testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    LOGRID_REQUIRE_GL();
    glUseProgram(0);
    glBindVertexArray(0);
  }
  DepthSetup setup() const { return GetParam() ? reversedSetup() : standardSetup(); }
};

// Under the default state the occluders store their own depths: the test's reference.
TEST_P(OccluderRendererState, DefaultStateStoresTheQuadsDepths) {
  const Scene scene(setup());
  gl::Framebuffer fb(framebufferDesc(scene.setup));
  gl::OccluderRenderer renderer;
  freshFrame(fb);
  renderer.draw(scene.occluders, scene.camera, fb.handle());
  const std::vector<float> depth = fb.readDepth();
  const float clear = scene.setup.convention == DepthConvention::Reversed ? 0.0f : 1.0f;
  auto at = [&](std::uint32_t x, std::uint32_t y) { return depth[y * kWidth + x]; };
  // Pixel centres: (x + 0.5) / 40 * 2 - 1 and (y + 0.5) / 24 * 2 - 1.
  EXPECT_NEAR(at(2, 2), windowDepth(scene.setup, scene.za), 1e-5f);    // A alone
  EXPECT_NEAR(at(15, 12), windowDepth(scene.setup, scene.za), 1e-5f);  // A in front of C
  EXPECT_NEAR(at(22, 12), windowDepth(scene.setup, scene.zc), 1e-5f);  // C alone
  EXPECT_NEAR(at(35, 16), windowDepth(scene.setup, scene.zb), 1e-5f);  // B, upper right
  EXPECT_EQ(at(35, 6), clear);                                         // below B
  EXPECT_EQ(at(25, 22), clear);
  const std::vector<std::uint8_t> color = fb.readColor();
  for (std::size_t i = 0; i < color.size(); i += 4) {
    ASSERT_EQ(color[i], std::uint8_t(kBackground[0] * 255 + 0.5f)) << "colour written at " << i / 4;
  }
  gl::checkGlErrors("DefaultStateStoresTheQuadsDepths");
}

TEST_P(OccluderRendererState, EachHostileStateBreaksAPlainDrawAndNotTheRenderer) {
  const Scene scene(setup());
  gl::Framebuffer fb(framebufferDesc(scene.setup));
  gl::OccluderRenderer renderer;
  PlainDraw plain;
  test::AppObjects objects;
  freshFrame(fb);
  const std::vector<std::uint8_t> background = fb.readColor();
  renderer.draw(scene.occluders, scene.camera, fb.handle());
  const std::vector<float> reference = fb.readDepth();
  // The plain draw under the default state agrees with the renderer.
  freshFrame(fb);
  plain.draw(scene.occluders);
  ASSERT_EQ(differingPixels(fb.readDepth(), reference), 0u);

  for (const test::HostileState& h :
       hostileStates(scene.setup, objects.framebuffer, objects.program, objects.vertex_array)) {
    SCOPED_TRACE(h.name);
    freshFrame(fb);
    h.set();
    plain.draw(scene.occluders);
    test::setDefaultGlState(int(kWidth), int(kHeight));
    fb.bind();
    const bool broken =
        differingPixels(fb.readDepth(), reference) > 0 || fb.readColor() != background;
    EXPECT_TRUE(h.undefined || broken)
        << "a plain draw stored the right depths under this state: the test shows nothing";

    freshFrame(fb);
    h.set();
    const test::GlSnapshot before = test::snapshotGlState({}, {fb.handle()});
    renderer.draw(scene.occluders, scene.camera, fb.handle());
    EXPECT_EQ(test::diffGlState(before, test::snapshotGlState({}, {fb.handle()})), "");
    test::setDefaultGlState(int(kWidth), int(kHeight));
    fb.bind();
    EXPECT_EQ(differingPixels(fb.readDepth(), reference), 0u);
    EXPECT_TRUE(fb.readColor() == background) << "the renderer wrote colour";
  }
  test::setDefaultGlState(int(kWidth), int(kHeight));
  gl::checkGlErrors("EachHostileState");
}

// Random application state of every kind the probe knows: the same depths, no colour, the
// state restored item by item.
TEST_P(OccluderRendererState, RandomStateGivesTheSameDepthsAndIsRestored) {
  const Scene scene(setup());
  gl::Framebuffer fb(framebufferDesc(scene.setup));
  gl::OccluderRenderer renderer;
  test::AppObjects objects;
  freshFrame(fb);
  const std::vector<std::uint8_t> background = fb.readColor();
  renderer.draw(scene.occluders, scene.camera, fb.handle());
  const std::vector<float> reference = fb.readDepth();
  std::mt19937 rng(GetParam() ? 1402u : 1401u);
  for (int round = 0; round < 30; ++round) {
    freshFrame(fb);
    const std::string what = test::setRandomGlState(rng, objects, test::kAllGlState, fb.handle(),
                                                    int(kWidth), int(kHeight));
    SCOPED_TRACE("round " + std::to_string(round) + ": " + what);
    const test::GlSnapshot before = test::snapshotGlState({}, {fb.handle()});
    renderer.draw(scene.occluders, scene.camera, fb.handle());
    EXPECT_EQ(test::diffGlState(before, test::snapshotGlState({}, {fb.handle()})), "");
    test::setDefaultGlState(int(kWidth), int(kHeight));
    fb.bind();
    EXPECT_EQ(differingPixels(fb.readDepth(), reference), 0u);
    EXPECT_TRUE(fb.readColor() == background) << "the renderer wrote colour";
  }
  test::setDefaultGlState(int(kWidth), int(kHeight));
  gl::checkGlErrors("RandomState");
}

INSTANTIATE_TEST_SUITE_P(Conventions, OccluderRendererState, testing::Bool(),
                         [](const testing::TestParamInfo<bool>& p) {
                           return p.param ? "reversed_d32f" : "standard_d24";
                         });

}  // namespace
}  // namespace logrid
