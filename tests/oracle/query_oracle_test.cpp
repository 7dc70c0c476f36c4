// The hardware-occlusion-query methods (hwq, chc, stat, nohc, log+hwq with each schedule)
// on real GL frames, every frame checked against the object-ID oracle: the forest, the
// city and a scene read from a model file, in both depth conventions (24-bit standard and
// 32-bit float reversed), over frames close together (the schedules' temporal coherence
// at work) and frames far apart (what they remember turns stale). Also: boxes queried
// both as faces and as rectangles, and GL_ANY_SAMPLES_PASSED_CONSERVATIVE queries.
#include <gtest/gtest.h>

#include <sstream>

#include "logrid/error.hpp"
#include "model_files.hpp"
#include "oracle_harness.hpp"
#include "scene/loader.hpp"

namespace logrid::oracle {
namespace {

// A village for the file scene: a ground slab and a 9 x 9 grid of box houses of varying
// heights, one OBJ object each, their faces split into 6 x 6 quads (432 triangles a house,
// so that querying one can pay against drawing it), seen from the loader's default orbit
// (above, outside).
std::string villageObj() {
  std::ostringstream obj;
  int vertices = 0;
  auto box = [&](const std::string& name, const double lo[3], const double hi[3], int split) {
    obj << "o " << name << "\n";
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        const int first = vertices;
        for (int i = 0; i <= split; ++i) {
          for (int k = 0; k <= split; ++k) {
            double p[3];
            p[axis] = side ? hi[axis] : lo[axis];
            p[u] = lo[u] + (hi[u] - lo[u]) * i / split;
            p[w] = lo[w] + (hi[w] - lo[w]) * k / split;
            obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
            ++vertices;
          }
        }
        for (int i = 0; i < split; ++i) {
          for (int k = 0; k < split; ++k) {
            const int a = first + i * (split + 1) + k + 1, b = a + 1, c = a + split + 1, d = c + 1;
            obj << "f " << a << " " << c << " " << b << "\nf " << b << " " << c << " " << d << "\n";
          }
        }
      }
    }
  };
  const double ground_lo[3] = {-60, -1, -60}, ground_hi[3] = {60, 0, 60};
  box("ground", ground_lo, ground_hi, 1);
  for (int i = 0; i < 9; ++i) {
    for (int k = 0; k < 9; ++k) {
      const double x = -48 + 12.0 * i, z = -48 + 12.0 * k;
      const double lo[3] = {x - 4, 0, z - 4};
      const double hi[3] = {x + 4, 4 + double((i * 7 + k * 3) % 5) * 3, z + 4};
      box("house_" + std::to_string(i) + "_" + std::to_string(k), lo, hi, 6);
    }
  }
  return obj.str();
}

LoadedScene& fileScene(std::string& path) {
  static std::unique_ptr<LoadedScene> scene;
  static std::string file;
  if (!scene) {
    file = test::tempFilePath("query_oracle", "village.obj");
    test::writeBytes(file, villageObj());
    samples::Scene s = samples::loadSceneFile(file);
    const bvh::BuildArgs args = samples::defaultBuildArgs(s);
    scene = std::make_unique<LoadedScene>();
    scene->prepared = samples::prepareScene(std::move(s), args);
    scene->renderer = std::make_unique<gl::MeshRenderer>(scene->prepared.mesh);
  }
  path = file;
  return *scene;
}

// Fixed parameters for nohc (the calibration has a test of its own, gl_test): cheap
// queries and dear triangles, so that nohc queries a good share of the boxes.
HardwareParameters testHardware() {
  HardwareParameters p;
  p.render_setup = 2e-6;
  p.render_triangle = 5e-8;
  p.render_fragment = 5e-9;
  p.query_setup = 1e-5;
  p.query_fragment = 5e-9;
  p.query_latency = 1e-4;
  p.query_overhead = 5e-6;
  p.poll = 1e-6;
  return p;
}

struct QueryCase {
  std::string scene;  // forest, city or file
  Method method;
  QuerySchedule schedule;  // log+hwq's
  DepthConvention convention;
  bool coherent;  // frames close together, else spread over the whole path
  QueryShape shape = QueryShape::Box;
  bool any_samples = false;
};

class QueryOracle : public testing::TestWithParam<QueryCase> {};

TEST_P(QueryOracle, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const QueryCase& c = GetParam();
  SceneKey key;
  LoadedScene* scene = nullptr;
  if (c.scene == "file") {
    std::string path;
    scene = &fileScene(path);
    key = {path, 1, Offset::None, 0};
  } else {
    key = {c.scene, c.scene == "city" ? kCityScale : kForestScale, Offset::None, 0};
    scene = &loadScene(key);
  }
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  v.convention = c.convention;
  v.format = c.convention == DepthConvention::Standard ? DepthFormat::D24 : DepthFormat::D32F;
  RunConfig config = makeConfig(scene->prepared, c.method, "readpixels", v, 8);
  config.culler.queries.schedule = c.schedule;
  config.culler.queries.shape = c.shape;
  config.culler.queries.hardware = testHardware();
  config.culler.queries.stat_base_frames = 4;  // stale statistics within the walk
  config.any_samples_passed = c.any_samples;
  // Close frames: a few metres of walking (the file scene's orbit is some 400 m round).
  if (c.coherent) config.time_step = c.scene == "file" ? 6.0 : 1.5;
  const WalkTotals t = checkedWalk(key, *scene, config);
  std::printf("[ oracle ] %s %s/%s %s %s: %s\n", c.scene.c_str(), toString(c.method),
              toString(c.schedule), toString(c.convention), c.coherent ? "close" : "spread",
              summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config) << " --query-schedule " << toString(c.schedule)
                          << (c.coherent ? " (with RunConfig::time_step)" : "");
  EXPECT_GT(t.visible, 0u);
  EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
}

std::vector<QueryCase> queryCases() {
  std::vector<QueryCase> out;
  const Method methods[] = {Method::Hwq, Method::Chc, Method::Stat, Method::Nohc};
  for (const char* scene : {"forest", "city", "file"}) {
    for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
      for (Method m : methods) {
        const QuerySchedule schedule = *methodInfo(m).schedule;
        out.push_back({scene, m, schedule, conv, true});
        out.push_back({scene, Method::LogHwq, schedule, conv, conv == DepthConvention::Reversed});
      }
      out.push_back({scene, Method::Chc, QuerySchedule::Chc, conv, false});
      out.push_back({scene, Method::Stat, QuerySchedule::Stat, conv, false});
    }
    out.push_back({scene, Method::Chc, QuerySchedule::Chc, DepthConvention::Standard, true,
                   QueryShape::Rect});
    out.push_back({scene, Method::Stat, QuerySchedule::Stat, DepthConvention::Reversed, true,
                   QueryShape::Box, true});
  }
  return out;
}

std::string queryName(const testing::TestParamInfo<QueryCase>& p) {
  const QueryCase& c = p.param;
  return sanitize(c.scene + "_" + toString(c.method) + "_" + toString(c.schedule) + "_" +
                  toString(c.convention) + (c.coherent ? "_close" : "_spread") +
                  (c.shape == QueryShape::Rect ? "_rect" : "") + (c.any_samples ? "_any" : ""));
}

INSTANTIATE_TEST_SUITE_P(Methods, QueryOracle, testing::ValuesIn(queryCases()), queryName);

// log+hwq names its schedule as a suffix (what bench's --methods lists); other methods,
// repeated or unknown schedules are refused.
TEST(QueryMethodNames, LogHwqTakesItsScheduleAsASuffix) {
  const auto chc = samples::parseMethodChoice("log+hwq:chc");
  ASSERT_TRUE(chc);
  EXPECT_EQ(chc->method, Method::LogHwq);
  ASSERT_TRUE(chc->schedule);
  EXPECT_EQ(*chc->schedule, QuerySchedule::Chc);
  EXPECT_EQ(chc->name(), "log+hwq:chc");
  const auto plain = samples::parseMethodChoice("log+hwq");
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->schedule);
  for (const char* bad :
       {"log+hwq:log+hwq", "log+hwq:log-state", "log+hwq:chc:stat", "hwq:chc", "log-state:stat",
        "oracle:chc", "log+hwq:bogus", "log-state:99999999999999999999", "log-state:4294967296"}) {
    EXPECT_FALSE(samples::parseMethodChoice(bad)) << bad;
  }
}

}  // namespace
}  // namespace logrid::oracle
