// On a rendered frame, every GL depth source (glReadPixels, PBO ring, compute-shader
// reduction with both kernels, occlusion queries) gives the same answers as a software
// source holding the same depth values, in every depth format and convention, whether
// asked one request at a time or in batches; and so they do under any GL state the
// application left (culling, winding, polygon mode, stencil, depth range, pack state,
// random state of every kind), which each of them leaves as it found it.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <random>

#include "gl_state_probe.hpp"
#include "gl_test_context.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/projection.hpp"
#include "logrid/zread/gl_sources.hpp"
#include "logrid/zread/reduction_source.hpp"

namespace logrid {
namespace {

struct Case {
  DepthFormat format;
  DepthConvention convention;
};

class SourcesTest : public testing::TestWithParam<Case> {};

Camera testCamera(const Case& c, std::uint32_t w, std::uint32_t h) {
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = {c.convention,
               c.convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                         : ClipDepthRange::NegativeOneToOne,
               c.format};
  cam.view_projection = multiply(perspective(1.0, double(w) / h, 0.5, 100, cam.depth),
                                 lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}));
  return cam;
}

// Random boxes in front of the camera, drawn with the mesh renderer.
gl::RenderMesh randomBoxes(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> p(-6, 6), s(0.3f, 3.0f);
  gl::RenderMesh mesh;
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  for (int i = 0; i < 40; ++i) {
    const Vec3 lo{p(rng), p(rng), p(rng) - 5};
    const std::size_t first = indices.size(), base = positions.size() / 3;
    cpu::appendBox({lo, {lo.x + s(rng), lo.y + s(rng), lo.z + s(rng)}}, positions, indices);
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(first);
    d.index_count = std::uint32_t(indices.size() - first);
    d.color = 0xFF808080u;
    for (std::size_t k = first; k < indices.size(); ++k) indices[k] -= std::uint32_t(base);
    d.base_vertex = std::int32_t(base);
    mesh.draws.push_back(d);
  }
  mesh.positions = positions;
  mesh.indices32 = indices;
  return mesh;
}

TEST_P(SourcesTest, EverySourceAgreesWithTheSoftwareSource) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  const std::uint32_t w = 97, h = 61;
  const Camera cam = testCamera(c, w, h);
  gl::Framebuffer fb({w, h, cam.depth, false});
  fb.bind();
  const float clear[4] = {0, 0, 0, 1};
  fb.clear(clear);
  gl::MeshRenderer renderer(randomBoxes(3));
  renderer.begin(gl::Pass::DepthOnly, cam);
  for (ObjectId id = 0; id < renderer.objectCount(); ++id) renderer.draw(id);
  renderer.end();

  // The software reference holds exactly what GL stored (read back as float).
  cpu::SoftwareDepthBuffer reference(w, h, c.convention);
  const std::vector<float> depth = fb.readDepth();
  std::copy(depth.begin(), depth.end(), reference.data());
  zread::ReadPixelsSource readpixels(fb.handle());
  zread::PboSource pbo(fb.handle());
  zread::QuerySource query(fb.handle());
  zread::ReductionSource reduce_serial(fb.handle(), zread::ReductionSource::Kernel::PerRequest);
  zread::ReductionSource reduce_groups(fb.handle(), zread::ReductionSource::Kernel::PerWorkgroup);
  for (DepthSource* s : std::initializer_list<DepthSource*>{&reference, &readpixels, &pbo, &query,
                                                            &reduce_serial, &reduce_groups}) {
    orThrow(s->beginFrame(cam));
  }

  std::mt19937 rng(5);
  const double step = quantisationStep(c.format);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    const std::int32_t x0 = std::int32_t(rng() % w), y0 = std::int32_t(rng() % h);
    const PixelRect r{x0, y0, x0 + 1 + std::int32_t(rng() % (w - std::uint32_t(x0))),
                      y0 + 1 + std::int32_t(rng() % (h - std::uint32_t(y0)))};
    AreaDepth want, got_rp, got_pbo, got_rs, got_rg;
    reference.summarize(&r, 1, &want);
    readpixels.summarize(&r, 1, &got_rp);
    pbo.summarize(&r, 1, &got_pbo);
    reduce_serial.summarize(&r, 1, &got_rs);
    reduce_groups.summarize(&r, 1, &got_rg);
    for (const AreaDepth* got : {&got_rp, &got_pbo, &got_rs, &got_rg}) {
      EXPECT_EQ(got->free_pixels, want.free_pixels);
      EXPECT_LE(got->min_key, want.min_key + 1e-7f);  // rounded outwards
      EXPECT_GE(got->max_key, want.max_key - 1e-7f);
      EXPECT_NEAR(got->min_key, want.min_key, 2e-7);
      EXPECT_NEAR(got->max_key, want.max_key, 2e-7);
    }
    // Thresholds between stored values: every source counts exactly the same pixels.
    // Exactly at a stored value: none may count fewer (that would be non-conservative).
    const float at = want.min_key + (want.max_key - want.min_key) * float(rng() % 100) / 100.0f;
    const float margin = float(std::max(step, 1e-6) * 0.5);
    for (float t : {at - margin, at + margin, want.max_key, want.min_key}) {
      std::uint32_t n_ref = 0, n_rp = 0, n_pbo = 0, n_q = 0, n_rs = 0, n_rg = 0, n_step_below = 0;
      reference.countAtOrBeyond(&r, 1, t, &n_ref);
      readpixels.countAtOrBeyond(&r, 1, t, &n_rp);
      pbo.countAtOrBeyond(&r, 1, t, &n_pbo);
      query.countAtOrBeyond(&r, 1, t, &n_q);
      reduce_serial.countAtOrBeyond(&r, 1, t, &n_rs);
      reduce_groups.countAtOrBeyond(&r, 1, t, &n_rg);
      reference.countAtOrBeyond(&r, 1, float(t - step - 2e-7), &n_step_below);
      // Never fewer than the pixels at or beyond t: fewer would be non-conservative.
      EXPECT_GE(n_rp, n_ref);
      EXPECT_GE(n_pbo, n_ref);
      EXPECT_GE(n_rs, n_ref);
      EXPECT_EQ(n_rg, n_rs);
      EXPECT_LE(n_rs, n_step_below);
      EXPECT_GE(n_q, n_ref) << "rect " << r.x0 << "," << r.y0 << " t " << t;
      if (t == want.max_key) {
        EXPECT_GT(n_q, 0u);  // the farthest pixel is at the threshold
      }
      if (t != want.max_key && t != want.min_key) {
        // Between stored values the readers count exactly.
        EXPECT_EQ(n_rp, n_ref) << "rect " << r.x0 << "," << r.y0 << " t " << t;
        EXPECT_EQ(n_pbo, n_ref);
        EXPECT_EQ(n_rs, n_ref);
      }
      // A query compares in the buffer's quantised domain: it may also count pixels up
      // to one quantisation step below the threshold (none for 32F), never more.
      EXPECT_LE(n_q, n_step_below) << "rect " << r.x0 << "," << r.y0 << " t " << t;
      if (c.format == DepthFormat::D32F && t != want.max_key && t != want.min_key) {
        EXPECT_EQ(n_q, n_ref);
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 1200);
  EXPECT_GT(query.counters().queries, 0u);
  EXPECT_GT(readpixels.counters().pixels, 0u);
  gl::checkGlErrors("SourcesTest");
}

TEST_P(SourcesTest, QuerySourceRestoresTheStateItChanges) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  const Camera cam = testCamera(c, 32, 32);
  gl::Framebuffer fb({32, 32, cam.depth, false});
  fb.bind();
  zread::QuerySource query(fb.handle());
  orThrow(query.beginFrame(cam));
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_TRUE);
  glEnable(GL_SCISSOR_TEST);
  glScissor(1, 2, 3, 4);
  const PixelRect q{0, 0, 8, 8};
  std::uint32_t n = 0;
  query.countAtOrBeyond(&q, 1, 0.5f, &n);
  GLint func = 0, box[4];
  GLboolean mask = GL_FALSE, colors[4];
  glGetIntegerv(GL_DEPTH_FUNC, &func);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
  glGetBooleanv(GL_COLOR_WRITEMASK, colors);
  glGetIntegerv(GL_SCISSOR_BOX, box);
  EXPECT_EQ(func, GL_LEQUAL);
  gl::checkGlErrors("QuerySourceRestoresTheStateItChanges");
  EXPECT_EQ(mask, GL_TRUE);
  EXPECT_EQ(colors[0], GL_TRUE);
  EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));
  EXPECT_EQ(box[2], 3);
  glDisable(GL_SCISSOR_TEST);
}

// A framebuffer with a stencil buffer where the format has one (D24S8, D32F_S8), so that
// a stencil test can fail, and the random boxes drawn into it.
struct StencilFramebuffer {
  GLuint fbo = 0, color = 0, depth = 0;
  StencilFramebuffer(const Camera& cam, const gl::RenderMesh& mesh) {
    const GLenum format = cam.depth.format == DepthFormat::D24    ? GL_DEPTH24_STENCIL8
                          : cam.depth.format == DepthFormat::D32F ? GL_DEPTH32F_STENCIL8
                                                                  : GL_DEPTH_COMPONENT16;
    const GLsizei w = GLsizei(cam.width), h = GLsizei(cam.height);
    glCreateFramebuffers(1, &fbo);
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA8, w, h);
    glCreateTextures(GL_TEXTURE_2D, 1, &depth);
    glTextureStorage2D(depth, 1, format, w, h);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, color, 0);
    glNamedFramebufferTexture(
        fbo, format == GL_DEPTH_COMPONENT16 ? GL_DEPTH_ATTACHMENT : GL_DEPTH_STENCIL_ATTACHMENT,
        depth, 0);
    const float far_depth = cam.depth.convention == DepthConvention::Reversed ? 0.0f : 1.0f;
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, far_depth, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    gl::applyDepthState(cam.depth);
    gl::MeshRenderer renderer(mesh);
    renderer.begin(gl::Pass::DepthOnly, cam);
    for (ObjectId id = 0; id < renderer.objectCount(); ++id) renderer.draw(id);
    renderer.end();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  ~StencilFramebuffer() {
    glDeleteFramebuffers(1, &fbo);
    GLuint t[2] = {color, depth};
    glDeleteTextures(2, t);
  }
  std::vector<float> readDepth(const Camera& cam) const {
    std::vector<float> out(std::size_t(cam.width) * cam.height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureSubImage(depth, 0, 0, 0, 0, GLsizei(cam.width), GLsizei(cam.height), 1,
                         GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(out.size() * 4), out.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    return out;
  }
};

// Every source under each hostile state of tests/support/gl_state_probe.hpp, then under
// random state of every kind: the same counts and summaries as the software reference,
// and every item of the state as the application set it. Before GlStateGuard the query
// source counted 0 under most of them (culling, winding, polygon mode, stencil, discard),
// and the readers wrote out of bounds under the application's pack row length and skips.
TEST_P(SourcesTest, EverySourceAnswersTheSameUnderAnyApplicationState) {
  LOGRID_REQUIRE_GL();
  const Case c = GetParam();
  const std::uint32_t w = 53, h = 37;
  const Camera cam = testCamera(c, w, h);
  const StencilFramebuffer fb(cam, randomBoxes(8));
  cpu::SoftwareDepthBuffer reference(w, h, c.convention);
  const std::vector<float> depth = fb.readDepth(cam);
  std::copy(depth.begin(), depth.end(), reference.data());
  orThrow(reference.beginFrame(cam));
  zread::ReadPixelsSource readpixels(fb.fbo);
  zread::PboSource pbo(fb.fbo);
  zread::QuerySource query(fb.fbo);
  zread::ReductionSource reduce(fb.fbo);
  const std::pair<const char*, DepthSource*> sources[] = {
      {"readpixels", &readpixels}, {"pbo", &pbo}, {"query", &query}, {"reduce", &reduce}};
  const double step = quantisationStep(c.format);
  std::vector<test::HostileState> states = test::hostileGlStates();
  test::AppObjects objects;
  std::mt19937 state_rng(41);
  for (int round = 0; round < 8; ++round) {
    // Random state of every kind; the seed is drawn now so that each source sees it.
    const std::uint32_t seed = std::uint32_t(state_rng());
    states.push_back({"random state", [&objects, seed, &fb] {
                        std::mt19937 r(seed);
                        test::setRandomGlState(r, objects, test::kAllGlState, fb.fbo, 53, 37);
                      }});
  }
  std::mt19937 rng(9);
  for (const test::HostileState& state : states) {
    for (const auto& [name, source] : sources) {
      SCOPED_TRACE(std::string(name) + " under " + state.name);
      test::setDefaultGlState(int(w), int(h));
      state.set();
      const test::GlSnapshot before = test::snapshotGlState({fb.depth}, {fb.fbo});
      try {
        orThrow(source->beginFrame(cam));
        for (int i = 0; i < 12; ++i) {
          const std::int32_t x0 = std::int32_t(rng() % w), y0 = std::int32_t(rng() % h);
          const PixelRect r{x0, y0, x0 + 1 + std::int32_t(rng() % (w - std::uint32_t(x0))),
                            y0 + 1 + std::int32_t(rng() % (h - std::uint32_t(y0)))};
          AreaDepth want;
          reference.summarize(&r, 1, &want);
          if (source->traits().reads_depth) {
            AreaDepth got;
            source->summarize(&r, 1, &got);
            EXPECT_EQ(got.free_pixels, want.free_pixels);
            EXPECT_NEAR(got.min_key, want.min_key, 2e-7);
            EXPECT_NEAR(got.max_key, want.max_key, 2e-7);
          }
          for (float t : {want.min_key, want.max_key}) {
            std::uint32_t n = 0, n_ref = 0, n_step_below = 0;
            source->countAtOrBeyond(&r, 1, t, &n);
            reference.countAtOrBeyond(&r, 1, t, &n_ref);
            reference.countAtOrBeyond(&r, 1, float(t - step - 2e-7), &n_step_below);
            EXPECT_GE(n, n_ref) << "rect " << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1
                                << " threshold " << t;
            EXPECT_LE(n, n_step_below);
          }
        }
      } catch (const Error& e) {
        ADD_FAILURE() << e.what();
      }
      EXPECT_EQ(test::diffGlState(before, test::snapshotGlState({fb.depth}, {fb.fbo})), "");
    }
  }
  test::setDefaultGlState(int(w), int(h));
  gl::checkGlErrors("EverySourceAnswersTheSameUnderAnyApplicationState");
}

TEST(SourcesErrorTest, AMismatchedDepthFormatIsAClearError) {
  LOGRID_REQUIRE_GL();
  Camera cam = testCamera({DepthFormat::D24, DepthConvention::Standard}, 16, 16);
  gl::Framebuffer fb({16, 16, cam.depth, false});
  cam.depth.format = DepthFormat::D32F;  // the camera claims another format
  zread::ReadPixelsSource source(fb.handle());
  const Status begun = source.beginFrame(cam);
  EXPECT_EQ(begun.code(), ErrorCode::InvalidArgument);
  EXPECT_NE(begun.message().find("24-bit unorm"), std::string::npos) << begun.message();
  // A request a source cannot answer is answered "visible" and reported.
  zread::QuerySource query(fb.handle());
  const PixelRect one{0, 0, 1, 1};
  AreaDepth summary;
  query.summarize(&one, 1, &summary);
  const Status refused = query.takeError();
  EXPECT_EQ(refused.code(), ErrorCode::Unsupported);
  EXPECT_NE(refused.message().find("cannot read depth values"), std::string::npos)
      << refused.message();
  EXPECT_EQ(summary.free_pixels, 1u) << "answered as if nothing were drawn";
  EXPECT_GT(summary.max_key, 1.0f);
}

std::string caseName(const testing::TestParamInfo<Case>& param) {
  return std::string("d") + toString(param.param.format) + "_" + toString(param.param.convention);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, SourcesTest,
                         testing::Values(Case{DepthFormat::D16, DepthConvention::Standard},
                                         Case{DepthFormat::D16, DepthConvention::Reversed},
                                         Case{DepthFormat::D24, DepthConvention::Standard},
                                         Case{DepthFormat::D24, DepthConvention::Reversed},
                                         Case{DepthFormat::D32F, DepthConvention::Standard},
                                         Case{DepthFormat::D32F, DepthConvention::Reversed}),
                         caseName);

}  // namespace
}  // namespace logrid
