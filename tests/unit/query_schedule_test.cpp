// The hardware-query schedules without GL (log/src/query_*.cpp): the scheduling rules of
// each paper, checked on hand-built trees with a scripted query source of deterministic
// latency (tests/support/test_queries.hpp), and every schedule end to end on the box world
// against the object-ID oracle, with queries answered from the software depth buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "box_world.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"
#include "test_queries.hpp"

namespace logrid {
namespace {

using test::QueryEvent;
using test::ScriptedQueries;
using test::TestTree;

// Looking down -z from the origin; 200x150 pixels.
Camera testCamera(DepthConvention convention = DepthConvention::Standard) {
  Camera cam;
  cam.width = 200;
  cam.height = 150;
  cam.depth = {convention,
               convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                       : ClipDepthRange::NegativeOneToOne,
               DepthFormat::D32F};
  cam.view_projection = multiply(perspective(1.2, 200.0 / 150.0, 0.5, 500, cam.depth),
                                 lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}));
  return cam;
}

// Leaf i of a row of `count` boxes at depth z, within the view at z = -20 (about 35
// units wide): at most 1 unit apart, each 60 % of that wide, gaps between neighbours.
Aabb rowBox(int i, int count, float z) {
  const float pitch = std::min(1.0f, 24.0f / float(count));
  const float x0 = pitch * (-0.5f * float(count) + float(i));
  return {{x0, -0.3f, z - 0.5f}, {x0 + 0.6f * pitch, 0.3f, z}};
}

// Root with `leaves` leaf children in a row at z = -20.
TestTree flatTree(int leaves) {
  TestTree t;
  t.add({}, false);
  for (int i = 0; i < leaves; ++i) t.link(0, t.add(rowBox(i, leaves, -20), true));
  t.nodes[0].box = t.nodes[1].box;
  t.fitBoxes();
  return t;
}

// Root -> `groups` groups -> `per_group` leaves each, in one row at z = -20.
TestTree groupedTree(int groups, int per_group) {
  TestTree t;
  t.add({}, false);
  const int leaves = groups * per_group;
  for (int g = 0; g < groups; ++g) {
    const NodeId group = t.add({}, false);
    t.link(0, group);
    for (int k = 0; k < per_group; ++k) {
      t.link(group, t.add(rowBox(g * per_group + k, leaves, -20), true));
    }
    t.nodes[group].box = t.nodes[t.nodes[group].children.front()].box;
  }
  t.nodes[0].box = t.nodes[1].box;
  t.fitBoxes();
  return t;
}

// The leaves of `t` and every ancestor of a leaf in `leaves` (visibility pulls up).
std::set<NodeId> visibleWith(const TestTree& t, const std::set<NodeId>& leaves) {
  std::set<NodeId> out = leaves;
  for (bool grew = true; grew;) {
    grew = false;
    for (NodeId n = 0; n < t.nodes.size(); ++n) {
      for (NodeId c : t.nodes[n].children) {
        if (out.count(c) && out.insert(n).second) grew = true;
      }
    }
  }
  return out;
}

struct Frame {
  FrameStats stats;
  std::set<ObjectId> drawn;
};

Frame runFrame(Culler& culler, const TestTree& t, test::LoggingQueries& q, std::uint32_t frame,
               const Camera& cam = testCamera()) {
  Frame out;
  q.frame = frame;
  out.stats = culler.cullFrame(cam, t, {nullptr, &q}, [&](ObjectId id) {
    q.drawn(id);
    EXPECT_TRUE(out.drawn.insert(id).second) << "object " << id << " drawn twice";
  });
  return out;
}

CullerDesc desc(Method m) {
  CullerDesc d;
  d.method = m;
  return d;
}

// ---------------------------------------------------------------------------
// hwq: one query per tested box, each answer waited for before the walk goes on.
// ---------------------------------------------------------------------------

TEST(HwqSchedule, OneQueryPerTestedBoxWaitedForAtOnce) {
  const TestTree t = groupedTree(4, 4);  // nodes: 0 root, groups 1, 6, 11, 16
  ScriptedQueries q(t);
  // Group 1 wholly visible, group 6 through one leaf; groups 11 and 16 hidden.
  q.visible = visibleWith(t, {2, 3, 4, 5, 7});
  Culler culler(desc(Method::Hwq));
  const Frame f = runFrame(culler, t, q, 1);
  EXPECT_EQ(f.drawn, (std::set<ObjectId>{2, 3, 4, 5, 7}));
  // Root, the four groups and the eight leaves of the two visible groups.
  EXPECT_EQ(f.stats.queries, 13u);
  EXPECT_EQ(f.stats.boxes_tested, 13u);
  EXPECT_EQ(f.stats.boxes_occluded, 2u + 3u);
  EXPECT_EQ(q.max_in_flight, 1u);
  // Every issue is followed by its own result before anything else is issued.
  const auto events = q.events(1);
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (events[i]->kind != QueryEvent::Issue) continue;
    ASSERT_LT(i + 1, events.size());
    EXPECT_EQ(events[i + 1]->kind, QueryEvent::Result);
    EXPECT_EQ(events[i + 1]->handle, events[i]->handle);
    EXPECT_TRUE(events[i + 1]->waited) << "stop and wait must wait";
  }
  // No child of a hidden group was queried.
  for (NodeId n : t.nodes[11].children) EXPECT_EQ(q.issuesOf(n, 1), 0u);
}

// ---------------------------------------------------------------------------
// stat (Kovalčík & Sochor §3)
// ---------------------------------------------------------------------------

TEST(StatSchedule, KeepsQueriesInFlightAndCollectsThemInASecondPass) {
  const TestTree t = flatTree(30);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1, 2, 3});
  CullerDesc d = desc(Method::Stat);
  d.queries.stat_in_flight = 20;
  Culler culler(d);
  const Frame f = runFrame(culler, t, q, 1);
  EXPECT_EQ(f.drawn, (std::set<ObjectId>{1, 2, 3}));
  // The root alone, then 20 leaves issued before any of their answers is read, then the
  // remaining 10: I R, I x20, R x20, I x10, R x10.
  std::string pattern;
  for (const QueryEvent* e : q.events(1)) {
    if (e->kind == QueryEvent::Issue) pattern += 'I';
    if (e->kind == QueryEvent::Result) pattern += 'R';
  }
  EXPECT_EQ(pattern, "IR" + std::string(20, 'I') + std::string(20, 'R') + std::string(10, 'I') +
                         std::string(10, 'R'));
  EXPECT_EQ(q.max_in_flight, 20u);
  // Answers read in the second pass were mostly there already: 20 queries of latency 3.
  EXPECT_LT(f.stats.query_waits, 10u);
}

TEST(StatSchedule, VisibleNodesAreQueriedOnThePapersSchedule) {
  const TestTree t = flatTree(3);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1, 2, 3});
  CullerDesc d = desc(Method::Stat);
  d.queries.stat_base_frames = 4;  // BASE_TIME
  Culler culler(d);
  std::vector<std::uint32_t> queried;
  for (std::uint32_t frame = 1; frame <= 40; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(f.drawn.size(), 3u) << "frame " << frame;
    if (q.issuesOf(1, frame)) queried.push_back(frame);
  }
  // Query at frame q with k unoccluded results: the next one at the first frame after
  // q + 4 (2 - 0.5^k): 1 + 6 -> 8, 8 + 7 -> 16, 16 + 7.5 -> 24, 24 + 7.75 -> 32, 40.
  EXPECT_EQ(queried, (std::vector<std::uint32_t>{1, 8, 16, 24, 32, 40}));
}

TEST(StatSchedule, OccludedNodesAreQueriedEveryFrame) {
  const TestTree t = flatTree(2);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1});  // leaf 2 hidden
  CullerDesc d = desc(Method::Stat);
  d.queries.stat_base_frames = 4;
  Culler culler(d);
  for (std::uint32_t frame = 1; frame <= 10; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(q.issuesOf(2, frame), 1u) << "frame " << frame;
    EXPECT_EQ(q.issuesOf(1, frame), frame == 1 || frame == 8 ? 1u : 0u) << "frame " << frame;
    EXPECT_EQ(f.drawn, (std::set<ObjectId>{1}));
  }
}

// A query issued before a mid-frame depth clear no longer holds: its node is drawn.
TEST(StatSchedule, AnswersIssuedBeforeADepthClearCountAsVisible) {
  const TestTree t = flatTree(10);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1});  // the others "hidden" by what the clear removes
  Culler culler(desc(Method::Stat));
  q.frame = 1;
  std::set<ObjectId> drawn;
  culler.cullFrame(testCamera(), t, {nullptr, &q}, [&](ObjectId id) {
    drawn.insert(id);
    if (id == 1) culler.noteDepthCleared();
  });
  // Leaves 2..10 were queried with leaf 1 and answered after the clear.
  EXPECT_EQ(drawn.size(), 10u);
}

// ---------------------------------------------------------------------------
// chc (CHC++)
// ---------------------------------------------------------------------------

TEST(ChcSchedule, PreviouslyVisibleLeavesAreDrawnBeforeAnyAnswerIsAwaited) {
  const TestTree t = groupedTree(2, 4);
  ScriptedQueries q(t);
  std::set<NodeId> leaves;
  for (NodeId n = 0; n < t.nodes.size(); ++n) {
    if (t.isLeaf(n)) leaves.insert(n);
  }
  q.visible = visibleWith(t, leaves);
  Culler culler(desc(Method::Chc));
  // Frame 1: everything was invisible, so the root is queried and waited for first.
  const Frame first = runFrame(culler, t, q, 1);
  EXPECT_EQ(first.drawn.size(), 8u);
  EXPECT_EQ(q.issuesOf(0, 1), 1u);
  for (std::uint32_t frame = 2; frame <= 4; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(f.drawn.size(), 8u);
    std::size_t draws = 0;
    for (const QueryEvent* e : q.events(frame)) {
      if (e->kind == QueryEvent::Draw) ++draws;
      if (e->kind == QueryEvent::Result) {
        EXPECT_EQ(draws, 8u) << "frame " << frame << ": an answer was read before every "
                             << "previously visible leaf was drawn";
        break;
      }
    }
    // Interior nodes that were visible are not queried.
    EXPECT_EQ(q.issuesOf(0, frame), 0u);
    EXPECT_EQ(q.issuesOf(1, frame), 0u);
    EXPECT_EQ(q.issuesOf(6, frame), 0u);
  }
}

TEST(ChcSchedule, VisibleLeavesAreQueriedEveryNavFramesFromARandomStart) {
  const TestTree t = flatTree(20);
  ScriptedQueries q(t);
  std::set<NodeId> leaves;
  for (NodeId n = 1; n <= 20; ++n) leaves.insert(n);
  q.visible = visibleWith(t, leaves);
  CullerDesc d = desc(Method::Chc);
  d.queries.chc_visible_interval = 5;
  Culler culler(d);
  std::vector<std::vector<std::uint32_t>> frames(21);
  for (std::uint32_t frame = 1; frame <= 60; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(f.drawn.size(), 20u);
    for (NodeId n = 1; n <= 20; ++n) {
      if (q.issuesOf(n, frame)) frames[n].push_back(frame);
    }
  }
  std::set<std::uint32_t> first_gaps;
  for (NodeId n = 1; n <= 20; ++n) {
    ASSERT_GE(frames[n].size(), 3u) << "leaf " << n;
    EXPECT_EQ(frames[n][0], 1u);
    const std::uint32_t first_gap = frames[n][1] - frames[n][0];
    EXPECT_GE(first_gap, 1u);
    EXPECT_LE(first_gap, 5u);
    first_gaps.insert(first_gap);
    for (std::size_t k = 2; k < frames[n].size(); ++k) {
      EXPECT_EQ(frames[n][k] - frames[n][k - 1], 5u) << "leaf " << n;
    }
  }
  EXPECT_GE(first_gaps.size(), 3u) << "the first queries were not spread over frames";
}

TEST(ChcSchedule, InvisibleNodesAreBatchedIntoMultiQueries) {
  const TestTree t = flatTree(40);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1, 2, 3, 4});
  Culler culler(desc(Method::Chc));
  Frame f;
  for (std::uint32_t frame = 1; frame <= 10; ++frame) f = runFrame(culler, t, q, frame);
  // 36 leaves invisible for 9 frames (p = 0.99 - 0.7 e^-9 each): far fewer queries.
  std::size_t hidden_queries = 0;
  for (const QueryEvent* e : q.events(10)) {
    if (e->kind != QueryEvent::Issue) continue;
    bool hidden = false;
    for (NodeId n : e->nodes) hidden |= n > 4;
    if (!hidden) continue;
    ++hidden_queries;
    for (NodeId n : e->nodes) EXPECT_GT(n, 4u) << "a visible leaf in a multi-query";
  }
  EXPECT_GT(f.stats.multi_queries, 0u);
  EXPECT_LE(hidden_queries, 8u);
  EXPECT_EQ(f.drawn, (std::set<ObjectId>{1, 2, 3, 4}));

  // Leaf 20 turns visible: its multi-query fails, each of its nodes is queried on its
  // own, and leaf 20 is drawn in that very frame.
  q.visible = visibleWith(t, {1, 2, 3, 4, 20});
  const Frame g = runFrame(culler, t, q, 11);
  EXPECT_TRUE(g.drawn.count(20)) << "a node of a failed multi-query was not drawn";
  const QueryEvent* group = nullptr;
  for (const QueryEvent* e : q.events(11)) {
    if (e->kind == QueryEvent::Issue && std::count(e->nodes.begin(), e->nodes.end(), 20)) {
      group = e;
      break;
    }
  }
  ASSERT_NE(group, nullptr);
  ASSERT_GT(group->nodes.size(), 1u);
  for (NodeId n : group->nodes) EXPECT_EQ(q.issuesOf(n, 11), 2u) << "node " << n;
}

// ---------------------------------------------------------------------------
// nohc (Guthe et al. §4)
// ---------------------------------------------------------------------------

HardwareParameters cheapQueries() {
  HardwareParameters p;
  p.render_setup = 1e-6;
  p.render_triangle = 1e-6;  // 1000 triangles per object: 1 ms to draw one
  p.render_fragment = 1e-9;
  p.query_setup = 2e-6;
  p.query_fragment = 1e-10;
  p.query_latency = 1e-5;
  p.query_overhead = 1e-6;
  p.poll = 1e-7;
  return p;
}

TEST(NohcSchedule, NeverQueriesWhereDrawingIsCheaper) {
  const TestTree t = groupedTree(3, 4);
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {2});
  CullerDesc d = desc(Method::Nohc);
  d.queries.hardware = cheapQueries();
  d.queries.hardware.query_setup = 1.0;  // a query costs more than drawing everything
  Culler culler(d);
  for (std::uint32_t frame = 1; frame <= 5; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(f.stats.queries, 0u) << "frame " << frame;
    EXPECT_EQ(f.drawn.size(), 12u) << "frame " << frame;  // as view-frustum culling
  }
}

TEST(NohcSchedule, PreviouslyOccludedNodesAreQueriedAndWaitedFor) {
  // A large near leaf (an occluder) and six small leaves behind it.
  TestTree t;
  t.add({}, false);
  t.link(0, t.add({{-8, -6, -6}, {8, 6, -5}}, true));
  for (int i = 0; i < 6; ++i) t.link(0, t.add(rowBox(i, 6, -30), true));
  t.fitBoxes();
  ScriptedQueries q(t);
  q.visible = visibleWith(t, {1});
  CullerDesc d = desc(Method::Nohc);
  d.queries.hardware = cheapQueries();
  Culler culler(d);
  runFrame(culler, t, q, 1);  // nothing known: the small leaves are queried and drawn
  for (NodeId n = 2; n <= 7; ++n) EXPECT_EQ(q.issuesOf(n, 1), 1u) << "leaf " << n;
  for (std::uint32_t frame = 2; frame <= 5; ++frame) {
    const Frame f = runFrame(culler, t, q, frame);
    EXPECT_EQ(f.drawn, (std::set<ObjectId>{1})) << "frame " << frame;
    for (NodeId n = 2; n <= 7; ++n) EXPECT_EQ(q.issuesOf(n, frame), 1u) << "leaf " << n;
    // The occluder was visible and its query cannot pay: drawn without one.
    EXPECT_EQ(q.issuesOf(1, frame), 0u) << "frame " << frame;
  }
}

TEST(NohcSchedule, RefusesUnmeasuredHardwareParameters) {
  try {
    Culler culler(desc(Method::Nohc));
    FAIL() << "nohc without hardware parameters was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("calibrate"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------
// Wiring: the right cullFrame() form for each method.
// ---------------------------------------------------------------------------

TEST(QueryMethods, NeedTheirQuerySourceAndLogHwqItsDepthSource) {
  const TestTree t = flatTree(2);
  ScriptedQueries q(t);
  cpu::SoftwareDepthBuffer depth(200, 150, DepthConvention::Standard);
  Culler chc(desc(Method::Chc));
  EXPECT_THROW(chc.cullFrame(testCamera(), t, depth, [](ObjectId) {}), Error);
  Culler log_hwq(desc(Method::LogHwq));
  EXPECT_THROW(log_hwq.cullFrame(testCamera(), t, {nullptr, &q}, [](ObjectId) {}), Error);
  EXPECT_NO_THROW(log_hwq.cullFrame(testCamera(), t, {&depth, &q}, [](ObjectId) {}));
  CullerDesc bad = desc(Method::LogHwq);
  bad.queries.schedule = QuerySchedule(7);  // no schedule
  EXPECT_THROW(Culler{bad}, Error);
}

// ---------------------------------------------------------------------------
// End to end on the box world: every schedule, with and without the grid, against
// the oracle.
// ---------------------------------------------------------------------------

struct WorldCase {
  Method method;
  QuerySchedule schedule;  // log+hwq's
  DepthConvention convention;
  QueryShape shape;
};

class QueryWorld : public testing::TestWithParam<WorldCase> {};

struct WorldTotals {
  std::size_t visible = 0, drawn = 0, missed = 0;
  std::uint64_t queries = 0, decided = 0;
};

WorldTotals walkWorld(const test::BoxWorld& world, const CullerDesc& d, DepthConvention convention,
                      std::uint32_t frames) {
  WorldTotals t;
  Culler culler(d);
  for (std::uint32_t f = 0; f < frames; ++f) {
    const Camera cam = test::boxCamera(160, 120, convention, -0.3 + 0.04 * f);
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, convention);
    test::SoftwareQueries queries(depth);
    queries.frame = f + 1;
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    std::set<ObjectId> drawn;
    const auto draw = [&](ObjectId id) {
      test::drawBox(raster, world.boxes[id], id);
      EXPECT_TRUE(drawn.insert(id).second) << "drawn twice: " << id;
    };
    // A source the method does not need is not used: every method gets both.
    const FrameStats s = culler.cullFrame(cam, world.hierarchy, {&depth, &queries}, draw);
    const std::set<ObjectId> visible = test::visibleBoxes(world.boxes, cam);
    for (ObjectId id : visible) {
      if (!drawn.count(id)) {
        ++t.missed;
        ADD_FAILURE() << toString(d.method) << " frame " << f << ": visible box " << id
                      << " was not drawn";
      }
    }
    t.visible += visible.size();
    t.drawn += drawn.size();
    t.queries += s.queries;
    t.decided += s.records_decided;
  }
  return t;
}

TEST_P(QueryWorld, NeverMissesAVisibleBoxAndCulls) {
  const WorldCase c = GetParam();
  const test::BoxWorld world = test::makeBoxWorld(5);
  CullerDesc d = desc(c.method);
  d.tile_size = 16;
  d.queries.schedule = c.schedule;
  d.queries.shape = c.shape;
  d.queries.hardware = cheapQueries();
  const WorldTotals t = walkWorld(world, d, c.convention, 8);
  const WorldTotals vfc = walkWorld(world, desc(Method::Vfc), c.convention, 8);
  std::printf(
      "[ oracle ] %s/%s %s: visible %zu, drawn %zu (vfc %zu), queries %llu, "
      "decided by records %llu\n",
      toString(c.method), toString(c.schedule), toString(c.convention), t.visible, t.drawn,
      vfc.drawn, (unsigned long long)t.queries, (unsigned long long)t.decided);
  EXPECT_EQ(t.missed, 0u);
  EXPECT_LT(t.drawn * 10, vfc.drawn * 7) << "the queries should cull a good share here";
  if (c.method == Method::LogHwq) {
    EXPECT_GT(t.decided, 0u);
  }
}

std::vector<WorldCase> worldCases() {
  std::vector<WorldCase> out;
  for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (Method m : {Method::Hwq, Method::Chc, Method::Stat, Method::Nohc}) {
      const QuerySchedule schedule = *methodInfo(m).schedule;
      out.push_back({m, schedule, conv, QueryShape::Box});
      out.push_back({Method::LogHwq, schedule, conv, QueryShape::Box});
    }
    out.push_back({Method::Chc, QuerySchedule::Chc, conv, QueryShape::Rect});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Schedules, QueryWorld, testing::ValuesIn(worldCases()),
                         [](const testing::TestParamInfo<WorldCase>& p) {
                           std::string name = std::string(toString(p.param.method)) + "_" +
                                              toString(p.param.schedule) + "_" +
                                              toString(p.param.convention) +
                                              (p.param.shape == QueryShape::Rect ? "_rect" : "");
                           for (char& ch : name) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return name;
                         });

// chc and stat save queries against hwq on the same frames; log+hwq saves more.
TEST(QueryWorld, SchedulesIssueFewerQueriesThanStopAndWait) {
  const test::BoxWorld world = test::makeBoxWorld(5);
  auto queries = [&](Method m, QuerySchedule schedule) {
    CullerDesc d = desc(m);
    d.tile_size = 16;
    d.queries.schedule = schedule;
    return walkWorld(world, d, DepthConvention::Standard, 12).queries;
  };
  const std::uint64_t hwq = queries(Method::Hwq, QuerySchedule::Hwq);
  const std::uint64_t chc = queries(Method::Chc, QuerySchedule::Chc);
  const std::uint64_t stat = queries(Method::Stat, QuerySchedule::Stat);
  const std::uint64_t log_hwq = queries(Method::LogHwq, QuerySchedule::Hwq);
  std::printf("[ queries ] hwq %llu, chc %llu, stat %llu, log+hwq %llu\n", (unsigned long long)hwq,
              (unsigned long long)chc, (unsigned long long)stat, (unsigned long long)log_hwq);
  EXPECT_LT(chc, hwq);
  EXPECT_LT(stat, hwq);
  EXPECT_LT(log_hwq, hwq);
}

}  // namespace
}  // namespace logrid
