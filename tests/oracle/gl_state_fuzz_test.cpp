// The GL-state fuzz test (label oracle): before each culled frame the "application"
// leaves random GL state on the context, and the object-ID oracle must still find every
// visible object drawn, with the application's state unchanged by logrid.
//
// Per frame, from seeds fixed by the case and the frame (tests/support/gl_state_probe.hpp):
//  * draw-shaping state (culling, winding, stencil, sample mask and coverage, alpha to
//    coverage, multisampling, rasterizer discard, scissor) is set after the clear and
//    stays for the whole frame: the application draws its frame with it, and the ID pass
//    runs under the same state, so "visible" means what the application would see;
//  * state the culling contract rules out for the application's own draws (depth test,
//    function and mask, clamp and range, polygon mode and offset, clip distances,
//    viewport, colour masks), every binding (framebuffers, program, pipeline, vertex
//    array, pack buffer, texture) and the pixel-store state are set before cullFrame and
//    set again, with the same values, after each of the application's draws; inside the
//    draw callback the application first restores what it draws with. So every depth
//    source call meets that state, and the state glGet reports when cullFrame returns
//    must equal the state when it was called.
// Methods log-state, log-zfar and pq with the readpixels, pbo and query readers, single-
// and multisampled framebuffers, on the forest and the city.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gl_state_probe.hpp"
#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

struct FuzzCase {
  Method method;
  std::string reader;
  std::uint32_t samples;
  DepthConvention convention;
  DepthFormat format;
};

std::string caseName(const testing::TestParamInfo<FuzzCase>& info) {
  const FuzzCase& c = info.param;
  std::ostringstream out;
  out << toString(c.method) << "_" << c.reader << "_ms" << c.samples << "_"
      << toString(c.convention) << "_" << formatName(c.format);
  return sanitize(out.str());
}

class GlStateFuzzTest : public testing::TestWithParam<FuzzCase> {};

// Frames per scene and case (times LOGRID_ORACLE_INTENSITY).
constexpr std::size_t kFrames = 4;

TEST_P(GlStateFuzzTest, NoMissesAndTheApplicationStateIsKept) {
  LOGRID_REQUIRE_GL();
  const FuzzCase c = GetParam();
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (GLint(c.samples) > max_samples) GTEST_SKIP() << "GL_MAX_SAMPLES is " << max_samples;
  test::AppObjects objects;
  std::uint32_t case_seed = 0x9E3779B9u;
  for (char ch : caseName({c, 0})) case_seed = case_seed * 31u + std::uint32_t(ch);

  std::uint64_t visible = 0, occluded = 0;
  for (const char* scene_name : {"forest", "city"}) {
    const SceneKey key{scene_name, scene_name == std::string("city") ? kCityScale : kForestScale};
    LoadedScene& scene = loadScene(key);
    View view;
    view.convention = c.convention;
    view.format = c.format;
    RunConfig config = makeConfig(scene.prepared, c.method, c.reader, view, kFrames);
    config.view.samples = c.samples;
    const int w = int(config.view.width), h = int(config.view.height);

    // The hooks' shared state: this frame's seeds, the snapshot at cullFrame, findings.
    std::uint32_t shaping_seed = 0, other_seed = 0;
    GLuint app_framebuffer = 0;
    test::GlSnapshot at_call;
    std::string what, changed;
    const unsigned other = test::kContractState | test::kBindings | test::kPixelStore;
    config.hooks.after_clear = [&] {
      // The application's framebuffer is the one the runner just bound and cleared.
      GLint bound = 0;
      glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
      app_framebuffer = GLuint(bound);
      std::mt19937 rng(shaping_seed);
      what = test::setRandomGlState(rng, objects, test::kDrawShaping, app_framebuffer, w, h);
    };
    config.hooks.before_cull = [&] {
      std::mt19937 rng(other_seed);
      what += "| " + test::setRandomGlState(rng, objects, other, app_framebuffer, w, h);
      at_call = test::snapshotGlState();
    };
    config.hooks.before_draw = [&] {
      // What the application draws its frame with (the runner then binds its
      // framebuffer and renderer): the contract's state.
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
      glDisable(GL_DEPTH_CLAMP);
      glDepthRangeIndexed(0, 0.0, 1.0);
      for (int i = 0; i < 8; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
      glDisable(GL_POLYGON_OFFSET_FILL);
      glDisable(GL_POLYGON_OFFSET_LINE);
      glDisable(GL_POLYGON_OFFSET_POINT);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      if (epoxy_has_gl_extension("GL_EXT_depth_bounds_test")) {
        glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
      }
    };
    config.hooks.after_draw = [&] {
      std::mt19937 rng(other_seed);
      test::setRandomGlState(rng, objects, other, app_framebuffer, w, h);
    };
    config.hooks.after_cull = [&] {
      changed = test::diffGlState(at_call, test::snapshotGlState());
      // Back to defaults, so that the ID pass's clear is whole; it sets the same
      // draw-shaping state again after its clear.
      test::setDefaultGlState(w, h);
    };

    FrameRunner runner(scene.prepared, *scene.renderer, config);
    for (std::size_t f = 0; f < config.frames; ++f) {
      shaping_seed = case_seed ^ std::uint32_t(f * 0x85EBCA6Bu) ^ (key.name == "city" ? 1u : 0u);
      other_seed = shaping_seed * 0xC2B2AE35u + 7u;
      test::setDefaultGlState(w, h);
      changed = "(cullFrame did not run)";
      FrameRecord r;
      try {
        r = runner.renderFrame(f);
      } catch (const Error& e) {
        ADD_FAILURE() << key.id() << " frame " << f << " under state {" << what
                      << "}: " << e.what();
        test::setDefaultGlState(w, h);
        continue;
      }
      test::setDefaultGlState(w, h);
      EXPECT_GE(r.visible, 0) << "the oracle did not run";
      visible += std::uint64_t(std::max<std::int64_t>(r.visible, 0));
      occluded += r.stats.boxes_occluded;
      EXPECT_EQ(r.missed, 0) << key.id() << " frame " << f << ": " << toString(c.method)
                             << " missed " << r.missed << " of " << r.visible
                             << " visible objects under application state {" << what << "}";
      EXPECT_EQ(r.missed_artifacts, 0) << key.id() << " frame " << f;
      EXPECT_EQ(changed, "") << key.id() << " frame " << f
                             << ": logrid changed the application's state {" << what << "}";
    }
  }
  // The frames showed objects and, single-sampled, culled boxes (else they would test
  // little). Multisampled frames may cull nothing: where a sample mask, sample coverage
  // or alpha to coverage left samples unwritten, the farthest sample is the cleared one.
  std::printf("%llu visible objects, %llu boxes occluded\n", (unsigned long long)visible,
              (unsigned long long)occluded);
  EXPECT_GT(visible, 0u);
  if (c.samples == 0) {
    EXPECT_GT(occluded, 0u);
  }
}

std::vector<FuzzCase> cases() {
  std::vector<FuzzCase> out;
  int i = 0;
  for (Method m : {Method::LogState, Method::LogZfar, Method::Pq}) {
    for (const char* r : {"readpixels", "pbo", "query", "reduce"}) {
      for (std::uint32_t samples : {0u, 4u}) {
        // Conventions and formats vary over the cases rather than multiplying them.
        const DepthConvention v =
            (i / 2 + i) % 2 ? DepthConvention::Reversed : DepthConvention::Standard;
        const DepthFormat f = v == DepthConvention::Reversed ? DepthFormat::D32F
                              : (i / 2) % 3 == 0             ? DepthFormat::D24
                              : (i / 2) % 3 == 1             ? DepthFormat::D16
                                                             : DepthFormat::D32F;
        out.push_back({m, r, samples, v, f});
        ++i;
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Methods, GlStateFuzzTest, testing::ValuesIn(cases()), caseName);

}  // namespace
}  // namespace logrid::oracle
