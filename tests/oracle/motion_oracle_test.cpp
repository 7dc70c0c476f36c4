// Walkthroughs with moving objects (samples/scene/movers.hpp) on the forest and the
// city, every frame checked against the object-ID oracle, which draws the movers from
// their own boxes at the frame's time (not from the hierarchy under test):
//
//   MovingWalk      log-state and log-zfar, both depth conventions, every motion
//                   hierarchy (refit, rebuild, ternary, binary): frames spread over the
//                   path (large motion between frames) and, reversed, 3 s apart (small
//                   motion: tight boxes, splits and merges develop).
//   MovingTraversal the ternary tree with lookahead, colliding-query detection and
//                   temporal coherence (its node ids change), with several depth readers,
//                   so the §3.3 statistics come from pixel reads and hardware queries;
//                   and pq (one hardware occlusion query per box) in both conventions.
//   AnimatedFile    a scene from a file whose meshes move along paths (--animate).
//   ManagedReaderWithMovers  the application-managed reader, multisampled, with the
//                   ternary-objects tree, whose statistics pass reads after the frame.
//   MotionScenario  the walks above contain what they claim: movers that leave the
//                   scene bounds, pass through each other, and stop and start again.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "oracle_harness.hpp"
#include "scene/loader.hpp"

namespace logrid::oracle {
namespace {

constexpr std::uint32_t kMovers = 60;
constexpr std::size_t kMotionFrames = 10;
constexpr double kSmallStep = 3.0;  // seconds between frames for the small-motion walks

SceneKey movingKey(const std::string& name) { return sceneKey(name, kMovers); }

class MovingWalk : public testing::TestWithParam<OracleCase> {};

TEST_P(MovingWalk, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const OracleCase& c = GetParam();
  ASSERT_EQ(loadScene(c.scene).prepared.motion.movers.size(), kMovers);
  checkCase(c);
}

std::vector<OracleCase> movingCases() {
  std::vector<OracleCase> out;
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar}) {
      for (const bvh::MotionInfo& h : bvh::motionTable()) {
        for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
          OracleCase c;
          c.scene = movingKey(scene);
          c.method = choice(m);
          c.view.convention = conv;
          c.frames = kMotionFrames;
          c.hierarchy = h.name;
          c.time_step = conv == DepthConvention::Reversed ? kSmallStep : 0.0;
          // Not vacuous: boxes are found occluded. The small-motion walks cover only the
          // first 30 m of the path, where the trees of the test city's few hundred objects
          // (cells of a dozen objects, drawn together) can be visible throughout.
          const std::string name = h.name;
          c.expect_occluded = c.time_step == 0 || (name != "ternary" && name != "binary");
          c.name = std::string(scene) + "_" + h.name + "_" + toString(m) + "_" + toString(conv);
          out.push_back(c);
        }
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Movers, MovingWalk, testing::ValuesIn(movingCases()), oracleCaseName);

// The ternary tree with lookahead, colliding-query detection and temporal coherence, with
// several depth readers.
class MovingTraversal : public testing::TestWithParam<OracleCase> {};

TEST_P(MovingTraversal, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  checkCase(GetParam());
}

OracleCase traversalCase(const std::string& scene, Method m, const std::string& reader,
                         std::uint32_t lookahead, bool coherence,
                         DepthConvention convention = DepthConvention::Standard) {
  OracleCase c;
  c.scene = movingKey(scene);
  c.method = choice(m, lookahead, coherence);
  c.reader = reader;
  c.view.width = 200;
  c.view.height = 150;
  c.view.tile = 16;
  c.view.format = DepthFormat::D24;
  c.view.convention = convention;
  c.frames = kMotionFrames;
  c.hierarchy = "ternary";
  // Small motion in the forest; frames over the whole path in the city, whose first
  // 30 m show too little to occlude (see MovingWalk).
  c.time_step = scene == "forest" ? kSmallStep : 0.0;
  c.colliding = true;
  c.expect_occluded = true;
  c.name = scene + "_" + toString(m) + "_" + reader + (coherence ? "_tc" : "") + "_" +
           toString(convention);
  return c;
}

INSTANTIATE_TEST_SUITE_P(
    Ternary, MovingTraversal,
    testing::Values(traversalCase("forest", Method::LogState, "pbo", kUnlimitedLookahead, true),
                    traversalCase("forest", Method::LogZfar, "query", 16, false),
                    traversalCase("city", Method::LogState, "query", kUnlimitedLookahead, true),
                    traversalCase("city", Method::LogZfar, "software", 16, true),
                    // The hardware-query method: one occlusion query per tested box.
                    traversalCase("forest", Method::Pq, "query", 16, false,
                                  DepthConvention::Reversed),
                    traversalCase("city", Method::Pq, "query", kUnlimitedLookahead, true,
                                  DepthConvention::Standard)),
    oracleCaseName);

// A scene from a file whose meshes move along paths (--animate, samples/scene/motion.hpp):
// crates behind a wall come out from behind it, drive past its end, circle, stop and go,
// pass through another crate, and one leaves the scene bounds.
std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string boxObj(const std::string& name, DVec3 lo, DVec3 hi, std::size_t& vertices) {
  std::ostringstream out;
  out << "o " << name << "\n";
  for (int i = 0; i < 8; ++i) {
    out << "v " << (i & 4 ? hi.x : lo.x) << " " << (i & 2 ? hi.y : lo.y) << " "
        << (i & 1 ? hi.z : lo.z) << "\n";
  }
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) {
    const std::size_t b = vertices + 1;
    out << "f " << b + q[0] << " " << b + q[1] << " " << b + q[2] << "\nf " << b + q[0] << " "
        << b + q[2] << " " << b + q[3] << "\n";
  }
  vertices += 8;
  return out.str();
}

// A wall (mesh 0) and eight crates side by side behind it (meshes 1-8), as an OBJ.
std::string wallAndCrates() {
  std::size_t vertices = 0;
  std::string obj = boxObj("wall", {-20, 0, -2}, {20, 10, 2}, vertices);
  for (int k = 0; k < 8; ++k) {
    obj += boxObj("crate" + std::to_string(k), {-16.0 + 4 * k, 0, -10}, {-14.0 + 4 * k, 2, -8},
                  vertices);
  }
  return obj;
}

TEST(AnimatedFile, NoVisibleMeshIsMissed) {
  LOGRID_REQUIRE_GL();
  if (!samples::sceneFilesSupported()) GTEST_SKIP() << "built without assimp";
  // No ground: it would straddle every plane and share the root's third child with the
  // wall, whose box (the ground's) is then drawn last in the two-list order and hides
  // nothing from log-state or pq.
  const std::string model = writeFile("logrid_animated.obj", wallAndCrates());
  const std::string motion = writeFile("logrid_animated.json", R"({"objects": [
    {"mesh": 1, "path": [[0, 0, 0], [0, 0, 40]], "speed": 8},
    {"mesh": 2, "path": [[0, 0, 0], [40, 0, 0]], "speed": 5, "move_seconds": 3, "stop_seconds": 2},
    {"mesh": 3, "path": [[0, 0, 0], [0, 0, 35], [17, 0, 35]], "speed": 6, "loop": true},
    {"mesh": 4, "path": [[0, 0, 0], [0, 0, -400]], "speed": 40},
    {"mesh": 7, "path": [[0, 0, 0], [6, 0, 0]], "speed": 2}]})");
  samples::Scene s = samples::loadSceneFile(model);
  samples::animateMeshes(s, motion);
  ASSERT_EQ(s.motion.movers.size(), 5u);
  s.path = samples::CameraPath({{{0, 6, 45}, {0, 3, 0}, 0}, {{8, 6, 40}, {0, 3, 0}, 12}});
  const bvh::BuildArgs args = samples::defaultBuildArgs(s);
  LoadedScene scene;
  scene.prepared = samples::prepareScene(std::move(s), args);
  scene.renderer = std::make_unique<gl::MeshRenderer>(scene.prepared.mesh);
  for (const char* hierarchy : {"refit", "ternary", "ternary-objects"}) {
    for (Method m : {Method::LogState, Method::LogZfar, Method::Pq}) {
      OracleCase c;
      c.scene = {model, 1, Offset::None, 0, 0};
      c.method = choice(m);
      c.reader = m == Method::Pq ? "query" : "readpixels";
      c.view.convention =
          m == Method::LogZfar ? DepthConvention::Reversed : DepthConvention::Standard;
      c.frames = 12;
      c.hierarchy = hierarchy;
      c.time_step = 1.0;
      // Ten meshes are fewer than O_split: leaves of two, so the ternary tree has boxes
      // the wall can hide.
      c.adjust = [](RunConfig& config) { config.motion.ternary.o_split = 2; };
      c.name =
          std::string("animated file (--animate ") + motion + ") " + hierarchy + " " + toString(m);
      checkCase(c, scene);
    }
  }
}

// Methods that read no depth (view-frustum culling, the hardware-query schedules), run
// with a depth reader all the same: the runner begins that reader's frame itself, since it
// feeds the cpu reader what is drawn and the ternary tree's statistics pass reads depth
// after the frame. Before, the first threw "OcclusionBuffer::drawObject: call it between
// beginFrame() and endFrame()" and the second read through a source whose frame was never
// begun (GL_INVALID_FRAMEBUFFER_OPERATION); the widened soak run found both.
TEST(MethodsWithoutDepth, RunWithAReaderThatIsFedAndMeasured) {
  LOGRID_REQUIRE_GL();
  for (Method m : {Method::Vfc, Method::Chc}) {
    OracleCase moving;
    moving.scene = movingKey("forest");
    moving.method = choice(m);
    moving.frames = 4;
    moving.hierarchy = "ternary";
    moving.expect_occluded = false;
    moving.name = std::string("forest movers ternary ") + toString(m) + " readpixels";
    checkCase(moving);
    OracleCase fed = moving;
    fed.scene = sceneKey("forest");
    fed.hierarchy.clear();
    fed.reader = "cpu";
    fed.name = std::string("forest ") + toString(m) + " cpu";
    checkCase(fed);
  }
}

// The cpu reader in a scene with movers: its buffer draws each moving object where the
// frame draws it (its own mesh placed by the frame's transform of its id). Before that it
// left them out, and before that, building its occluder meshes threw
// "OccluderMeshes::addObject: object N: a vertex lies outside the box given for the
// object" for the first mover (its mesh in its own coordinates against its box in the
// scene); the widened soak run found it. Both conventions, per pixel and masked.
TEST(CpuReaderWithMovers, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  for (const char* scene : {"forest", "city"}) {
    for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
      for (Method m : {Method::LogZfar, Method::LogState}) {
        OracleCase c;
        c.scene = movingKey(scene);
        c.method = choice(m);
        c.reader = "cpu";
        c.view.convention = conv;
        c.frames = 4;
        c.hierarchy = "refit";
        const bool masked = conv == DepthConvention::Reversed && m == Method::LogZfar;
        if (masked) {
          c.adjust = [](RunConfig& config) {
            config.cpu.representation = cpu::Representation::Masked;
          };
        }
        c.name = std::string(scene) + " movers refit " + toString(m) + " cpu " + toString(conv) +
                 (masked ? " masked" : "");
        const WalkTotals t = checkCase(c);
        EXPECT_GT(t.cpu_moved, 0u) << c.name << ": no mover was drawn into the buffer";
      }
    }
  }
}

// A moving wall hides static crates from the cpu reader: the walk culls boxes only the
// wall can hide (the crates stand side by side behind it), and misses nothing while the
// wall slides back and forth in front of them. With movers left out of the buffer (as
// before) no box was ever found occluded.
TEST(CpuReaderWithMovers, AMovingWallHidesWhatIsBehindIt) {
  LOGRID_REQUIRE_GL();
  if (!samples::sceneFilesSupported()) GTEST_SKIP() << "built without assimp";
  const std::string model = writeFile("logrid_moving_wall.obj", wallAndCrates());
  const std::string motion = writeFile("logrid_moving_wall.json", R"({"objects": [
    {"mesh": 0, "path": [[0, 0, 0], [3, 0, 0]], "speed": 1}]})");
  samples::Scene s = samples::loadSceneFile(model);
  samples::animateMeshes(s, motion);
  ASSERT_EQ(s.motion.movers.size(), 1u);
  s.path = samples::CameraPath({{{0, 6, 45}, {0, 3, 0}, 0}, {{8, 6, 40}, {0, 3, 0}, 12}});
  const bvh::BuildArgs args = samples::defaultBuildArgs(s);
  LoadedScene scene;
  scene.prepared = samples::prepareScene(std::move(s), args);
  scene.renderer = std::make_unique<gl::MeshRenderer>(scene.prepared.mesh);
  for (Method m : {Method::LogZfar, Method::LogState}) {
    for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
      OracleCase c;
      c.scene = {model, 1, Offset::None, 0, 0};
      c.method = choice(m);
      c.reader = "cpu";
      c.view.convention = conv;
      c.frames = 12;
      c.hierarchy = "refit";
      c.time_step = 1.0;
      c.expect_occluded = true;  // only the wall hides anything
      c.name = std::string("moving wall refit ") + toString(m) + " cpu " + toString(conv);
      const WalkTotals t = checkCase(c, scene);
      EXPECT_EQ(t.cpu_moved, t.frames) << c.name << ": the wall is drawn every frame";
      EXPECT_LT(t.drawn, 9 * t.frames) << c.name << ": nothing was culled";
    }
  }
}

// The reader for an application that manages its own GL state (readpixels-managed,
// GlStatePolicy::ApplicationManaged) leaves what logrid's passes set; a multisampled
// framebuffer's depth resolve leaves the scissor test on around its last rectangle. The
// ternary-objects tree's statistics pass reads depth after the frame, so the next frame's
// clears and draws were scissored, the application's part of the contract (set what it
// draws with) unmet by Framebuffer::bind(): hundreds of misses in 25 frames. The widened
// soak run found it (vfc missed objects in the same set-up).
TEST(ManagedReaderWithMovers, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  for (Method m : {Method::Hwq, Method::Vfc}) {
    OracleCase c;
    c.scene = movingKey("forest");
    c.method = choice(m);
    c.reader = "readpixels-managed";
    c.frames = 6;
    c.hierarchy = "ternary-objects";
    c.expect_occluded = false;
    c.adjust = [](RunConfig& config) { config.view.samples = 4; };
    c.name = std::string("forest movers ternary-objects ") + toString(m) +
             " readpixels-managed 4 samples";
    checkCase(c);
  }
}

// The same reader with methods that read depth during the frame: each read's resolve
// leaves its framebuffer, program and vertex array bound, and the runner drew the next
// batch with them until it set its own before each batch (the driver crashed on the
// resolve's vertex array, which has no element buffer). The widened soak run found it.
TEST(ManagedReaderMultisampled, EveryBatchIsDrawnWithTheApplicationsState) {
  LOGRID_REQUIRE_GL();
  for (Method m : {Method::LogState, Method::Bog}) {
    OracleCase c;
    c.scene = sceneKey("forest");
    c.method = choice(m);
    c.reader = "readpixels-managed";
    c.adjust = [](RunConfig& config) { config.view.samples = 4; };
    c.name = std::string("forest ") + toString(m) + " readpixels-managed 4 samples";
    checkCase(c);
  }
}

// The motion of the walks above (the same scenes, frames and times) has movers leaving
// the scene bounds, passing through each other, and stopping and starting again.
TEST(MotionScenario, WalksContainEveryKindOfMotion) {
  LOGRID_REQUIRE_GL();
  for (const char* name : {"forest", "city"}) {
    LoadedScene& scene = loadScene(movingKey(name));
    const PreparedScene& p = scene.prepared;
    const samples::Motion& motion = p.motion;
    std::size_t outside = 0, crossings = 0, restarts = 0;
    for (double step : {0.0, kSmallStep}) {
      std::vector<std::vector<Aabb>> boxes(kMotionFrames);
      for (std::size_t f = 0; f < kMotionFrames; ++f) {
        const double time = step > 0 ? p.path.keys().front().time + double(f) * step
                                     : p.path.frameTime(f, kMotionFrames);
        for (std::size_t i = 0; i < motion.movers.size(); ++i) {
          boxes[f].push_back(motion.boxAt(i, time));
        }
      }
      for (std::size_t i = 0; i < motion.movers.size(); ++i) {
        bool out = false, stood = false, restarted = false;
        for (std::size_t f = 0; f < kMotionFrames; ++f) {
          const Aabb& b = boxes[f][i];
          out |= b.max.x < p.bounds.min.x || b.min.x > p.bounds.max.x || b.max.z < p.bounds.min.z ||
                 b.min.z > p.bounds.max.z;
          const bool same = f > 0 && b.min.x == boxes[f - 1][i].min.x &&
                            b.min.z == boxes[f - 1][i].min.z && b.max.x == boxes[f - 1][i].max.x;
          if (f > 0 && !same && stood) restarted = true;
          stood |= same;
          for (std::size_t j = i + 1; j < motion.movers.size(); ++j) {
            const Aabb& o = boxes[f][j];
            crossings += b.min.x <= o.max.x && o.min.x <= b.max.x && b.min.y <= o.max.y &&
                         o.min.y <= b.max.y && b.min.z <= o.max.z && o.min.z <= b.max.z;
          }
        }
        outside += out;
        restarts += restarted;
      }
      std::printf(
          "[ scenario ] %s step %.0f: so far %zu movers leave the bounds, %zu "
          "overlapping pairs, %zu stop and start again\n",
          name, step, outside, crossings, restarts);
    }
    EXPECT_GT(outside, 0u) << name << ": no mover leaves the scene bounds";
    EXPECT_GT(crossings, 0u) << name << ": no movers pass through each other";
    EXPECT_GT(restarts, 0u) << name << ": no mover stops and starts again";
  }
}

}  // namespace
}  // namespace logrid::oracle
