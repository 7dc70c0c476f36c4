// Walkthroughs with the directional discretized occluders on real GL frames, every frame
// checked against the object-ID oracle: `ddo` (the paper's culler) and `ddo+log`
// (occluders drawn first, then log-state) never miss a visible object, on the city, the
// forest and an office building read from a model file (closed, finely tessellated walls
// and slabs: the faces of nodes inside them are the occluders), in both depth conventions.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "gl_state_probe.hpp"
#include "logrid/coverage.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/occluder_renderer.hpp"
#include "logrid/grid.hpp"
#include "oracle_harness.hpp"
#include "scene/ddo_scene.hpp"
#include "scene/loader.hpp"

namespace logrid::oracle {
namespace {

constexpr std::size_t kFrames = 6;
// ddo+log's grid tile: at the tests' 160x120 the city's occluders fill no 32-pixel tile,
// and an occluder that fills none is not drawn (ddo::OccluderBudget).
constexpr std::uint32_t kDdoLogTile = 8;

// ddo+log draws the selected occluders into the depth buffer; ddo enters them into its map.
bool drawsOccluders(const OracleCase& c) { return c.method.name() == "ddo+log"; }

// The DDO cases: each scene (with its octree; "office-file" is the office read back from
// OBJ) with ddo and ddo+log, in standard D24 and reversed D32F depth. Named
// <scene>_<method>_<convention>_d<format>.
std::vector<OracleCase> cases() {
  std::vector<OracleCase> out;
  for (const char* scene : {"city", "forest", "office-file"}) {
    for (const char* method : {"ddo", "ddo+log"}) {
      for (const auto& [convention, format] :
           {std::pair{DepthConvention::Standard, DepthFormat::D24},
            std::pair{DepthConvention::Reversed, DepthFormat::D32F}}) {
        OracleCase c;
        c.scene = sceneKey(scene, 0, true);
        c.method = *samples::parseMethodChoice(method);
        c.view.convention = convention;
        c.view.format = format;
        if (drawsOccluders(c)) c.view.tile = kDdoLogTile;
        c.frames = kFrames;
        c.name = std::string(scene) + "_" + method + "_" + toString(convention) + "_d" +
                 formatName(format);
        out.push_back(c);
      }
    }
  }
  return out;
}

// The office is read from a file, which needs assimp.
bool needsSceneFiles(const OracleCase& c) {
  return c.scene.name == "office-file" && !samples::sceneFilesSupported();
}

class DdoWalk : public testing::TestWithParam<OracleCase> {};

TEST_P(DdoWalk, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  if (needsSceneFiles(GetParam())) GTEST_SKIP() << "built without assimp: no scene from a file";
  checkCase(GetParam());
}

// What each walk must show besides zero misses and visible objects. Not vacuous where
// the scene has closed surfaces across octree cells: occluders were selected, and ddo
// culled nodes with its occlusion map while ddo+log (which draws only occluders that
// fill a tile) recorded tiles from their coverage. The forest has none along its trail
// (measured: 127 of 1314 faces valid from some region, none from the trail's viewpoints,
// which see them at more than 80 degrees or from closer than a cell); there the walk
// checks the plain traversal.
std::vector<OracleCase> walkCases() {
  std::vector<OracleCase> out = cases();
  for (OracleCase& c : out) {
    const bool occluders = c.scene.name != "forest";
    c.expect_occluders = occluders;
    c.expect_occluded = occluders && !drawsOccluders(c);
    c.expect_occluder_tiles = occluders && drawsOccluders(c);
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, DdoWalk, testing::ValuesIn(walkCases()), oracleCaseName);

// The ground truth of ddo+log: drawing the selected occluders into the depth buffer before
// the whole scene changes no pixel of the picture. Where an occluder lands, the geometry
// that makes it valid lies in front of it on screen; everything it hides is hidden anyway.
// And every pixel an occluder stores lies in the rectangle and key range ddo+log announces
// to the culler (Occluder::rect, near_key, far_key).
class DdoOccluderPixels : public testing::TestWithParam<OracleCase> {};

TEST_P(DdoOccluderPixels, DrawingOccludersFirstChangesNoPixel) {
  LOGRID_REQUIRE_GL();
  const OracleCase& c = GetParam();
  if (needsSceneFiles(c)) GTEST_SKIP() << "built without assimp: no scene from a file";
  LoadedScene& scene = loadScene(c.scene);
  const View& v = c.view;
  const DepthConvention convention = v.convention;
  const RunConfig config = configFor(c, scene.prepared);
  gl::FramebufferDesc fb;
  fb.width = v.width;
  fb.height = v.height;
  fb.depth = config.view.depth;
  gl::Framebuffer framebuffer(fb);
  gl::OccluderRenderer occluders;
  ddo::Selector selector(*scene.prepared.ddo);
  const float background[4] = {0.1f, 0.2f, 0.3f, 1.0f};
  const float clear = convention == DepthConvention::Reversed ? 0.0f : 1.0f;
  std::uint64_t occluder_pixels = 0, recorded_tiles = 0;
  for (std::size_t f = 0; f < config.frames; ++f) {
    const Camera camera = samples::makeCamera(scene.prepared.path.frame(f, config.frames),
                                              scene.prepared.origin, config.view);
    auto drawAll = [&] {
      scene.renderer->begin(gl::Pass::Shaded, camera);
      for (ObjectId id = 0; id < scene.prepared.mesh.draws.size(); ++id) scene.renderer->draw(id);
      scene.renderer->end();
    };
    framebuffer.bind();
    framebuffer.clear(background);
    drawAll();
    const std::vector<std::uint8_t> plain = framebuffer.readColor();
    const std::vector<float> plain_depth = framebuffer.readDepth();

    framebuffer.clear(background);
    ddo::SelectionStats stats;
    selector.select(camera, {}, stats);
    occluders.draw(selector.occluders(), camera, framebuffer.handle());
    const std::vector<float> occluder_depth = framebuffer.readDepth();
    // The coverage ddo+log records without a read (coverage.hpp): every pixel of a cell
    // an occluder covers entirely holds a key at or in front of its far key where GL
    // draws the occluders; below, the scene's own keys lie in front of every occluder
    // pixel, so the scene, which ddo+log draws instead, hides the cells as well.
    OcclusionGrid grid({v.width, v.height, kDdoLogTile, GridVariant::OcclusionState});
    grid.reset(clear);
    const CoverageRule rule = coverageRule(camera);
    for (const ddo::Occluder& o : selector.occluders()) {
      DrawnQuad q;
      for (int i = 0; i < 4; ++i) q.window[i][0] = o.window[i][0], q.window[i][1] = o.window[i][1];
      q.near_key = o.near_key;
      q.far_key = o.far_key;
      recorded_tiles += grid.recordCovered(q, rule);
    }
    for (std::uint32_t y = 0; y < v.height; ++y) {
      for (std::uint32_t x = 0; x < v.width; ++x) {
        const float bound = grid.hiddenAt(x, y);
        if (!(bound < clear)) continue;
        const float stored = depthKey(convention, occluder_depth[y * v.width + x]);
        EXPECT_LE(stored, bound) << "frame " << f << " pixel " << x << ", " << y
                                 << ": recorded hidden, but stored beyond the recorded key";
        if (!(stored <= bound)) y = v.height - 1, x = v.width - 1;
      }
    }
    drawAll();
    const std::vector<std::uint8_t> with = framebuffer.readColor();

    std::size_t differing = 0, first = 0;
    for (std::size_t i = 0; i < plain.size(); i += 4) {
      if (std::equal(&plain[i], &plain[i] + 4, &with[i])) continue;
      if (differing++ == 0) first = i / 4;
    }
    for (std::size_t i = 0; i < occluder_depth.size(); ++i) {
      if (occluder_depth[i] == clear) continue;
      ++occluder_pixels;
      // The scene's depth there is nearer than the occluder's.
      const float scene_key = depthKey(convention, plain_depth[i]);
      const float occluder_key = depthKey(convention, occluder_depth[i]);
      EXPECT_LT(scene_key, occluder_key)
          << "frame " << f << " pixel " << i % v.width << ", " << i / v.width;
      if (!(scene_key < occluder_key)) break;
      // What ddo+log tells the culler (DrawnArea): the pixel lies in the rectangle of an
      // occluder whose key range holds the stored key.
      const auto x = std::int32_t(i % v.width), y = std::int32_t(i / v.width);
      bool announced = false;
      for (const ddo::Occluder& o : selector.occluders()) {
        announced =
            announced || (x >= o.rect.x0 && x < o.rect.x1 && y >= o.rect.y0 && y < o.rect.y1 &&
                          o.near_key <= occluder_key && occluder_key <= o.far_key);
      }
      EXPECT_TRUE(announced) << "frame " << f << " pixel " << x << ", " << y << ": key "
                             << occluder_key << " outside every occluder's rectangle and range";
      if (!announced) break;
    }
    EXPECT_EQ(differing, 0u) << c.scene.name << " frame " << f << ": " << differing
                             << " pixels differ when the occluders are drawn first, the first at "
                             << first % v.width << ", " << first / v.width;
  }
  std::printf("[ oracle ] %s: %llu occluder pixels, %llu tiles recorded full over %zu frames\n",
              c.scene.name.c_str(), (unsigned long long)occluder_pixels,
              (unsigned long long)recorded_tiles, config.frames);
  if (c.scene.name != "forest") {
    EXPECT_GT(occluder_pixels, 0u) << "no occluder reached the screen";
    EXPECT_GT(recorded_tiles, 0u) << "no tile was recorded from the occluders' coverage";
  }
}

std::vector<OracleCase> pixelCases() {
  std::vector<OracleCase> out;
  for (const OracleCase& c : cases()) {
    if (drawsOccluders(c)) out.push_back(c);
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, DdoOccluderPixels, testing::ValuesIn(pixelCases()),
                         oracleCaseName);

// ddo+log under the application's GL state: after each clear the "application" leaves
// random draw-shaping state (face culling and winding, stencil, sample state, rasterizer
// discard, scissor; tests/support/gl_state_probe.hpp), which the occluders are drawn
// under and the frame is drawn with (the ID pass too, so that "visible" means what the
// application sees). The occluders must land as under GL's defaults (no visible object
// missed) and leave that state as they found it.
class DdoGlStateWalk : public testing::TestWithParam<OracleCase> {};

TEST_P(DdoGlStateWalk, NoMissesAndTheApplicationStateIsKept) {
  LOGRID_REQUIRE_GL();
  const OracleCase& c = GetParam();
  if (needsSceneFiles(c)) GTEST_SKIP() << "built without assimp: no scene from a file";
  LoadedScene& scene = loadScene(c.scene);
  RunConfig config = configFor(c, scene.prepared);
  const int w = int(config.view.width), h = int(config.view.height);
  test::AppObjects objects;
  std::uint32_t seed = 0;
  std::string what, changed;
  test::GlSnapshot after_clear;
  // The occluders were drawn between the two hooks, and then the runner's renderer bound
  // its program and vertex array (the GL test occluder_renderer_test checks those too).
  auto snapshot = [] {
    test::GlSnapshot s = test::snapshotGlState();
    s.erase("GL_CURRENT_PROGRAM");
    s.erase("GL_VERTEX_ARRAY_BINDING");
    return s;
  };
  config.hooks.after_clear = [&] {
    GLint bound = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    std::mt19937 rng(seed);
    what = test::setRandomGlState(rng, objects, test::kDrawShaping, GLuint(bound), w, h);
    after_clear = snapshot();
  };
  config.hooks.before_cull = [&] { changed = test::diffGlState(after_clear, snapshot()); };
  config.hooks.after_cull = [&] { test::setDefaultGlState(w, h); };
  FrameRunner runner(scene.prepared, *scene.renderer, config);
  std::uint64_t occluders = 0, visible = 0;
  for (std::size_t f = 0; f < config.frames; ++f) {
    seed = 0x51ED270Bu * std::uint32_t(f + 1) + (c.view.convention == DepthConvention::Reversed);
    test::setDefaultGlState(w, h);
    changed = "(the culled frame did not run)";
    const FrameRecord r = runner.renderFrame(f);
    test::setDefaultGlState(w, h);
    occluders += std::uint64_t(std::max<std::int64_t>(r.occluders, 0));
    visible += std::uint64_t(std::max<std::int64_t>(r.visible, 0));
    EXPECT_EQ(r.missed, 0) << c.scene.name << " frame " << f << " under state {" << what << "}; "
                           << reproducer(c.scene, config);
    EXPECT_EQ(changed, "") << c.scene.name << " frame " << f
                           << ": drawing the occluders changed the application's state {" << what
                           << "}";
  }
  std::printf("[ oracle ] %s %s under random state: %llu visible, %llu occluders\n",
              c.scene.name.c_str(), c.method.name().c_str(), (unsigned long long)visible,
              (unsigned long long)occluders);
  EXPECT_GT(visible, 0u);
  EXPECT_GT(occluders, 0u) << "no occluder was drawn; the walk tests nothing";
}

std::vector<OracleCase> glStateCases() {
  std::vector<OracleCase> out;
  for (const OracleCase& c : pixelCases()) {
    if (c.scene.name != "forest") out.push_back(c);  // the forest's trail selects no occluder
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, DdoGlStateWalk, testing::ValuesIn(glStateCases()), oracleCaseName);

// A scene with moving objects: the octree holds the static objects only (its occluders
// hold whatever the movers do), ddo draws every mover in the view frustum, and ddo+log
// culls the motion hierarchy (refit) on top of the static scene's occluders. The movers
// pass in front of and behind the city's blocks; no visible object may be missed.
class DdoMovingWalk : public testing::TestWithParam<OracleCase> {};

TEST_P(DdoMovingWalk, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const OracleCase& c = GetParam();
  LoadedScene& scene = loadScene(c.scene);
  ASSERT_EQ(scene.prepared.motion.movers.size(), c.scene.movers);
  ASSERT_TRUE(scene.prepared.ddo);
  for (ObjectId id : scene.prepared.ddo->objects()) {
    ASSERT_LT(id, scene.prepared.static_objects) << "a moving object is in the DDO octree";
  }
  checkCase(c, scene);
}

std::vector<OracleCase> movingCases() {
  constexpr std::uint32_t kMovers = 60;
  std::vector<OracleCase> out;
  for (const char* method : {"ddo", "ddo+log"}) {
    OracleCase c;
    c.scene = sceneKey("city", kMovers, true);
    c.method = *samples::parseMethodChoice(method);
    if (drawsOccluders(c)) c.view.tile = kDdoLogTile;
    c.frames = kFrames;
    c.expect_occluded = false;
    c.expect_occluders = true;
    c.name = method;
    out.push_back(c);
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Movers, DdoMovingWalk, testing::ValuesIn(movingCases()), oracleCaseName);

}  // namespace
}  // namespace logrid::oracle
