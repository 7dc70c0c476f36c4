// Walkthroughs of the procedural forest and city on real GL frames, every frame checked
// against the object-ID oracle: a conservative method never misses a visible object.
//
//   WalkMatrix      log-state and log-zfar over both scenes, both depth conventions,
//                   24-bit and 32F depth, two resolutions (one odd) and two tile sizes.
//   Readers         log-state, log-zfar, bog, hzb and pq with every depth source
//                   (samples/cli/readers.cpp) at one configuration.
//   CpuBuffer       log-state and log-zfar with the CPU occlusion buffer over both scenes:
//                   each resolution, both conventions, 24-bit and 32F depth, full meshes
//                   and occluder models, with and without a worker thread; and the
//                   city's models over 30 frames of a larger city.
//   Lookahead       log-state and log-zfar with lookahead K in {1, 4, 16, all}, with and
//                   without temporal coherence, over both scenes.
//   Reduction       per scene, LOG draws clearly fewer objects than view-frustum culling
//                   along the same frames (and never fewer than the oracle's visible set).
#include <gtest/gtest.h>

#include "logrid/error.hpp"
#include "oracle_harness.hpp"

namespace logrid::oracle {
namespace {

constexpr std::size_t kMatrixFrames = 4;

SceneKey sceneKey(const std::string& name) {
  return {name, name == "city" ? kCityScale : kForestScale, Offset::None, 0};
}

// ---------------------------------------------------------------------------
// A. The walkthrough matrix.
// ---------------------------------------------------------------------------

struct MatrixCase {
  std::string scene;
  Method method;
  DepthConvention convention;
  DepthFormat format;
  std::uint32_t width;
  std::uint32_t height;
  std::uint32_t tile;
};

class WalkMatrix : public testing::TestWithParam<MatrixCase> {};

TEST_P(WalkMatrix, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const MatrixCase& c = GetParam();
  const SceneKey key = sceneKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = c.width;
  v.height = c.height;
  v.tile = c.tile;
  v.convention = c.convention;
  v.format = c.format;
  const RunConfig config = makeConfig(scene.prepared, c.method, "readpixels", v, kMatrixFrames);
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s\n", summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  // The check is not vacuous: the walk sees objects and the grid culls some.
  EXPECT_GT(t.visible, 0u);
  EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
}

std::vector<MatrixCase> matrixCases() {
  std::vector<MatrixCase> out;
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar}) {
      for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
        for (DepthFormat f : {DepthFormat::D24, DepthFormat::D32F}) {
          for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{160, 120}, {321, 239}}) {
            for (std::uint32_t tile : {8u, 32u}) out.push_back({scene, m, conv, f, w, h, tile});
          }
        }
      }
    }
  }
  return out;
}

std::string matrixName(const testing::TestParamInfo<MatrixCase>& p) {
  const MatrixCase& c = p.param;
  return sanitize(c.scene + "_" + toString(c.method) + "_" + toString(c.convention) + "_d" +
                  formatName(c.format) + "_" + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + "_t" + std::to_string(c.tile));
}

INSTANTIATE_TEST_SUITE_P(Scenes, WalkMatrix, testing::ValuesIn(matrixCases()), matrixName);

// ---------------------------------------------------------------------------
// Every method with every depth source, at one configuration.
// ---------------------------------------------------------------------------

struct ReaderCase {
  std::string scene;
  Method method;
  std::string reader;
};

class Readers : public testing::TestWithParam<ReaderCase> {};

TEST_P(Readers, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const ReaderCase& c = GetParam();
  const SceneKey key = sceneKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  // D24 standard: the software source must agree with a quantised GL buffer too.
  v.format = DepthFormat::D24;
  const RunConfig config = makeConfig(scene.prepared, c.method, c.reader, v, kMatrixFrames);
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s\n", summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  EXPECT_GT(t.visible, 0u);
  EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
}

std::vector<ReaderCase> readerCases() {
  std::vector<ReaderCase> out;
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar, Method::Bog, Method::Hzb, Method::Pq}) {
      for (const samples::ReaderInfo& r : samples::readerTable()) {
        if (methodInfo(m).needs.depth_values && !r.reads_depth) continue;  // refused: see below
        // Reads exactly what readpixels reads; only its GL-state queries differ.
        if (r.name == std::string("readpixels-per-read")) continue;
        out.push_back({scene, m, r.name});
      }
    }
  }
  return out;
}

std::string readerName(const testing::TestParamInfo<ReaderCase>& p) {
  return sanitize(p.param.scene + "_" + toString(p.param.method) + "_" + p.param.reader);
}

INSTANTIATE_TEST_SUITE_P(AllSources, Readers, testing::ValuesIn(readerCases()), readerName);

// HZB needs depth values; a query source cannot give them. That is refused up front,
// with a message that says what to use instead, not answered wrongly.
TEST(ReadersRefusal, HzbWithQueriesIsRefusedClearly) {
  LOGRID_REQUIRE_GL();
  const SceneKey key = sceneKey("forest");
  LoadedScene& scene = loadScene(key);
  const RunConfig config = makeConfig(scene.prepared, Method::Hzb, "query", View{}, 1);
  try {
    FrameRunner runner(scene.prepared, *scene.renderer, config);
    FAIL() << "hzb with the query reader was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("readpixels"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------
// The CPU occlusion buffer (`cpu` reader) across what it must agree with GL on: both
// conventions, 24-bit and 32F depth, each resolution, full meshes and occluder models,
// with and without a worker thread.
// ---------------------------------------------------------------------------

struct CpuCase {
  std::string scene;
  Method method;
  DepthConvention convention;
  DepthFormat format;
  cpu::Resolution resolution;
  samples::OccluderChoice occluders;
  std::uint32_t threads;
  cpu::Representation representation;
};

class CpuBuffer : public testing::TestWithParam<CpuCase> {};

TEST_P(CpuBuffer, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const CpuCase& c = GetParam();
  const SceneKey key = sceneKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  v.convention = c.convention;
  v.format = c.format;
  RunConfig config = makeConfig(scene.prepared, c.method, "cpu", v, kMatrixFrames);
  config.cpu.resolution = c.resolution;
  config.cpu.occluders = c.occluders;
  config.cpu.threads = c.threads;
  config.cpu.representation = c.representation;
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s\n", summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  EXPECT_GT(t.visible, 0u);
  EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
}

std::vector<CpuCase> cpuCases() {
  using samples::OccluderChoice;
  // Each resolution meets both conventions and both formats over the two scenes.
  struct Variant {
    DepthConvention convention;
    DepthFormat format;
    cpu::Resolution resolution;
    OccluderChoice occluders;
    std::uint32_t threads;
    cpu::Representation representation = cpu::Representation::PerPixel;
  };
  // The masked representation: full resolution with models and a worker, half with meshes.
  const Variant masked_variants[] = {
      {DepthConvention::Standard, DepthFormat::D24, cpu::Resolution::Full, OccluderChoice::Model, 1,
       cpu::Representation::Masked},
      {DepthConvention::Reversed, DepthFormat::D32F, cpu::Resolution::Half, OccluderChoice::Mesh, 0,
       cpu::Representation::Masked},
  };
  const Variant variants[] = {
      {DepthConvention::Standard, DepthFormat::D32F, cpu::Resolution::Full, OccluderChoice::Model,
       1},
      {DepthConvention::Reversed, DepthFormat::D24, cpu::Resolution::Full, OccluderChoice::Mesh, 0},
      {DepthConvention::Reversed, DepthFormat::D32F, cpu::Resolution::Half, OccluderChoice::Mesh,
       0},
      {DepthConvention::Standard, DepthFormat::D24, cpu::Resolution::Half, OccluderChoice::Model,
       0},
      {DepthConvention::Standard, DepthFormat::D32F, cpu::Resolution::Quarter, OccluderChoice::Mesh,
       0},
      {DepthConvention::Reversed, DepthFormat::D24, cpu::Resolution::Quarter, OccluderChoice::Model,
       1},
  };
  std::vector<CpuCase> out;
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar}) {
      for (const Variant& v : variants) {
        out.push_back({scene, m, v.convention, v.format, v.resolution, v.occluders, v.threads,
                       v.representation});
      }
      for (const Variant& v : masked_variants) {
        out.push_back({scene, m, v.convention, v.format, v.resolution, v.occluders, v.threads,
                       v.representation});
      }
    }
  }
  return out;
}

std::string cpuName(const testing::TestParamInfo<CpuCase>& p) {
  const CpuCase& c = p.param;
  return sanitize(c.scene + "_" + toString(c.method) + "_" + toString(c.convention) + "_d" +
                  formatName(c.format) + "_" + cpu::toString(c.resolution) + "_" +
                  samples::toString(c.occluders) + "_t" + std::to_string(c.threads) +
                  (c.representation == cpu::Representation::Masked ? "_masked" : ""));
}

INSTANTIATE_TEST_SUITE_P(Variants, CpuBuffer, testing::ValuesIn(cpuCases()), cpuName);

// The city's occluder models stand for whole buildings while each chunk holds a part of
// one (samples/scene/scene.hpp, OccluderSolid). Methods with occlusion-state semantics
// take any drawn pixel as hiding what they test next, so they get the models clipped to
// each chunk's box; unclipped, log-state missed 9 visible objects on these 30 frames.
TEST(CpuBufferCityModels, StateSemanticsGetModelsWithinTheirObjects) {
  LOGRID_REQUIRE_GL();
  const SceneKey key{"city", 0.03, Offset::None, 0};
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  for (Method m : {Method::LogState, Method::LogZfar}) {
    RunConfig config = makeConfig(scene.prepared, m, "cpu", v, 30);
    config.cpu.occluders = samples::OccluderChoice::Model;
    const WalkTotals t = checkedWalk(key, scene, config);
    std::printf("[ oracle ] %s: %s\n", toString(m), summary(t).c_str());
    EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
    EXPECT_GT(t.occluded, 0u);
  }
}

// ---------------------------------------------------------------------------
// Lookahead and temporal coherence: every K, with and without coherence, is exact.
// ---------------------------------------------------------------------------

struct LookaheadCase {
  std::string scene;
  Method method;
  std::uint32_t lookahead;
  bool coherence;
  std::string reader;
  DepthConvention convention;
};

class Lookahead : public testing::TestWithParam<LookaheadCase> {};

TEST_P(Lookahead, NoVisibleObjectIsMissed) {
  LOGRID_REQUIRE_GL();
  const LookaheadCase& c = GetParam();
  const SceneKey key = sceneKey(c.scene);
  LoadedScene& scene = loadScene(key);
  View v;
  v.width = 200;
  v.height = 150;
  v.tile = 16;
  v.convention = c.convention;
  RunConfig config = makeConfig(scene.prepared, c.method, c.reader, v, 6);
  config.culler.lookahead = c.lookahead;
  config.culler.temporal_coherence = c.coherence;
  const WalkTotals t = checkedWalk(key, scene, config);
  std::printf("[ oracle ] %s\n", summary(t).c_str());
  EXPECT_EQ(t.missed, 0u) << reproducer(key, config);
  EXPECT_GT(t.visible, 0u);
  EXPECT_GT(t.occluded, 0u) << "no box was ever found occluded; the walk tests nothing";
}

std::vector<LookaheadCase> lookaheadCases() {
  std::vector<LookaheadCase> out;
  // Each K with a different reader, so that every reader meets batches of many boxes.
  const std::pair<std::uint32_t, const char*> ks[] = {
      {1, "readpixels"}, {4, "pbo"}, {16, "reduce"}, {kUnlimitedLookahead, "readpixels"}};
  for (const char* scene : {"forest", "city"}) {
    for (Method m : {Method::LogState, Method::LogZfar}) {
      for (const auto& [k, reader] : ks) {
        for (bool tc : {false, true}) {
          out.push_back({scene, m, k, tc, reader,
                         tc ? DepthConvention::Reversed : DepthConvention::Standard});
        }
      }
    }
    out.push_back(
        {scene, Method::LogState, kUnlimitedLookahead, true, "query", DepthConvention::Standard});
  }
  return out;
}

std::string lookaheadName(const testing::TestParamInfo<LookaheadCase>& p) {
  const LookaheadCase& c = p.param;
  return sanitize(
      c.scene + "_" + toString(c.method) + "_K" +
      (c.lookahead == kUnlimitedLookahead ? std::string("all") : std::to_string(c.lookahead)) +
      (c.coherence ? "_tc_" : "_") + c.reader + "_" + toString(c.convention));
}

INSTANTIATE_TEST_SUITE_P(Traversal, Lookahead, testing::ValuesIn(lookaheadCases()), lookaheadName);

// ---------------------------------------------------------------------------
// The point of it all: fewer objects drawn than view-frustum culling.
// ---------------------------------------------------------------------------

// Measured on llvmpipe, 8 frames at 160x120, tile 32, 32F standard (objects drawn, summed
// over the frames; visible = objects in the ID buffers):
//   forest 0.1:  vfc 854, log-state 602 (0.70), log-zfar 404 (0.47), visible 260
//   city 0.01:   vfc 660, log-state 268 (0.41), log-zfar 244 (0.37), visible 177
// The bounds sit between the measured ratio and 1, so that a grid that stops culling
// (ratio 1) fails while a small change of scene or driver does not.
struct ReductionCase {
  std::string scene;
  Method method;
  double max_ratio;  // drawn / vfc drawn must stay below this
};

class Reduction : public testing::TestWithParam<ReductionCase> {};

TEST_P(Reduction, DrawsFewerObjectsThanFrustumCulling) {
  LOGRID_REQUIRE_GL();
  const ReductionCase& c = GetParam();
  const SceneKey key = sceneKey(c.scene);
  LoadedScene& scene = loadScene(key);
  const View v;
  const std::size_t frames = 8;
  const WalkTotals vfc =
      checkedWalk(key, scene, makeConfig(scene.prepared, Method::Vfc, "readpixels", v, frames));
  const RunConfig config = makeConfig(scene.prepared, c.method, "readpixels", v, frames);
  const WalkTotals log = checkedWalk(key, scene, config);
  const double ratio = vfc.drawn ? double(log.drawn) / double(vfc.drawn) : 1.0;
  std::printf("[ oracle ] %s %s: drawn %llu, vfc %llu (ratio %.3f, bound %.2f), visible %llu\n",
              c.scene.c_str(), toString(c.method), (unsigned long long)log.drawn,
              (unsigned long long)vfc.drawn, ratio, c.max_ratio, (unsigned long long)log.visible);
  EXPECT_EQ(vfc.visible, log.visible) << "the same frames must see the same objects";
  EXPECT_GE(log.drawn, log.visible) << "drew fewer objects than are visible";
  EXPECT_LT(ratio, c.max_ratio) << c.scene << " " << toString(c.method) << " drew " << log.drawn
                                << " objects against vfc's " << vfc.drawn
                                << "; reproduce: " << reproducer(key, config);
}

INSTANTIATE_TEST_SUITE_P(Scenes, Reduction,
                         testing::Values(ReductionCase{"forest", Method::LogState, 0.8},
                                         ReductionCase{"forest", Method::LogZfar, 0.6},
                                         ReductionCase{"city", Method::LogState, 0.5},
                                         ReductionCase{"city", Method::LogZfar, 0.5}),
                         [](const testing::TestParamInfo<ReductionCase>& p) {
                           return sanitize(p.param.scene + "_" + toString(p.param.method));
                         });

}  // namespace
}  // namespace logrid::oracle
