// The culler's traversal options and the application's announcements, without GL:
//   * lookahead K (batched tests) and temporal coherence keep every method exact: no
//     visible box is missed, with synchronous, asynchronous and count-only sources;
//   * noteDrawn() keeps the two-list order sound when the extra drawing lies behind
//     boxes still to be tested, with or without its depth;
//   * noteDepthCleared() makes records taken before a mid-frame clear void;
//   * areas drawn before the traversal (DrawnArea) are used as occluders, soundly.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "box_world.hpp"
#include "logrid/error.hpp"
#include "test_queries.hpp"

namespace logrid {
namespace {

using test::SourceKind;

struct TraversalCase {
  Method method;
  std::uint32_t lookahead;
  bool coherence;
  SourceKind source;
  DepthConvention convention;
};

class TraversalTest : public testing::TestWithParam<TraversalCase> {};

// Several frames of a turning camera with one culler, so temporal coherence carries
// leaves from frame to frame.
TEST_P(TraversalTest, NeverMissesAVisibleBox) {
  const TraversalCase c = GetParam();
  const test::BoxWorld world = test::makeBoxWorld(21);
  CullerDesc desc;
  desc.method = c.method;
  desc.tile_size = 16;
  desc.lookahead = c.lookahead;
  desc.temporal_coherence = c.coherence;
  Culler culler(desc);
  std::uint64_t drawn = 0, coherent = 0, batches = 0, tested = 0, occluded = 0;
  for (int frame = 0; frame < 6; ++frame) {
    const Camera cam = test::boxCamera(160, 96, c.convention, -0.3 + 0.12 * frame);
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
    const test::CulledFrame f = test::cullBoxes(culler, world, cam, depth, c.source);
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
      EXPECT_TRUE(f.drawn.count(id)) << "frame " << frame << ": visible box " << id << " culled";
    }
    drawn += f.drawn.size();
    coherent += f.stats.coherent_leaves;
    batches += f.stats.batches;
    tested += f.stats.boxes_tested;
    occluded += f.stats.boxes_occluded;
  }
  // pq has no records: with an unlimited lookahead and nothing drawn first, every box is
  // read before anything is drawn, and nothing can be occluded yet.
  if (!(c.method == Method::Pq && c.lookahead == kUnlimitedLookahead && !c.coherence)) {
    EXPECT_GT(occluded, 0u) << "the walls hide boxes: something must be culled";
  }
  if (c.coherence) {
    EXPECT_GT(coherent, 0u) << "later frames start from the last frame's visible leaves";
  } else {
    EXPECT_EQ(coherent, 0u);
  }
  std::printf(
      "[ traversal ] %s K=%u tc=%d %s: drawn %llu, tested %llu, occluded %llu, "
      "batches %llu, coherent %llu\n",
      toString(c.method), c.lookahead, int(c.coherence), test::toString(c.source),
      (unsigned long long)drawn, (unsigned long long)tested, (unsigned long long)occluded,
      (unsigned long long)batches, (unsigned long long)coherent);
}

std::string traversalName(const testing::TestParamInfo<TraversalCase>& info) {
  const TraversalCase& c = info.param;
  std::string s = std::string(toString(c.method)) + "_K" +
                  (c.lookahead == kUnlimitedLookahead ? "all" : std::to_string(c.lookahead)) +
                  (c.coherence ? "_tc_" : "_") + test::toString(c.source) + "_" +
                  toString(c.convention);
  for (char& ch : s) ch = ch == '-' ? '_' : ch;
  return s;
}

std::vector<TraversalCase> traversalCases() {
  std::vector<TraversalCase> out;
  for (Method m : {Method::LogState, Method::LogZfar, Method::Pq}) {
    for (std::uint32_t k : {1u, 4u, 16u, kUnlimitedLookahead}) {
      for (bool tc : {false, true}) {
        for (SourceKind s : {SourceKind::Software, SourceKind::Batched, SourceKind::CountOnly}) {
          out.push_back({m, k, tc, s, DepthConvention::Standard});
        }
      }
    }
    out.push_back({m, 16, true, SourceKind::Batched, DepthConvention::Reversed});
  }
  // Methods without lookahead accept the settings and test one box at a time.
  for (Method m : {Method::Bog, Method::Hzb}) {
    out.push_back({m, kUnlimitedLookahead, true, SourceKind::Software, DepthConvention::Standard});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Options, TraversalTest, testing::ValuesIn(traversalCases()),
                         traversalName);

TEST(TraversalTest, LookaheadBatchesTheReads) {
  // The same frame with K = 1 and K unlimited: the same boxes are drawn only if both
  // are exact, and the batched traversal waits for the source far fewer times.
  const test::BoxWorld world = test::makeBoxWorld(22);
  const Camera cam = test::boxCamera(160, 96, DepthConvention::Standard, 0.1);
  CullerDesc one;
  one.method = Method::LogZfar;
  one.tile_size = 16;
  CullerDesc all = one;
  all.lookahead = kUnlimitedLookahead;
  Culler a(one), b(all);
  cpu::SoftwareDepthBuffer da(160, 96, DepthConvention::Standard),
      db(160, 96, DepthConvention::Standard);
  const test::CulledFrame fa = test::cullBoxes(a, world, cam, da, SourceKind::Batched);
  const test::CulledFrame fb = test::cullBoxes(b, world, cam, db, SourceKind::Batched);
  EXPECT_GT(fa.stats.batches, 0u);
  EXPECT_LT(fb.stats.batches * 3, fa.stats.batches)
      << "K=1: " << fa.stats.batches << " batches, K=all: " << fb.stats.batches;
  for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
    EXPECT_TRUE(fa.drawn.count(id) && fb.drawn.count(id)) << id;
  }
}

TEST(TraversalTest, CoherenceIsForgottenWhenTheHierarchyIsRebuilt) {
  test::BoxWorld world = test::makeBoxWorld(23);
  const Camera cam = test::boxCamera(160, 96, DepthConvention::Standard, 0.0);
  CullerDesc desc;
  desc.temporal_coherence = true;
  Culler culler(desc);
  cpu::SoftwareDepthBuffer depth(160, 96, DepthConvention::Standard);
  test::cullBoxes(culler, world, cam, depth, SourceKind::Software);
  depth.clear();
  EXPECT_GT(test::cullBoxes(culler, world, cam, depth, SourceKind::Software).stats.coherent_leaves,
            0u);
  world.hierarchy = bvh::buildOverBoxes(world.boxes, {2, 2, 1});  // new node ids
  depth.clear();
  EXPECT_EQ(test::cullBoxes(culler, world, cam, depth, SourceKind::Software).stats.coherent_leaves,
            0u);
}

// A hand-made scene for the announcement tests: boxes at chosen depths, one leaf each,
// straight ahead of a camera at the origin looking down -z.
struct Stage {
  std::vector<Aabb> boxes;
  bvh::FlatHierarchy hierarchy;
  Camera cam;
};

Stage makeStage(const std::vector<Aabb>& boxes, DepthConvention convention) {
  Stage s;
  s.boxes = boxes;
  s.hierarchy = bvh::buildOverBoxes(boxes, {1, 2, 1});
  s.cam.width = 64;
  s.cam.height = 64;
  s.cam.depth = {convention,
                 convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                         : ClipDepthRange::NegativeOneToOne,
                 DepthFormat::D32F};
  s.cam.view_projection = multiply(perspective(1.2, 1.0, 0.5, 200, s.cam.depth),
                                   lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}));
  return s;
}

struct AnnounceCase {
  Method method;
  bool with_depth;
  DepthConvention convention;
};

class NoteDrawnTest : public testing::TestWithParam<AnnounceCase> {};

// Box 0 is near and small on the left; box 1 lies further away on the right. While box
// 0 is drawn, the application also draws a particle — a large quad far behind box 1,
// covering it on screen — and announces it. Box 1 is in front of the particle, so it is
// visible; a culler that took the particle's pixels for "drawn in front" would cull it.
TEST_P(NoteDrawnTest, ExtraDrawingBehindABoxStillToBeTestedDoesNotHideIt) {
  const AnnounceCase c = GetParam();
  Stage s = makeStage({{{-3, -1, -8}, {-2, 1, -7}}, {{1, -1, -21}, {3, 1, -20}}}, c.convention);
  const Aabb particle{{-40, -40, -90}, {40, 40, -90}};
  CullerDesc desc;
  desc.method = c.method;
  desc.tile_size = 8;
  Culler culler(desc);
  cpu::SoftwareDepthBuffer depth(64, 64, c.convention);
  test::BoxWorld world{s.boxes, s.hierarchy};
  const test::CulledFrame f =
      test::cullBoxes(culler, world, s.cam, depth, SourceKind::Software,
                      [&](ObjectId id, cpu::SoftwareRasterizer& raster) {
                        if (id != 0) return;
                        test::drawBox(raster, particle, 99);
                        if (c.with_depth) {
                          culler.noteDrawn(particle);
                        } else {
                          const BoxProjection p = culler.project(particle);
                          culler.noteDrawn(DrawnArea{p.rect});  // depth unknown
                        }
                      });
  EXPECT_TRUE(f.drawn.count(1)) << "box 1 lies in front of the particle and is visible";
  EXPECT_TRUE(f.drawn.count(0));
}

std::string announceName(const testing::TestParamInfo<AnnounceCase>& info) {
  std::string s = std::string(toString(info.param.method)) +
                  (info.param.with_depth ? "_box_" : "_rect_") + toString(info.param.convention);
  for (char& ch : s) ch = ch == '-' ? '_' : ch;
  return s;
}

std::vector<AnnounceCase> announceCases() {
  std::vector<AnnounceCase> out;
  for (Method m : {Method::LogState, Method::LogZfar, Method::Bog, Method::Hzb, Method::Pq}) {
    for (bool d : {false, true}) {
      for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
        out.push_back({m, d, conv});
      }
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Methods, NoteDrawnTest, testing::ValuesIn(announceCases()), announceName);

class DepthClearTest : public testing::TestWithParam<AnnounceCase> {};

// Box 0 (near, in the middle) hides boxes 1 and 3 behind it; box 2 lies off to the side
// between them in depth. Box 1 is tested while box 0's depth is in the buffer (its
// tiles get up-to-date "full" records); box 2's draw clears the depth buffer; box 3,
// tested after the clear, is visible in the final image (drawn over box 0's colour).
TEST_P(DepthClearTest, RecordsFromBeforeAMidFrameClearAreNotTrusted) {
  const AnnounceCase c = GetParam();
  Stage s = makeStage({{{-2, -2, -6}, {2, 2, -5}},
                       {{-1, -1, -31}, {1, 1, -30}},
                       {{20, -1, -36}, {22, 1, -35}},
                       {{-1, -1, -41}, {1, 1, -40}}},
                      c.convention);
  CullerDesc desc;
  desc.method = c.method;
  desc.tile_size = 8;
  Culler culler(desc);
  cpu::SoftwareDepthBuffer depth(64, 64, c.convention);
  test::BoxWorld world{s.boxes, s.hierarchy};
  const test::CulledFrame f = test::cullBoxes(culler, world, s.cam, depth, SourceKind::Software,
                                              [&](ObjectId id, cpu::SoftwareRasterizer&) {
                                                if (id != 2) return;
                                                depth.clear();
                                                culler.noteDepthCleared();
                                              });
  EXPECT_FALSE(f.drawn.count(1)) << "box 1 is hidden behind box 0 before the clear";
  EXPECT_TRUE(f.drawn.count(3)) << "box 3 is tested after the clear and is visible";
}

INSTANTIATE_TEST_SUITE_P(
    Methods, DepthClearTest,
    testing::Values(AnnounceCase{Method::LogState, false, DepthConvention::Standard},
                    AnnounceCase{Method::LogState, false, DepthConvention::Reversed},
                    AnnounceCase{Method::LogZfar, false, DepthConvention::Standard},
                    AnnounceCase{Method::LogZfar, false, DepthConvention::Reversed},
                    AnnounceCase{Method::Hzb, false, DepthConvention::Standard}),
    announceName);

// The same frame with the query schedules of log+hwq: what the records found hidden
// while box 2 waited to be drawn is tested again after the clear, also when the
// schedule had nothing left to do.
TEST(DepthClearTest, QueryScheduleRecordsFromBeforeAMidFrameClearAreNotTrusted) {
  for (const char* schedule : {"hwq", "chc", "stat", "nohc"}) {
    Stage s = makeStage({{{-2, -2, -6}, {2, 2, -5}},
                         {{-1, -1, -31}, {1, 1, -30}},
                         {{20, -1, -36}, {22, 1, -35}},
                         {{-1, -1, -41}, {1, 1, -40}}},
                        DepthConvention::Standard);
    CullerDesc desc;
    desc.method = Method::LogHwq;
    desc.tile_size = 8;
    desc.queries.schedule = *parseQuerySchedule(schedule);
    desc.queries.hardware = {1e-6, 1e-9, 1e-10, 1e-6};  // nohc's costs
    Culler culler(desc);
    cpu::SoftwareDepthBuffer depth(64, 64, DepthConvention::Standard);
    test::SoftwareQueries queries(depth);
    cpu::SoftwareRasterizer raster(s.cam, depth, nullptr);
    std::set<ObjectId> drawn;
    culler.cullFrame(s.cam, s.hierarchy, {&depth, &queries}, [&](ObjectId id) {
      test::drawBox(raster, s.boxes[id], id);
      drawn.insert(id);
      if (id != 2) return;
      depth.clear();
      culler.noteDepthCleared();
    });
    EXPECT_TRUE(drawn.count(3)) << schedule << ": box 3 is tested after the clear and is visible";
  }
}

TEST(DepthClearTest, AClearToANearerValueIsTestedByDepth) {
  // glClearDepth(d) then glClear mid-frame, with d nearer than the far plane: every pixel
  // holds d, which is not "free", yet a box in front of d is visible; a box behind d is
  // hidden by the clear itself.
  for (Method m : {Method::LogState, Method::LogZfar, Method::Pq}) {
    Stage s = makeStage(
        {{{-3, -1, -6}, {-2, 1, -5}}, {{1, -1, -11}, {3, 1, -10}}, {{-1, -1, -151}, {1, 1, -150}}},
        DepthConvention::Standard);
    const Projector projector(s.cam);
    const float cleared_key = projector.project({{-1, -1, -50}, {1, 1, -50}}).near_key;
    CullerDesc desc;
    desc.method = m;
    desc.tile_size = 8;
    Culler culler(desc);
    cpu::SoftwareDepthBuffer depth(64, 64, DepthConvention::Standard);
    test::BoxWorld world{s.boxes, s.hierarchy};
    const test::CulledFrame f =
        test::cullBoxes(culler, world, s.cam, depth, SourceKind::Software,
                        [&](ObjectId id, cpu::SoftwareRasterizer&) {
                          if (id != 0) return;
                          std::fill(depth.data(), depth.data() + 64 * 64, cleared_key);
                          culler.noteDepthCleared(cleared_key);
                        });
    EXPECT_TRUE(f.drawn.count(1)) << toString(m) << ": box 1 lies in front of the cleared depth";
    EXPECT_FALSE(f.drawn.count(2)) << toString(m) << ": box 2 lies behind the cleared depth";
  }
}

TEST(DepthClearTest, AnnouncementsOutsideAFrameThrow) {
  Culler culler;
  EXPECT_THROW(culler.noteDrawn(DrawnArea{{0, 0, 4, 4}}), Error);
  EXPECT_THROW(culler.noteDrawn(Aabb{{0, 0, 0}, {1, 1, 1}}), Error);
  EXPECT_THROW(culler.noteDepthCleared(), Error);
}

TEST(DrawnBeforeTest, OccludersDrawnBeforeTheTraversalCullSoundly) {
  // A wall drawn before cullFrame() and announced: the boxes behind it are culled, none
  // in front of it or beside it.
  const test::BoxWorld world = test::makeBoxWorld(24);
  for (Method m : {Method::LogState, Method::LogZfar}) {
    for (bool announce : {false, true}) {
      const Camera cam = test::boxCamera(160, 96, DepthConvention::Standard, 0.0);
      cpu::SoftwareDepthBuffer depth(160, 96, DepthConvention::Standard);
      const Aabb wall{{-6, -3, -30}, {6, 4, -30}};
      std::vector<Aabb> all = world.boxes;
      {
        cpu::SoftwareRasterizer raster(cam, depth, nullptr);
        test::drawBox(raster, wall, 0);
      }
      all.push_back(wall);
      CullerDesc desc;
      desc.method = m;
      desc.tile_size = 16;
      Culler culler(desc);
      std::vector<DrawnArea> before;
      if (announce) {
        const Projector projector(cam);
        const BoxProjection p = projector.project(wall);
        before.push_back({p.rect, p.far_key + p.margin});
      }
      // Drawn before and not announced breaks the contract only towards "visible".
      const test::CulledFrame f =
          test::cullBoxes(culler, world, cam, depth, SourceKind::Software, {}, before);
      std::set<ObjectId> visible = test::visibleBoxes(all, cam);
      visible.erase(ObjectId(all.size() - 1));
      for (ObjectId id : visible) EXPECT_TRUE(f.drawn.count(id)) << toString(m) << " " << id;
    }
  }
}

// Areas drawn before the traversal are judged by their rectangles. A backdrop far behind
// every box, drawn first over the left half of the screen: boxes on the right keep the
// occlusion-state test, and a box in front of the backdrop on its half is drawn. Drawn
// over the whole screen, it sends every occlusion-state test to depth.
TEST(DrawnBeforeTest, AnAreaBehindOnlyAffectsTheBoxesItOverlaps) {
  for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
    std::uint64_t fallbacks[2] = {}, f_tested[2] = {};
    for (bool left : {true, false}) {
      // Box 0 near on the right, box 1 behind it (hidden), box 2 on the left.
      Stage s = makeStage(
          {{{0.5, -3, -8}, {6, 3, -7}}, {{2, -1, -21}, {3, 1, -20}}, {{-4, -1, -21}, {-3, 1, -20}}},
          conv);
      const Aabb backdrop =
          left ? Aabb{{-60, -60, -90}, {-1, 60, -90}} : Aabb{{-60, -60, -90}, {60, 60, -90}};
      cpu::SoftwareDepthBuffer depth(64, 64, conv);
      {
        cpu::SoftwareRasterizer raster(s.cam, depth, nullptr);
        test::drawBox(raster, backdrop, 99);
      }
      const Projector projector(s.cam);
      const BoxProjection p = projector.project(backdrop);
      ASSERT_EQ(p.cls, ProjectionClass::Inside);
      CullerDesc desc;
      desc.method = Method::LogState;
      desc.tile_size = 8;
      Culler culler(desc);
      test::BoxWorld world{s.boxes, s.hierarchy};
      const test::CulledFrame f = test::cullBoxes(culler, world, s.cam, depth, SourceKind::Software,
                                                  {}, {{p.rect, p.far_key + p.margin}});
      EXPECT_TRUE(f.drawn.count(0)) << toString(conv);
      EXPECT_TRUE(f.drawn.count(2)) << toString(conv) << ": in front of the backdrop";
      EXPECT_FALSE(f.drawn.count(1)) << toString(conv) << ": hidden by box 0";
      fallbacks[left] = f.stats.order_fallbacks;
      f_tested[left] = f.stats.boxes_tested;
    }
    // Over the whole screen it sends every test to depth; over the left half, only those
    // of boxes reaching into it (the inner nodes), not those of boxes 0 and 1.
    EXPECT_EQ(fallbacks[false], f_tested[false]) << toString(conv);
    EXPECT_LE(fallbacks[true] + 2, fallbacks[false]) << toString(conv);
  }
}

}  // namespace
}  // namespace logrid
