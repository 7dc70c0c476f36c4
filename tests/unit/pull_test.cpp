// The pull form of a frame (Culler::beginFrame, nextBatch, endFrame): the same draws,
// reads and statistics as the callback form for every method and traversal setting; no
// query while objects handed out (or about to be) are not drawn, and no read of pixels
// they may cover; a batch drawn in any order; clears and extra drawing announced between
// batches; misuse refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "box_world.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"
#include "test_queries.hpp"

namespace logrid {
namespace {

// An occluder pre-pass that hides nothing but announces an area of unknown depth when
// asked to draw (a stand-in for ddo's occluders: honest, so no visible box is missed).
class AnnouncingOccluders final : public OccluderSource {
 public:
  Result<std::uint64_t> beginFrame(const Camera& camera, const ProjectionSettings&, bool draw,
                                   std::vector<DrawnArea>& drawn) override {
    if (draw) drawn.push_back({{0, 0, 40, std::int32_t(camera.height)}});
    return std::uint64_t{1};
  }
  bool occludes(const PixelRect&, float) const override { return false; }
};

// Objects the culler handed out or put in the batch it hands out next (its observer's
// onDrawn) and objects drawn: a query while they differ, or a read of pixels that the
// undrawn ones may cover, would miss what is still to be drawn.
struct Watch : CullObserver {
  const Hierarchy* hierarchy = nullptr;
  std::size_t handed = 0;
  std::size_t drawn = 0;
  std::vector<PixelRect> undrawn;  // the rectangles of the nodes handed and not drawn
  std::size_t early_reads = 0;     // reads while some were undrawn (none under them)
  void onDrawn(NodeId node, const BoxProjection& p) override {
    handed += hierarchy->objectCount(node);
    undrawn.push_back(p.rect);
  }
  void addDrawn(std::size_t n) {
    drawn += n;
    if (drawn == handed) undrawn.clear();
  }
  void check(const char* what) const {
    EXPECT_EQ(handed, drawn) << what << " while " << handed - drawn
                             << " objects handed out are not drawn";
  }
  void checkRead(const PixelRect& rect) {
    if (handed == drawn) return;
    ++early_reads;
    for (const PixelRect& r : undrawn) {
      EXPECT_FALSE(rect.meets(r)) << "a read of " << rect.x0 << "," << rect.y0 << "," << rect.x1
                                  << "," << rect.y1 << " under an object not drawn yet, at " << r.x0
                                  << "," << r.y0 << "," << r.x1 << "," << r.y1;
    }
  }
};

// Occlusion queries over the software buffer that fail the test when issued or waited
// for while the application holds undrawn objects.
class WatchedQueries final : public test::SoftwareQueries {
 public:
  WatchedQueries(cpu::SoftwareDepthBuffer& buffer, const Watch& watch)
      : SoftwareQueries(buffer), watch_(watch) {}
  QueryHandle issueBoxes(const QueryBox* boxes, std::size_t count) override {
    watch_.check("a query");
    return SoftwareQueries::issueBoxes(boxes, count);
  }
  QueryHandle issueRects(const RectQuery* rects, std::size_t count) override {
    watch_.check("a query");
    return SoftwareQueries::issueRects(rects, count);
  }
  std::uint32_t result(QueryHandle h) override {
    watch_.check("an answer");
    return SoftwareQueries::result(h);
  }

 private:
  const Watch& watch_;
};

// A depth source that fails the test when asked to read pixels that objects handed out
// and not drawn yet may cover.
class WatchedSource final : public DepthSource, public KeyReader {
 public:
  WatchedSource(DepthSource& inner, Watch& watch) : inner_(inner), watch_(watch) {}
  DepthSourceTraits traits() const override { return inner_.traits(); }
  Status beginFrame(const Camera& camera) override { return inner_.beginFrame(camera); }
  Status endFrame() override { return inner_.endFrame(); }
  void noteDraw() override { inner_.noteDraw(); }
  void submit(const AreaRequest* r, std::size_t n, AreaAnswer* a) override {
    for (std::size_t i = 0; i < n; ++i) watch_.checkRead(r[i].rect);
    inner_.submit(r, n, a);
    counters_ = inner_.counters();
  }
  void collect() override {
    inner_.collect();
    counters_ = inner_.counters();
  }
  void readKeys(const PixelRect& rect, float* keys) override {
    watch_.checkRead(rect);
    dynamic_cast<KeyReader&>(inner_).readKeys(rect, keys);
  }

 private:
  DepthSource& inner_;
  Watch& watch_;
};

struct Setting {
  Method method;
  std::uint32_t lookahead;
  bool coherence;
};

std::string name(const Setting& s) {
  return std::string(toString(s.method)) + ":" + std::to_string(s.lookahead) +
         (s.coherence ? ":tc" : "");
}

std::vector<Setting> settings() {
  std::vector<Setting> out;
  for (const MethodInfo& m : methodTable()) {
    // auto chooses from measured times (Culler::costEstimate), so two runs of the same
    // frames may choose apart; its frames are checked against the oracle in auto_test.
    if (m.method == Method::Auto) continue;
    for (std::uint32_t k : {1u, 16u}) {
      if (k > 1 && !m.takes.lookahead) continue;
      for (bool tc : {false, true}) {
        if (tc && !m.takes.temporal_coherence) continue;
        out.push_back({m.method, k, tc});
      }
    }
  }
  return out;
}

struct Walk {
  std::vector<std::vector<ObjectId>> drawn;  // per frame, in draw order
  std::vector<FrameStats> stats;
  std::vector<std::size_t> batches;  // per frame (pull form)
  std::size_t early_reads = 0;       // reads while objects handed out were not drawn
};

// Four frames of the box world with `setting`, through the callback form or the pull form.
Walk walk(const Setting& setting, bool pull) {
  const test::BoxWorld world = test::makeBoxWorld(11);
  CullerDesc d;
  d.method = setting.method;
  d.tile_size = 8;
  d.lookahead = setting.lookahead;
  d.temporal_coherence = setting.coherence;
  d.queries.hardware = {1e-6, 1e-9, 1e-10, 1e-6};
  Culler culler(d);
  Watch watch;
  watch.hierarchy = &world.hierarchy;
  culler.setObserver(&watch);
  AnnouncingOccluders occluders;
  Walk run;
  for (int f = 0; f < 4; ++f) {
    const Camera cam = test::boxCamera(96, 72, DepthConvention::Standard, -0.2 + 0.1 * f);
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
    WatchedSource watched(depth, watch);
    WatchedQueries queries(depth, watch);
    queries.frame = std::uint32_t(f + 1);
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    const CullSources sources{&watched, &queries, &occluders};
    std::vector<ObjectId> drawn;
    const auto draw = [&](ObjectId id) {
      test::drawBox(raster, world.boxes[id], id);
      drawn.push_back(id);
      watch.addDrawn(1);
    };
    if (!pull) {
      run.stats.push_back(culler.cullFrame(cam, world.hierarchy, sources, draw));
    } else {
      culler.beginFrame(cam, world.hierarchy, sources);
      std::size_t batches = 0;
      for (DrawBatch b = culler.nextBatch(); !b.empty(); b = culler.nextBatch()) {
        ++batches;
        // Drawn back to front: the order within a batch is the application's.
        std::vector<ObjectId> ids(b.begin(), b.end());
        for (auto it = ids.rbegin(); it != ids.rend(); ++it) {
          test::drawBox(raster, world.boxes[*it], *it);
        }
        drawn.insert(drawn.end(), ids.begin(), ids.end());
        watch.addDrawn(ids.size());
      }
      run.stats.push_back(culler.endFrame());
      run.batches.push_back(batches);
      EXPECT_EQ(run.stats.back().draw_batches, batches);
    }
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
      EXPECT_NE(std::find(drawn.begin(), drawn.end(), id), drawn.end())
          << name(setting) << (pull ? " pull" : " callback") << " frame " << f << ": visible box "
          << id << " missed";
    }
    run.drawn.push_back(std::move(drawn));
  }
  run.early_reads = watch.early_reads;
  return run;
}

class PullForm : public testing::TestWithParam<Setting> {};

TEST_P(PullForm, SameDrawsReadsAndStatisticsAsTheCallbackForm) {
  const Walk callback = walk(GetParam(), false);
  const Walk pull = walk(GetParam(), true);
  for (std::size_t f = 0; f < callback.drawn.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    EXPECT_EQ(pull.drawn[f], callback.drawn[f]);
    const FrameStats& a = callback.stats[f];
    const FrameStats& b = pull.stats[f];
    EXPECT_EQ(a.nodes_visited, b.nodes_visited);
    EXPECT_EQ(a.boxes_tested, b.boxes_tested);
    EXPECT_EQ(a.boxes_occluded, b.boxes_occluded);
    EXPECT_EQ(a.boxes_view_culled, b.boxes_view_culled);
    EXPECT_EQ(a.order_fallbacks, b.order_fallbacks);
    EXPECT_EQ(a.tiles_tested, b.tiles_tested);
    EXPECT_EQ(a.tiles_read, b.tiles_read);
    EXPECT_EQ(a.reads, b.reads);
    EXPECT_EQ(a.pixels_read, b.pixels_read);
    EXPECT_EQ(a.batches, b.batches);
    EXPECT_EQ(a.queries, b.queries);
    EXPECT_EQ(a.records_decided, b.records_decided);
    EXPECT_EQ(a.objects_drawn, b.objects_drawn);
    EXPECT_EQ(a.leaves_drawn, b.leaves_drawn);
    EXPECT_EQ(a.draw_batches, b.draw_batches);
    EXPECT_EQ(a.occluders, b.occluders);
    EXPECT_GT(b.draw_batches, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, PullForm, testing::ValuesIn(settings()),
                         [](const testing::TestParamInfo<Setting>& p) {
                           std::string n = name(p.param);
                           for (char& c : n) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return n;
                         });

// With lookahead the records decide many boxes between reads: the draws they allow come
// out together, far fewer batches than leaves.
TEST(PullForm, LookaheadHandsOutFewerBatchesThanLeaves) {
  const Walk k1 = walk({Method::LogZfar, 1, false}, true);
  const Walk k16 = walk({Method::LogZfar, 16, false}, true);
  std::size_t leaves = 0, batches1 = 0, batches16 = 0;
  for (std::size_t f = 0; f < k16.stats.size(); ++f) {
    leaves += k16.stats[f].leaves_drawn;
    batches1 += k1.batches[f];
    batches16 += k16.batches[f];
  }
  EXPECT_LT(batches16 * 2, leaves) << batches16 << " batches for " << leaves << " leaves";
  EXPECT_LT(batches16, batches1);
}

// A test that reads none of the pixels the batch may cover reads before the batch is
// handed out, so the batch grows and the renderer is waited for once for both: the
// grid's methods read so at one box at a time and with lookahead (the reads of such
// tests are checked above: none under an undrawn object).
TEST(PullForm, TestsReadingAwayFromTheBatchReadBeforeItIsDrawn) {
  for (const Setting& s :
       {Setting{Method::LogState, 1, false}, Setting{Method::LogZfar, 1, false},
        Setting{Method::DdoLog, 1, false}, Setting{Method::LogState, 16, false}}) {
    EXPECT_GT(walk(s, true).early_reads, 0u) << name(s);
  }
}

TEST(PullForm, MisuseIsRefusedAndTheNextFrameStartsAfresh) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler;
  EXPECT_THROW(culler.nextBatch(), Error);
  EXPECT_THROW(culler.endFrame(), Error);
  culler.beginFrame(cam, world.hierarchy, {&depth});
  EXPECT_THROW(culler.beginFrame(cam, world.hierarchy, {&depth}), Error);
  const DrawBatch first = culler.nextBatch();
  ASSERT_FALSE(first.empty());
  // Ending before the traversal is done: refused, and the frame is abandoned.
  EXPECT_THROW(culler.endFrame(), Error);
  EXPECT_THROW(culler.nextBatch(), Error);
  EXPECT_THROW(culler.noteDepthCleared(), Error);
  culler.beginFrame(cam, world.hierarchy, {&depth});
  cpu::SoftwareRasterizer raster(cam, depth, nullptr);
  std::set<ObjectId> drawn;
  for (DrawBatch b = culler.nextBatch(); !b.empty(); b = culler.nextBatch()) {
    for (ObjectId id : b) {
      test::drawBox(raster, world.boxes[id], id);
      drawn.insert(id);
    }
  }
  const FrameStats s = culler.endFrame();
  EXPECT_EQ(s.objects_drawn, drawn.size());
  for (ObjectId id : test::visibleBoxes(world.boxes, cam)) EXPECT_TRUE(drawn.count(id)) << id;
}

// A draw callback that throws ends the frame: the culler is usable again.
TEST(PullForm, AnExceptionFromTheCallbackEndsTheFrame) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(64, 48, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(64, 48, DepthConvention::Standard);
  Culler culler;
  EXPECT_THROW(culler.cullFrame(cam, world.hierarchy, depth,
                                [](ObjectId) { throw Error(ErrorCode::Runtime, "draw failed"); }),
               Error);
  EXPECT_NO_THROW(culler.cullFrame(cam, world.hierarchy, depth, [](ObjectId) {}));
}

}  // namespace
}  // namespace logrid
