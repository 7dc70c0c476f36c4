// Multisampled framebuffers (label oracle): the forest and the city rendered with 4
// samples per pixel, culled with log-state, log-zfar and pq through the readpixels, pbo
// and query readers in both conventions, and checked against the object-ID pass per
// sample: an object is visible if any sample of it survives in the ID buffer
// (Framebuffer::readObjectIds reads every sample). Zero misses, and boxes are culled
// (the farthest-sample resolve still lets occlusion work).
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

struct MultisampleCase {
  Method method;
  std::string reader;
  DepthConvention convention;
  DepthFormat format;
};

std::string caseName(const testing::TestParamInfo<MultisampleCase>& info) {
  const MultisampleCase& c = info.param;
  std::ostringstream out;
  out << toString(c.method) << "_" << c.reader << "_" << toString(c.convention) << "_"
      << formatName(c.format);
  return sanitize(out.str());
}

class MultisampleOracleTest : public testing::TestWithParam<MultisampleCase> {};

constexpr std::uint32_t kSamples = 4;

TEST_P(MultisampleOracleTest, NoVisibleObjectMissed) {
  LOGRID_REQUIRE_GL();
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (max_samples < GLint(kSamples)) GTEST_SKIP() << "GL_MAX_SAMPLES is " << max_samples;
  const MultisampleCase c = GetParam();
  for (const char* name : {"forest", "city"}) {
    const SceneKey key{name, name == std::string("city") ? kCityScale : kForestScale};
    LoadedScene& scene = loadScene(key);
    View view;
    view.convention = c.convention;
    view.format = c.format;
    RunConfig config = makeConfig(scene.prepared, c.method, c.reader, view, 4);
    config.view.samples = kSamples;
    const WalkTotals t = checkedWalk(key, scene, config);
    std::printf("%s %s: %s\n", key.id().c_str(), caseName({c, 0}).c_str(), summary(t).c_str());
    EXPECT_GT(t.visible, 0u) << key.id();
    EXPECT_GT(t.occluded, 0u) << key.id() << ": nothing was culled";
  }
}

std::vector<MultisampleCase> cases() {
  std::vector<MultisampleCase> out;
  for (Method m : {Method::LogState, Method::LogZfar, Method::Pq}) {
    for (const char* r : {"readpixels", "pbo", "query", "reduce"}) {
      out.push_back({m, r, DepthConvention::Standard, DepthFormat::D24});
      out.push_back({m, r, DepthConvention::Reversed, DepthFormat::D32F});
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Methods, MultisampleOracleTest, testing::ValuesIn(cases()), caseName);

}  // namespace
}  // namespace logrid::oracle
