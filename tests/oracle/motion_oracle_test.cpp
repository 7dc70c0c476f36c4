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
//   MotionScenario  the walks above contain what they claim: movers that leave the
//                   scene bounds, pass through each other, and stop and start again.
#include <gtest/gtest.h>

#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

constexpr std::uint32_t kMovers = 60;
constexpr std::size_t kMotionFrames = 10;
constexpr double kSmallStep = 3.0;  // seconds between frames for the small-motion walks

SceneKey movingKey(const std::string& name) {
  return {name, name == "city" ? kCityScale : kForestScale, Offset::None, 0, kMovers};
}

struct MovingCase {
  std::string scene;
  Method method;
  std::string hierarchy;
  DepthConvention convention;
};

class MovingWalk : public testing::TestWithParam<MovingCase> {};

TEST_P(MovingWalk, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const MovingCase& c = GetParam();
  const SceneKey key = movingKey(c.scene);
  LoadedScene& scene = loadScene(key);
  ASSERT_EQ(scene.prepared.motion.movers.size(), kMovers);
  View v;
  v.convention = c.convention;
  RunConfig config = makeConfig(scene.prepared, c.method, "readpixels", v, kMotionFrames);
  config.hierarchy = c.hierarchy;
  config.time_step = c.convention == DepthConvention::Reversed ? kSmallStep : 0.0;
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s %s %s: %s\n", c.scene.c_str(), c.hierarchy.c_str(), toString(c.method),
              summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  EXPECT_GT(t.visible, 0u);
  // Not vacuous: boxes are found occluded. The small-motion walks cover only the first
  // 30 m of the path, where the trees of the test city's few hundred objects (cells of
  // a dozen objects, drawn together) can be visible throughout.
  if (config.time_step == 0 || (c.hierarchy != "ternary" && c.hierarchy != "binary")) {
    EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
  }
}

std::vector<MovingCase> movingCases() {
  std::vector<MovingCase> out;
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar}) {
      for (const bvh::MotionInfo& h : bvh::motionTable()) {
        for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
          out.push_back({scene, m, h.name, conv});
        }
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Movers, MovingWalk, testing::ValuesIn(movingCases()),
                         [](const testing::TestParamInfo<MovingCase>& p) {
                           const MovingCase& c = p.param;
                           return sanitize(c.scene + "_" + c.hierarchy + "_" + toString(c.method) +
                                           "_" + toString(c.convention));
                         });

struct TraversalCase {
  std::string scene;
  Method method;
  std::string reader;
  std::uint32_t lookahead;
  bool coherence;
  DepthConvention convention = DepthConvention::Standard;
};

class MovingTraversal : public testing::TestWithParam<TraversalCase> {};

TEST_P(MovingTraversal, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const TraversalCase& c = GetParam();
  const SceneKey key = movingKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  v.format = DepthFormat::D24;
  v.convention = c.convention;
  RunConfig config = makeConfig(scene.prepared, c.method, c.reader, v, kMotionFrames);
  config.hierarchy = "ternary";
  // Small motion in the forest; frames over the whole path in the city, whose first
  // 30 m show too little to occlude (see MovingWalk).
  config.time_step = c.scene == "forest" ? kSmallStep : 0.0;
  config.culler.lookahead = c.lookahead;
  config.culler.detect_colliding = true;
  config.culler.temporal_coherence = c.coherence;
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s ternary %s %s %s K=%u tc=%d: %s\n", c.scene.c_str(),
              toString(c.method), c.reader.c_str(), toString(c.convention), c.lookahead,
              int(c.coherence), summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  EXPECT_GT(t.occluded, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Ternary, MovingTraversal,
    testing::Values(TraversalCase{"forest", Method::LogState, "pbo", kUnlimitedLookahead, true},
                    TraversalCase{"forest", Method::LogZfar, "query", 16, false},
                    TraversalCase{"city", Method::LogState, "query", kUnlimitedLookahead, true},
                    TraversalCase{"city", Method::LogZfar, "software", 16, true},
                    // The hardware-query method: one occlusion query per tested box.
                    TraversalCase{"forest", Method::Pq, "query", 16, false,
                                  DepthConvention::Reversed},
                    TraversalCase{"city", Method::Pq, "query", kUnlimitedLookahead, true,
                                  DepthConvention::Standard}),
    [](const testing::TestParamInfo<TraversalCase>& p) {
      const TraversalCase& c = p.param;
      return sanitize(c.scene + "_" + toString(c.method) + "_" + c.reader +
                      (c.coherence ? "_tc" : "") + "_" + toString(c.convention));
    });

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
