// The method table (method.hpp, log/src/methods/): every method defined once, its
// capabilities consistent with what makes it sound, and the culler asking for exactly the
// sources a method needs (CullSources). The occluder methods with an occluder source of
// the test's own.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "box_world.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

TEST(MethodTable, EveryMethodOnceInEnumOrderWithAUniqueName) {
  const std::vector<MethodInfo>& table = methodTable();
  ASSERT_EQ(table.size(), std::size_t(Method::Auto) + 1);
  std::set<std::string> names;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const MethodInfo& m = table[i];
    EXPECT_EQ(std::size_t(m.method), i) << m.name;
    EXPECT_TRUE(names.insert(m.name).second) << "name given twice: " << m.name;
    EXPECT_EQ(parseMethod(m.name), m.method);
    EXPECT_STREQ(toString(m.method), m.name);
    EXPECT_NE(std::string(m.description), "") << m.name;
    EXPECT_NE(methodNames().find(m.name), std::string::npos) << m.name;
  }
}

// What makes each kind of method sound, or able to run, as its MethodInfo states it.
TEST(MethodTable, CapabilitiesAreConsistent) {
  for (const MethodInfo& m : methodTable()) {
    SCOPED_TRACE(m.name);
    // "Any drawn pixel hides" holds only while everything drawn lies in front (LOG §3).
    if (m.semantics == TestSemantics::OcclusionState) {
      EXPECT_EQ(m.traversal, Traversal::TwoList);
    }
    // A grid reads the depth buffer; the knobs that act on tiles need one.
    if (m.grid) {
      EXPECT_TRUE(m.needs.depth);
    }
    if (m.takes.row_stride) {
      EXPECT_TRUE(m.grid.has_value());
    }
    if (m.takes.full_fraction) {
      EXPECT_EQ(m.grid, GridVariant::OcclusionState);
      EXPECT_EQ(m.semantics, TestSemantics::OcclusionState);
    }
    // Queries come with a schedule, and a schedule with queries.
    EXPECT_EQ(m.traversal == Traversal::Schedule, m.needs.queries);
    if (m.traversal == Traversal::Schedule) {
      EXPECT_NE(m.schedule.has_value(), m.takes.query_schedule)
          << "a schedule of its own, or CullerDesc::queries.schedule";
    } else {
      EXPECT_FALSE(m.schedule.has_value());
      EXPECT_FALSE(m.takes.query_schedule);
    }
    EXPECT_EQ(m.occluders != OccluderUse::None, m.needs.occluders);
    if (m.occluders == OccluderUse::Recorded) {
      EXPECT_TRUE(m.needs.depth);
    }
    if (m.needs.depth_values) {
      EXPECT_TRUE(m.needs.depth);
    }
    // Batches read tiles or counts through a depth source.
    if (m.takes.lookahead) {
      EXPECT_TRUE(m.needs.depth);
    }
    if (m.semantics == TestSemantics::None) {
      EXPECT_FALSE(m.needs.depth || m.needs.queries || m.needs.occluders);
    }
  }
}

TEST(MethodTable, EveryMethodBuildsWithItsDefaults) {
  for (const MethodInfo& m : methodTable()) {
    CullerDesc d;
    d.method = m.method;
    if (m.schedule == QuerySchedule::Nohc) d.queries.hardware = {1e-6, 1e-9, 1e-10, 1e-6};
    EXPECT_EQ(validateCullerDesc(d), "") << m.name;
    EXPECT_NO_THROW(Culler{d}) << m.name;
  }
  CullerDesc d;
  d.method = Method::LogHwq;
  d.queries.schedule = QuerySchedule::Nohc;  // hardware parameters unmeasured
  EXPECT_NE(validateCullerDesc(d).find("hardware parameter"), std::string::npos);
  EXPECT_EQ(querySchedule(d), QuerySchedule::Nohc);
  d.method = Method::Chc;
  EXPECT_EQ(querySchedule(d), QuerySchedule::Chc);
  d.method = Method::LogState;
  EXPECT_FALSE(querySchedule(d).has_value());
}

// A depth source that fails the test if anything is asked of it.
class UntouchableSource final : public DepthSource {
 public:
  DepthSourceTraits traits() const override { return {"untouchable", true, false}; }
  Status beginFrame(const Camera&) override {
    ADD_FAILURE() << "beginFrame";
    return {};
  }
  void submit(const AreaRequest*, std::size_t, AreaAnswer*) override { ADD_FAILURE() << "submit"; }
  void noteDraw() override { ADD_FAILURE() << "noteDraw"; }
};

// Every pixel left of `split` is hidden at any depth; nothing is drawn. Records what the
// culler asked.
class HalfOccluders final : public OccluderSource {
 public:
  explicit HalfOccluders(std::int32_t split) : split_(split) {}
  Result<std::uint64_t> beginFrame(const Camera& camera, const ProjectionSettings&, bool draw,
                                   std::vector<DrawnArea>& drawn) override {
    ++frames;
    asked_to_draw = draw;
    // Its farthest key unknown: every occlusion-state test it overlaps goes by depth.
    if (draw) drawn.push_back({{0, 0, split_, std::int32_t(camera.height)}});
    return std::uint64_t{7};
  }
  bool occludes(const PixelRect& rect, float) const override { return rect.x1 <= split_; }

  int frames = 0;
  bool asked_to_draw = false;

 private:
  std::int32_t split_;
};

TEST(CullSources, AMissingSourceIsRefusedNamingWhatToPass) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(64, 48, DepthConvention::Standard, 0);
  for (const MethodInfo& m : methodTable()) {
    CullerDesc d;
    d.method = m.method;
    d.queries.hardware = {1e-6, 1e-9, 1e-10, 1e-6};
    Culler culler(d);
    const bool needs = m.needs.depth || m.needs.queries || m.needs.occluders;
    try {
      culler.cullFrame(cam, world.hierarchy, CullSources{}, [](ObjectId) {});
      EXPECT_FALSE(needs) << m.name << " ran without the sources it needs";
    } catch (const Error& e) {
      EXPECT_TRUE(needs) << m.name << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("CullSources"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(m.name), std::string::npos) << e.what();
    }
  }
}

TEST(CullSources, ASourceTheMethodDoesNotNeedIsNotTouched) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(64, 48, DepthConvention::Standard, 0);
  UntouchableSource untouchable;
  HalfOccluders occluders(32);
  for (Method method : {Method::Vfc, Method::Ddo}) {
    Culler culler({method, 8, {}, {}});
    std::size_t drawn = 0;
    const FrameStats s = culler.cullFrame(cam, world.hierarchy, {&untouchable, nullptr, &occluders},
                                          [&](ObjectId) { ++drawn; });
    EXPECT_GT(drawn, 0u) << toString(method);
    EXPECT_EQ(s.reads, 0u);
  }
}

// ddo tests boxes against the occluders' map alone: a box left of the split is culled,
// one that reaches right of it is drawn; nothing is read or drawn first.
TEST(OccluderMethods, DdoCullsWhatTheMapHidesAndReadsNothing) {
  const test::BoxWorld world = test::makeBoxWorld(5);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0.1);
  const Projector projector(cam);
  HalfOccluders occluders(80);
  Culler culler({Method::Ddo, 8, {}, {}});
  std::set<ObjectId> drawn;
  const FrameStats s = culler.cullFrame(cam, world.hierarchy, {nullptr, nullptr, &occluders},
                                        [&](ObjectId id) { drawn.insert(id); });
  EXPECT_EQ(occluders.frames, 1);
  EXPECT_FALSE(occluders.asked_to_draw);
  EXPECT_EQ(s.occluders, 7u);
  EXPECT_EQ(s.reads, 0u);
  std::size_t left = 0, right = 0;
  for (ObjectId id = 0; id < world.boxes.size(); ++id) {
    const BoxProjection p = projector.project(world.boxes[id]);
    if (p.cls != ProjectionClass::Inside) continue;
    if (p.rect.x0 >= 80) {
      EXPECT_TRUE(drawn.count(id)) << "box " << id << " lies right of the occluders";
      ++right;
    }
    if (p.rect.x1 <= 80 && !drawn.count(id)) ++left;
  }
  EXPECT_GT(right, 0u);
  EXPECT_GT(left, 0u) << "no box left of the split was culled: the map was not asked";
}

// ddo+log with a source that draws its occluders (the culler announces what it drew):
// the grid finds their tiles outdated and reads them, and occlusion-state tests of boxes
// they may lie behind go by depth. No visible box is missed.
TEST(OccluderMethods, DdoLogAnnouncesTheOccludersItAskedToBeDrawn) {
  const test::BoxWorld world = test::makeBoxWorld(5);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0.1);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  HalfOccluders occluders(80);
  Culler culler({Method::DdoLog, 8, {}, {}});
  cpu::SoftwareRasterizer raster(cam, depth, nullptr);
  std::set<ObjectId> drawn;
  const FrameStats s =
      culler.cullFrame(cam, world.hierarchy, {&depth, nullptr, &occluders}, [&](ObjectId id) {
        test::drawBox(raster, world.boxes[id], id);
        drawn.insert(id);
      });
  EXPECT_TRUE(occluders.asked_to_draw);
  EXPECT_EQ(s.occluders, 7u);
  EXPECT_GT(s.order_fallbacks, 0u) << "boxes in front of the announced area must go by depth";
  for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
    EXPECT_TRUE(drawn.count(id)) << "visible box " << id << " missed";
  }
}

}  // namespace
}  // namespace logrid
