// The `auto` method (docs/AUTO.md) on real GL frames, every frame checked against the
// object-ID oracle: the forest, the city, the office, the sparse forest (scale 0.02,
// where nothing is hidden and testing switches itself off) and the office read back
// from an OBJ file, in both depth conventions (24-bit standard, 32-bit float reversed),
// over frames close together (so that coherence and the probes of neighbouring settings
// are exercised) with two depth sources (readpixels, the PBO ring). Whatever auto
// chooses per node and per frame, no visible object may be missed.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

constexpr double kSparseForestScale = 0.02;
constexpr std::size_t kFrames = 20;  // past two probe periods (AutoPolicy::kProbePeriod)

// "forest", "city", "office", "office-file" (the office read back through the model
// loader) or "sparse-forest" (the forest at kSparseForestScale).
SceneKey autoKey(const std::string& name) {
  if (name != "sparse-forest") return sceneKey(name);
  SceneKey key = sceneKey("forest");
  key.scale = kSparseForestScale;
  return key;
}

struct AutoCase {
  std::string scene;
  DepthConvention convention;
  std::string reader;
};

class AutoOracle : public testing::TestWithParam<AutoCase> {};

TEST_P(AutoOracle, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const AutoCase& c = GetParam();
  const SceneKey key = autoKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  v.convention = c.convention;
  v.format = c.convention == DepthConvention::Standard ? DepthFormat::D24 : DepthFormat::D32F;
  RunConfig config = makeConfig(scene.prepared, Method::Auto, c.reader, v, kFrames);
  config.time_step = 2.0;  // a couple of metres a frame: coherent frames
  WalkTotals t;
  FrameRunner runner(scene.prepared, *scene.renderer, config);
  std::set<std::uint32_t> lookaheads;
  std::uint64_t probes = 0, untested = 0;
  for (std::size_t f = 0; f < config.frames; ++f) {
    const FrameRecord r = runner.renderFrame(f);
    ++t.frames;
    ASSERT_GE(r.visible, 0) << "the oracle did not run for frame " << f;
    EXPECT_EQ(r.missed, 0) << "auto (" << toString(r.stats.setting.method) << ", K "
                           << r.stats.setting.lookahead
                           << (r.stats.setting.temporal_coherence ? ", coherence" : "")
                           << ") missed " << r.missed << " of " << r.visible
                           << " visible objects in frame " << f
                           << "; reproduce: " << reproducer(key, config)
                           << " (with RunConfig::time_step 2)";
    EXPECT_EQ(r.missed_artifacts, 0) << "frame " << f;
    EXPECT_TRUE(r.stats.setting.method == Method::LogState ||
                r.stats.setting.method == Method::LogZfar);
    t.visible += std::uint64_t(r.visible);
    t.missed += std::uint64_t(std::max<std::int64_t>(r.missed, 0));
    t.drawn += r.stats.objects_drawn;
    t.occluded += r.stats.boxes_occluded;
    t.tested += r.stats.boxes_tested;
    t.ms += r.ms;
    lookaheads.insert(r.stats.setting.lookahead);
    probes += r.stats.setting.probe;
    untested += r.stats.boxes_untested;
  }
  std::printf("[ oracle ] auto %s %s %s: %s; %llu untested, %llu probes, %zu lookaheads\n",
              c.scene.c_str(), toString(c.convention), c.reader.c_str(), summary(t).c_str(),
              (unsigned long long)untested, (unsigned long long)probes, lookaheads.size());
  EXPECT_EQ(t.missed, 0u);
  EXPECT_GT(t.visible, 0u);
  // The frames ran the probes: more than one setting was tried.
  EXPECT_GT(probes, 0u);
  EXPECT_GT(t.tested + untested, 0u);
}

std::vector<AutoCase> autoCases() {
  std::vector<AutoCase> out;
  for (const char* scene : {"forest", "sparse-forest", "city", "office", "office-file"}) {
    for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
      out.push_back({scene, conv, "readpixels"});
    }
  }
  // The asynchronous ring: batches read with one wait.
  out.push_back({"forest", DepthConvention::Reversed, "pbo"});
  out.push_back({"city", DepthConvention::Standard, "pbo"});
  return out;
}

std::string autoName(const testing::TestParamInfo<AutoCase>& p) {
  return sanitize(p.param.scene + "_" + toString(p.param.convention) + "_" + p.param.reader);
}

INSTANTIATE_TEST_SUITE_P(Scenes, AutoOracle, testing::ValuesIn(autoCases()), autoName);

}  // namespace
}  // namespace logrid::oracle
