// The floor and the check kept apart from the timed frame (label oracle; docs/ANALYSIS.md,
// "An honest floor"):
//  * every runner's frames, verified or not, the oracle's included, go into the same
//    kind of framebuffer, without an object-ID attachment; verifying a frame changes
//    neither its picture nor what the culler did;
//  * the oracle's frame draws exactly the set an untimed ID pass found visible;
//  * the check still catches a miss: a frame whose depth buffer the application spoils
//    before culling (cleared to the nearest depth: every box looks occluded) misses
//    visible objects, and the ID pass, in its own framebuffer after the frame, finds them.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

constexpr std::size_t kFrames = 6;

void expectSameFramebuffer(const gl::FramebufferDesc& a, const gl::FramebufferDesc& b,
                           const std::string& what) {
  EXPECT_FALSE(b.object_ids) << what << ": a timed frame's framebuffer has an ID attachment";
  EXPECT_EQ(a.width, b.width) << what;
  EXPECT_EQ(a.height, b.height) << what;
  EXPECT_EQ(a.samples, b.samples) << what;
  EXPECT_EQ(a.depth.format, b.depth.format) << what;
  EXPECT_EQ(a.depth.convention, b.depth.convention) << what;
}

TEST(Floor, VerifiedAndOracleFramesUseTheSameFramebufferAndDoTheSameWork) {
  LOGRID_REQUIRE_GL();
  LoadedScene& scene = loadScene(sceneKey("forest"));
  RunConfig plain = makeConfig(scene.prepared, Method::LogZfar, "readpixels", View{}, kFrames);
  plain.verify = false;
  RunConfig verified = plain;
  verified.verify = true;
  RunConfig oracle = plain;
  oracle.method = samples::MethodChoice{};
  FrameRunner a(scene.prepared, *scene.renderer, plain);
  FrameRunner b(scene.prepared, *scene.renderer, verified);
  FrameRunner o(scene.prepared, *scene.renderer, oracle);
  expectSameFramebuffer(a.framebuffer().desc(), a.framebuffer().desc(), "unverified");
  expectSameFramebuffer(a.framebuffer().desc(), b.framebuffer().desc(), "verified");
  expectSameFramebuffer(a.framebuffer().desc(), o.framebuffer().desc(), "oracle");
  std::uint64_t visible = 0;
  for (std::size_t f = 0; f < kFrames; ++f) {
    const FrameRecord ra = a.renderFrame(f);
    const std::vector<std::uint8_t> color_a = a.readColor();
    const std::vector<float> depth_a = a.framebuffer().readDepth();
    const FrameRecord rb = b.renderFrame(f);
    EXPECT_EQ(ra.visible, -1) << "frame " << f << ": an unverified frame ran the ID pass";
    ASSERT_GE(rb.visible, 0) << "frame " << f << ": the verified frame ran no ID pass";
    EXPECT_EQ(rb.missed, 0) << "frame " << f;
    visible += std::uint64_t(rb.visible);
    // The ID pass after the frame leaves the frame's own buffers as the frame drew them.
    EXPECT_TRUE(b.readColor() == color_a) << "frame " << f << ": verifying changed the picture";
    EXPECT_TRUE(b.framebuffer().readDepth() == depth_a)
        << "frame " << f << ": verifying changed the frame's depth buffer";
    EXPECT_EQ(ra.stats.objects_drawn, rb.stats.objects_drawn) << "frame " << f;
    EXPECT_EQ(ra.stats.pixels_read, rb.stats.pixels_read) << "frame " << f;
    EXPECT_EQ(ra.triangles, rb.triangles) << "frame " << f;

    const FrameRecord ro = o.renderFrame(f);
    ASSERT_GE(ro.visible, 0) << "frame " << f << ": the oracle found no visible set";
    EXPECT_EQ(ro.visible, rb.visible) << "frame " << f << ": two ID passes of one frame differ";
    EXPECT_EQ(ro.missed, 0) << "frame " << f;
    // Exactly the visible set (and the objects shown only by depth-extrapolated
    // fragments, which the full render shows too): nothing more, nothing less.
    EXPECT_EQ(std::int64_t(o.drawnObjects().size()), ro.visible + ro.artifacts) << "frame " << f;
    EXPECT_EQ(ro.stats.objects_drawn, o.drawnObjects().size()) << "frame " << f;
    EXPECT_LE(ro.triangles, rb.triangles)
        << "frame " << f << ": the floor drew more triangles than a conservative method";
  }
  EXPECT_GT(visible, 0u) << "the walk saw nothing: the test tests nothing";
  expectSameFramebuffer(a.framebuffer().desc(), b.framebuffer().desc(), "verified, after frames");
  expectSameFramebuffer(a.framebuffer().desc(), o.framebuffer().desc(), "oracle, after frames");
}

// A deliberately wrong cull: the application clears the depth buffer to the nearest depth
// right before culling, so every box that does not cross the near plane looks occluded.
// The verification, in its own framebuffer after the frame, must report the misses; the
// same runner without the spoiled depth must report none.
TEST(Floor, VerificationCatchesADeliberatelyWrongCull) {
  LOGRID_REQUIRE_GL();
  LoadedScene& scene = loadScene(sceneKey("forest"));
  for (const DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (const bool spoil : {false, true}) {
      View view;
      view.convention = convention;
      RunConfig config = makeConfig(scene.prepared, Method::LogZfar, "readpixels", view, kFrames);
      const FrameRunner* runner = nullptr;
      if (spoil) {
        config.hooks.before_cull = [&runner, convention] {
          const GLfloat nearest = convention == DepthConvention::Reversed ? 1.0f : 0.0f;
          glClearNamedFramebufferfv(runner->framebuffer().handle(), GL_DEPTH, 0, &nearest);
        };
      }
      FrameRunner r(scene.prepared, *scene.renderer, config);
      runner = &r;
      std::int64_t visible = 0, missed = 0;
      for (std::size_t f = 0; f < config.frames; ++f) {
        const FrameRecord rec = r.renderFrame(f);
        ASSERT_GE(rec.visible, 0) << "frame " << f << ": no ID pass";
        visible += rec.visible;
        missed += rec.missed;
        // What was missed is visible and was not drawn.
        const std::vector<ObjectId>& drawn = r.drawnObjects();
        for (ObjectId id : r.missedObjects()) {
          EXPECT_EQ(std::count(drawn.begin(), drawn.end(), id), 0)
              << "frame " << f << ": object " << id << " was drawn yet counted missed";
        }
      }
      const std::string what =
          std::string(toString(convention)) + (spoil ? ", spoiled depth" : ", honest");
      EXPECT_GT(visible, 0) << what << ": the walk saw nothing";
      if (spoil) {
        EXPECT_GT(missed, 0) << what << ": the verification did not catch a wrong cull";
      } else {
        EXPECT_EQ(missed, 0) << what;
      }
    }
  }
}

}  // namespace
}  // namespace logrid::oracle
