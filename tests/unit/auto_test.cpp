// The `auto` method against scripted costs: the per-node reasonability test (a test that
// cannot pay is skipped, one that can is run), the per-frame choice (a cheaper neighbour
// is adopted, a dearer one is not, and the setting does not flicker), the online cost
// estimate, the costs file (round trip and bad files), and auto's frames in the box world
// against the software oracle: nothing visible is ever culled.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <random>
#include <vector>

#include "auto_policy.hpp"
#include "box_world.hpp"
#include "logrid/costs.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using detail::AutoPolicy;
using detail::NodeLoad;
using detail::TestOutlook;
using detail::testPays;

// A renderer where a flush costs 100 µs and a triangle 20 ns.
CullerCosts scripted() {
  CullerCosts c;
  c.flush_s = 100e-6;
  c.pixel_s = 2e-9;
  c.box_test_s = 0.5e-6;
  c.triangle_s = 20e-9;
  c.draw_s = 2e-6;
  c.query_s = 20e-6;
  return c;
}

TEST(AutoNodeDecision, AFlushForASmallObjectDoesNotPay) {
  // One flush per test, p = 0.5: the test of a 32x32 rectangle costs ~102.5 µs; a
  // 500-triangle object draws in 12 µs: saving at most 6 µs. Drawn untested.
  const TestOutlook flushing{1.0, 1.0, 0.5};
  EXPECT_FALSE(testPays(scripted(), flushing, NodeLoad{500, 1}, 1024));
  // A 100k-triangle subtree draws in ~2 ms: half of it saved pays for the flush.
  EXPECT_TRUE(testPays(scripted(), flushing, NodeLoad{100000, 50}, 1024));
}

TEST(AutoNodeDecision, BatchedReadsMakeSmallTestsPay) {
  // The same object with one flush per 64 tests: ~4.1 µs a test against 6 µs saved.
  const TestOutlook batched{1.0 / 64, 1.0, 0.5};
  EXPECT_TRUE(testPays(scripted(), batched, NodeLoad{500, 1}, 1024));
}

TEST(AutoNodeDecision, ATestCostsThePixelsOfItsRectangle) {
  // Reads batched, a quarter of the tested rectangles read: a 32x32 box's test costs
  // ~2.6 µs and pays for a 400-triangle object (p = 0.5: 5 µs saved); the same object
  // behind a 320x240 rectangle (a large box near the camera) would read ~19,200 pixels,
  // ~40 µs: drawn untested. One average "pixels per test" would refuse the small box's
  // test wherever large boxes are tested too (at 1280x960 every rectangle is 4x larger).
  const TestOutlook quarter{1.0 / 64, 0.25, 0.5};
  EXPECT_TRUE(testPays(scripted(), quarter, NodeLoad{400, 1}, 32 * 32));
  EXPECT_FALSE(testPays(scripted(), quarter, NodeLoad{400, 1}, 320 * 240));
}

TEST(AutoNodeDecision, TestingSwitchesOffWhereNothingIsHiddenButNotForLargeSubtrees) {
  // Nothing was found occluded lately: p is held at kMinOccludedFraction, so a small
  // leaf is drawn untested while the root of a large scene is still tested, which is
  // how testing comes back where occlusion appears.
  const TestOutlook nothing_hidden{1.0 / 16, 1.0, 0.0};
  EXPECT_FALSE(testPays(scripted(), nothing_hidden, NodeLoad{2000, 1}, 1024));
  EXPECT_TRUE(testPays(scripted(), nothing_hidden, NodeLoad{1.5e6, 5000}, 1024));
  // The boundary: p x draw == test cost pays (>=), one triangle fewer does not.
  const CullerCosts c = scripted();
  const double test = detail::expectedTestSeconds(c, nothing_hidden, 1024);
  const double objects = 1;
  const double triangles =
      (test / detail::kMinOccludedFraction - objects * c.draw_s) / c.triangle_s;
  EXPECT_TRUE(testPays(c, nothing_hidden, NodeLoad{std::ceil(triangles), objects}, 1024));
  EXPECT_FALSE(testPays(c, nothing_hidden, NodeLoad{std::floor(triangles) - 1, objects}, 1024));
}

// A hierarchy of one leaf: enough for AutoPolicy::beginFrame.
class OneLeaf : public Hierarchy {
 public:
  NodeId root() const override { return 0; }
  Aabb bounds(NodeId) const override { return {{0, 0, 0}, {1, 1, 1}}; }
  std::uint32_t childCount(NodeId) const override { return 0; }
  NodeId child(NodeId, std::uint32_t) const override { return kNoNode; }
  std::uint32_t objectCount(NodeId) const override { return 1; }
  ObjectId object(NodeId, std::uint32_t) const override { return 0; }
  std::uint32_t objectTriangles(ObjectId) const override { return 300; }
};

TEST(AutoNodeDecision, EveryNodeIsTestedUntilAFrameHasShownTheCosts) {
  // The prior alone would refuse the test of a 300-triangle leaf behind a full-screen
  // rectangle; before any frame auto tests it, as the fixed methods would.
  const CullerCosts c = scripted();
  OneLeaf h;
  AutoPolicy policy;
  policy.beginFrame(h);
  EXPECT_TRUE(policy.worthTesting(h.root(), 640 * 480, c));
  // A frame that flushed for its one test, read the whole rectangle and found nothing
  // hidden: the leaf draws in ~2.3 ms (its triangles took what the test did not), so at
  // p = 0.175 a test pays up to ~0.4 ms: the full-screen one (~0.7 ms) does not, an 8x8
  // one (one flush, ~0.1 ms) does.
  FrameStats f;
  f.boxes_tested = 1;
  f.flushes = 1;
  f.pixels_read = 640 * 480;
  f.objects_drawn = 1;
  f.triangles_drawn = 300;
  f.seconds = 0.003;
  policy.noteAnswer(640 * 480, false, true);
  policy.endFrame(f, c);
  policy.beginFrame(h);
  EXPECT_FALSE(policy.worthTesting(h.root(), 640 * 480, c));
  EXPECT_TRUE(policy.worthTesting(h.root(), 8 * 8, c));
}

// ---- The per-frame choice ----

// What a frame at `s` does in a scripted scene: flushes fall with K (one per K of 1024
// boxes tested), triangles drawn grow with K (late knowledge), coherence halves the
// flushes; log-zfar flushes 1.5 times as often.
FrameStats scriptedFrame(const FrameSetting& s, double triangles_per_k) {
  FrameStats f;
  f.setting = s;
  f.boxes_tested = 1024;
  f.boxes_occluded = 256;
  double flushes = std::ceil(1024.0 / s.lookahead);
  if (s.temporal_coherence) flushes = std::ceil(flushes / 2);
  if (s.method == Method::LogZfar) flushes *= 1.5;
  f.flushes = std::uint64_t(flushes);
  f.pixels_read = f.flushes * 2048;
  f.objects_drawn = 400;
  f.triangles_drawn = std::uint64_t(100000 + triangles_per_k * s.lookahead);
  return f;
}

double scriptedSeconds(const FrameSetting& s, double triangles_per_k, const CullerCosts& c) {
  const FrameStats f = scriptedFrame(s, triangles_per_k);
  return double(f.flushes) * c.flush_s + double(f.pixels_read) * c.pixel_s +
         double(f.boxes_tested) * c.box_test_s + double(f.triangles_drawn) * c.triangle_s +
         double(f.objects_drawn) * c.draw_s;
}

// No neighbour of `s` (K one step up or down, coherence or the grid variant flipped)
// models kSwitchMargin cheaper: where the hysteresis lets the choice rest.
void expectLocalOptimum(const FrameSetting& s, double triangles_per_k, const CullerCosts& c) {
  std::vector<FrameSetting> neighbours;
  const auto& ks = AutoPolicy::kLookaheads;
  for (std::size_t i = 0; i < std::size(ks); ++i) {
    if (ks[i] != s.lookahead) continue;
    if (i + 1 < std::size(ks)) neighbours.push_back(s), neighbours.back().lookahead = ks[i + 1];
    if (i > 0) neighbours.push_back(s), neighbours.back().lookahead = ks[i - 1];
  }
  neighbours.push_back(s);
  neighbours.back().temporal_coherence = !s.temporal_coherence;
  neighbours.push_back(s);
  neighbours.back().method = s.method == Method::LogState ? Method::LogZfar : Method::LogState;
  const double here = scriptedSeconds(s, triangles_per_k, c);
  for (const FrameSetting& n : neighbours) {
    EXPECT_GE(scriptedSeconds(n, triangles_per_k, c), (1 - AutoPolicy::kSwitchMargin) * here)
        << "a cheaper neighbour was left: K " << n.lookahead << ", coherence "
        << n.temporal_coherence << ", " << toString(n.method);
  }
}

TEST(AutoFrameChoice, AdoptsACheaperNeighbourAndSettles) {
  CullerCosts c = scripted();
  c.flush_s = 1e-3;
  OneLeaf h;
  AutoPolicy policy;
  // Flushes dear (1 ms), late knowledge cheap: K climbs to the ladder's top, with
  // coherence and the variant that flushes less, and stays.
  std::uint32_t changes = 0;
  FrameSetting last = policy.current();
  for (int frame = 0; frame < 400; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    policy.endFrame(scriptedFrame(s, 1.0), c);
    if (policy.current().lookahead != last.lookahead ||
        policy.current().temporal_coherence != last.temporal_coherence ||
        policy.current().method != last.method) {
      ++changes;
      last = policy.current();
    }
  }
  EXPECT_EQ(policy.current().lookahead, 256u);
  EXPECT_TRUE(policy.current().temporal_coherence);
  EXPECT_EQ(policy.current().method, Method::LogState);
  expectLocalOptimum(policy.current(), 1.0, c);
  // Each change is a step toward the cheapest setting: no flicker back and forth.
  EXPECT_LE(changes, 5u);
}

TEST(AutoFrameChoice, AProbeIsJudgedUnderTheSameCostsAsTheFrameBeforeIt) {
  // Flushes (1 ms) and triangles (1 µs) dear while the base frames run (K = 16: ~212 ms
  // modelled); the probe (K = 64: fewer flushes, more triangles) then moves the estimate
  // so that flushes are cheap. Under the new costs the probe (~164 ms) is dearer than
  // the base frame (~116 ms) and must not be adopted, though it models far cheaper than
  // the base frame did under the old costs.
  CullerCosts dear_flush = scripted();
  dear_flush.flush_s = 1e-3;
  dear_flush.triangle_s = 1e-6;
  CullerCosts dear_triangle = dear_flush;
  dear_triangle.flush_s = 1e-6;
  OneLeaf h;
  AutoPolicy policy;
  const FrameSetting start = policy.current();
  for (int frame = 0; frame < 64; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    if (!s.probe) {
      policy.endFrame(scriptedFrame(s, 1000.0), dear_flush);
      continue;
    }
    const FrameStats probe = scriptedFrame(s, 1000.0);
    const FrameStats base = scriptedFrame(start, 1000.0);
    ASSERT_GT(probe.triangles_drawn, base.triangles_drawn);
    policy.endFrame(probe, dear_triangle);
    policy.beginFrame(h);  // the frame after the probe, at the current setting
    policy.endFrame(base, dear_triangle);
    EXPECT_EQ(policy.current().lookahead, start.lookahead) << "probe at K " << s.lookahead;
    EXPECT_EQ(policy.current().temporal_coherence, start.temporal_coherence);
    EXPECT_EQ(policy.current().method, start.method);
    break;
  }
}

TEST(AutoFrameChoice, AProbeOnACheaperViewIsNotAdopted) {
  // Late knowledge dear: on any one view K = 64 models ~1.6x the start's K = 16. The view
  // halves in cost at the probe (frames far apart on a path), so the probe beats the
  // frame before it by its view alone; the frame after it, on the same cheap view at
  // K = 16, shows it dearer.
  const CullerCosts c = scripted();
  OneLeaf h;
  AutoPolicy policy;
  const FrameSetting start = policy.current();
  auto doubled = [](FrameStats f) {
    f.flushes *= 2, f.pixels_read *= 2, f.boxes_tested *= 2;
    f.triangles_drawn *= 2, f.objects_drawn *= 2;
    return f;
  };
  bool probed = false;
  for (int frame = 0; frame < 64 && !probed; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    if (!s.probe) {
      policy.endFrame(doubled(scriptedFrame(s, 20000.0)), c);
      continue;
    }
    ASSERT_EQ(s.lookahead, 64u);
    policy.endFrame(scriptedFrame(s, 20000.0), c);
    policy.beginFrame(h);
    policy.endFrame(scriptedFrame(start, 20000.0), c);
    probed = true;
  }
  ASSERT_TRUE(probed);
  EXPECT_EQ(policy.current().lookahead, start.lookahead);
}

TEST(AutoFrameChoice, LessBatchingWhereLateKnowledgeDrawsTooMuch) {
  const CullerCosts c = scripted();
  OneLeaf h;
  AutoPolicy policy;
  // Each unit of K draws 2000 triangles more (40 µs): K = 256 would draw 512 k
  // triangles more than K = 1 (10 ms) to save a few flushes.
  for (int frame = 0; frame < 400; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    policy.endFrame(scriptedFrame(s, 2000.0), c);
  }
  EXPECT_LT(policy.current().lookahead, 256u);
  expectLocalOptimum(policy.current(), 2000.0, c);
}

TEST(AutoFrameChoice, ProbesBackOffAtALocalOptimumAndComeBackWhenTheSceneChanges) {
  const CullerCosts c = scripted();
  OneLeaf h;
  AutoPolicy policy;
  std::vector<std::size_t> probe_frames;
  auto run = [&](std::size_t frames, double triangles_per_k, double scale) {
    for (std::size_t f = 0; f < frames; ++f) {
      const FrameSetting s = policy.beginFrame(h);
      if (s.probe) probe_frames.push_back(f);
      FrameStats stats = scriptedFrame(s, triangles_per_k);
      stats.triangles_drawn = std::uint64_t(double(stats.triangles_drawn) * scale);
      policy.endFrame(stats, c);
    }
  };
  // The first probe comes on the kProbePeriod-th frame.
  run(AutoPolicy::kProbePeriod, 2000.0, 1);
  ASSERT_EQ(probe_frames.size(), 1u);
  EXPECT_EQ(probe_frames.front(), AutoPolicy::kProbePeriod - 1);
  // Settled: the probes thin out to one in kMaxProbePeriod frames.
  run(600, 2000.0, 1);
  expectLocalOptimum(policy.current(), 2000.0, c);
  EXPECT_EQ(policy.probePeriod(), AutoPolicy::kMaxProbePeriod);
  probe_frames.clear();
  run(640, 2000.0, 1);
  EXPECT_LE(probe_frames.size(), 640u / AutoPolicy::kMaxProbePeriod);
  EXPECT_GE(probe_frames.size(), 640u / AutoPolicy::kMaxProbePeriod - 1);
  // The scene turns three times dearer to draw: the probes come back at once, one per
  // kProbePeriod frames (at kMaxProbePeriod there would be at most one in these frames).
  probe_frames.clear();
  run(2 * AutoPolicy::kProbePeriod, 2000.0, 3);
  EXPECT_GE(probe_frames.size(), 2u);
  EXPECT_EQ(policy.probePeriod(), AutoPolicy::kProbePeriod);
}

// The frame `s` of the scripted scene with its visible set: `kept` of 100 visible nodes
// with objects were visible the frame before.
FrameStats framedViews(const FrameSetting& s, double triangles_per_k, std::uint64_t kept) {
  FrameStats f = scriptedFrame(s, triangles_per_k);
  f.visible_leaves = 100;
  f.visible_kept = kept;
  return f;
}

// The frames on which the policy probed, and with what, over `frames` frames.
std::vector<std::pair<int, FrameSetting>> probesOver(AutoPolicy& policy, int frames,
                                                     std::uint64_t kept, const CullerCosts& c) {
  OneLeaf h;
  std::vector<std::pair<int, FrameSetting>> probes;
  for (int frame = 0; frame < frames; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    if (s.probe) probes.emplace_back(frame, s);
    policy.endFrame(framedViews(s, 1.0, kept), c);
  }
  return probes;
}

TEST(AutoFrameChoice, CoherentViewsTryCoherenceAtOnce) {
  // 95 of 100 visible nodes were visible the frame before: coherence is probed as soon
  // as the second frame has shown it (the third frame), not on the kProbePeriod-th, and
  // with dear flushes (coherence halves them) it is adopted at once.
  CullerCosts c = scripted();
  c.flush_s = 1e-3;
  AutoPolicy coherent;
  const auto probes = probesOver(coherent, 4, 95, c);
  ASSERT_EQ(probes.size(), 1u);
  EXPECT_EQ(probes[0].first, 2);
  EXPECT_TRUE(probes[0].second.temporal_coherence);
  EXPECT_TRUE(coherent.current().temporal_coherence);
  EXPECT_NEAR(coherent.keptShare(), 0.95, 1e-9);
  // Views that change (20 of 100 kept): nothing out of turn; the first probe is K's, on
  // the kProbePeriod-th frame.
  AutoPolicy incoherent;
  const auto turns = probesOver(incoherent, int(AutoPolicy::kProbePeriod), 20, c);
  ASSERT_EQ(turns.size(), 1u);
  EXPECT_EQ(turns[0].first, int(AutoPolicy::kProbePeriod) - 1);
  EXPECT_FALSE(turns[0].second.temporal_coherence);
  EXPECT_FALSE(incoherent.current().temporal_coherence);
}

TEST(AutoFrameChoice, AStepOfKThatWonIsTriedAgainAtOnce) {
  // Flushes dear, views not coherent: K = 64 wins on the kProbePeriod-th frame, and
  // K = 256 is probed on the second frame after the one that adopted it, not a probe
  // period later.
  CullerCosts c = scripted();
  c.flush_s = 1e-3;
  AutoPolicy policy;
  const int first = int(AutoPolicy::kProbePeriod) - 1;
  const auto probes = probesOver(policy, first + 4, 0, c);
  ASSERT_EQ(probes.size(), 2u);
  EXPECT_EQ(probes[0].first, first);
  EXPECT_EQ(probes[0].second.lookahead, 64u);
  EXPECT_EQ(probes[1].first, first + 2);
  EXPECT_EQ(probes[1].second.lookahead, 256u);
  EXPECT_EQ(policy.current().lookahead, 256u);
}

// Runs `frames` frames of the scripted scene with flushes dear (coherence models half
// as dear), `kept` of 100 visible nodes kept from frame to frame, each frame taking
// `plain_s` seconds without coherence and `coherent_s` with it. Returns the settings run.
std::vector<FrameSetting> timedFrames(AutoPolicy& policy, int frames, std::uint64_t kept,
                                      double plain_s, double coherent_s) {
  CullerCosts c = scripted();
  c.flush_s = 1e-3;
  OneLeaf h;
  std::vector<FrameSetting> run;
  for (int frame = 0; frame < frames; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    run.push_back(s);
    FrameStats f = framedViews(s, 1.0, kept);
    f.seconds = s.temporal_coherence ? coherent_s : plain_s;
    policy.endFrame(f, c);
  }
  return run;
}

TEST(AutoFrameChoice, ASwitchTheFramesOwnTimeDoesNotBearOutIsTakenBack) {
  // Coherent views: coherence, probed on the third frame, models cheaper and runs from the
  // fifth (the fourth judges the probe), but its frames take 1.4x as long (as on a loaded
  // machine): after the trial it is taken back.
  const int trial_end = 4 + int(AutoPolicy::kTrialSkip + AutoPolicy::kTrialFrames);
  AutoPolicy slower;
  const std::vector<FrameSetting> run = timedFrames(slower, trial_end + 1, 95, 0.050, 0.070);
  EXPECT_TRUE(run[2].temporal_coherence && run[2].probe);
  EXPECT_TRUE(run[4].temporal_coherence);
  EXPECT_TRUE(run[std::size_t(trial_end) - 1].temporal_coherence);
  EXPECT_FALSE(run[std::size_t(trial_end)].temporal_coherence);
  EXPECT_FALSE(slower.current().temporal_coherence);
  EXPECT_EQ(slower.reverts(), 1u);
  // No probe during the trial.
  for (int f = 4; f < trial_end; ++f) EXPECT_FALSE(run[std::size_t(f)].probe) << f;
  // Its frames as fast as the model says, or within the margin: kept.
  for (double coherent_s : {0.030, 0.054}) {
    AutoPolicy kept;
    timedFrames(kept, trial_end + 1, 95, 0.050, coherent_s);
    EXPECT_TRUE(kept.current().temporal_coherence) << coherent_s;
    EXPECT_EQ(kept.reverts(), 0u);
  }
}

TEST(AutoFrameChoice, WhereTheViewsChangeTheModelAloneJudges) {
  // 20 of 100 kept: frames far apart differ by their views more than by their settings;
  // K = 64 wins by the model and stays though its frames took longer.
  AutoPolicy policy;
  CullerCosts c = scripted();
  c.flush_s = 1e-3;
  OneLeaf h;
  for (int frame = 0; frame < 40; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    FrameStats f = framedViews(s, 1.0, 20);
    f.seconds = s.lookahead > 16 ? 0.070 : 0.050;
    policy.endFrame(f, c);
  }
  EXPECT_GT(policy.current().lookahead, 16u);
  EXPECT_EQ(policy.reverts(), 0u);
}

TEST(AutoFrameChoice, TheFrameAfterAProbeIsJudgedUnderTheProbesCosts) {
  // Flushes dear (1 ms) at the probe: K = 64 models far cheaper than K = 16. The frame
  // after it moves the estimate so that flushes look nearly free (as one slow frame on
  // a loaded machine did); it is judged with the probe under the costs of the probe, and
  // the probe is adopted.
  CullerCosts dear_flush = scripted();
  dear_flush.flush_s = 1e-3;
  CullerCosts cheap_flush = dear_flush;
  cheap_flush.flush_s = 1e-7;
  OneLeaf h;
  AutoPolicy policy;
  FrameSetting k64 = policy.current();
  k64.lookahead = 64;
  // Under the costs the frame after would bring, the probe would lose.
  ASSERT_GE(scriptedSeconds(k64, 1.0, cheap_flush),
            (1 - AutoPolicy::kSwitchMargin) * scriptedSeconds(policy.current(), 1.0, cheap_flush));
  const FrameSetting start = policy.current();
  for (int frame = 0; frame < 64; ++frame) {
    const FrameSetting s = policy.beginFrame(h);
    policy.endFrame(scriptedFrame(s, 1.0), dear_flush);
    if (!s.probe) continue;
    ASSERT_EQ(s.lookahead, 64u);
    policy.beginFrame(h);  // the frame after the probe, at the current setting
    policy.endFrame(scriptedFrame(start, 1.0), cheap_flush);
    break;
  }
  EXPECT_EQ(policy.current().lookahead, 64u);
}

TEST(AutoFrameChoice, FreeVisibleAnswersDoNotDragTheOccludedFractionDown) {
  // A frame's counts say 1000 tests and nothing occluded, but most were answered visible
  // on tiles nothing was drawn on; of the answers that were evidence, half were occluded.
  const CullerCosts c = scripted();
  OneLeaf h;
  AutoPolicy policy;
  FrameStats f;
  f.boxes_tested = 1000;
  f.flushes = 10;
  for (int frame = 0; frame < 30; ++frame) {
    policy.beginFrame(h);
    for (int i = 0; i < 10; ++i) policy.noteAnswer(1024, i % 2 == 0, true);
    for (int i = 0; i < 990; ++i) policy.noteAnswer(1024, false, false);
    policy.endFrame(f, c);
  }
  EXPECT_NEAR(policy.outlook().occluded_fraction, 0.5, 0.01);
  // Frames whose answers were all free leave it where it was.
  for (int frame = 0; frame < 30; ++frame) {
    policy.beginFrame(h);
    policy.endFrame(f, c);
  }
  EXPECT_NEAR(policy.outlook().occluded_fraction, 0.5, 0.01);
}

// ---- The online estimate ----

TEST(CostEstimate, ConvergesToTheCostsThatMadeTheFrames) {
  const CullerCosts truth = scripted();
  CullerCosts prior = truth;
  prior.flush_s *= 3;
  prior.triangle_s /= 2;
  CostEstimate estimate(prior);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> flushes(1, 100), tests(100, 900), objects(100, 1200);
  std::uniform_int_distribution<int> triangles(50000, 400000), pixels(10000, 800000);
  for (int i = 0; i < 300; ++i) {
    FrameStats f;
    f.flushes = std::uint64_t(flushes(rng));
    f.pixels_read = std::uint64_t(pixels(rng));
    f.boxes_tested = std::uint64_t(tests(rng));
    f.triangles_drawn = std::uint64_t(triangles(rng));
    f.objects_drawn = std::uint64_t(objects(rng));
    f.seconds = double(f.flushes) * truth.flush_s + double(f.pixels_read) * truth.pixel_s +
                double(f.boxes_tested) * truth.box_test_s +
                double(f.triangles_drawn) * truth.triangle_s +
                double(f.objects_drawn) * truth.draw_s;
    estimate.update(f);
  }
  EXPECT_EQ(estimate.frames(), 300u);
  EXPECT_NEAR(estimate.costs().flush_s / truth.flush_s, 1.0, 0.15);
  EXPECT_NEAR(estimate.costs().triangle_s / truth.triangle_s, 1.0, 0.15);
  // Queries never happened: their cost stays the prior's.
  EXPECT_DOUBLE_EQ(estimate.costs().query_s, prior.query_s);
}

TEST(CostEstimate, IgnoresFramesWithoutATime) {
  CostEstimate estimate(scripted());
  FrameStats f;
  f.flushes = 10;
  f.seconds = std::nan("");
  estimate.update(f);
  EXPECT_EQ(estimate.frames(), 0u);
  EXPECT_DOUBLE_EQ(estimate.costs().flush_s, scripted().flush_s);
}

// ---- The costs file ----

TEST(CostsFile, RoundTrip) {
  CullerCostsFile file;
  file.machine = "llvmpipe \"test\"";
  file.sources["readpixels"] = scripted();
  CullerCosts pbo = scripted();
  pbo.flush_s = 3.5e-5;
  file.sources["pbo"] = pbo;
  const CullerCostsFile back = parseCullerCosts(formatCullerCosts(file), "round trip");
  EXPECT_EQ(back.machine, file.machine);
  ASSERT_EQ(back.sources.size(), 2u);
  EXPECT_NEAR(back.sources.at("pbo").flush_s, 3.5e-5, 1e-12);
  EXPECT_NEAR(back.sources.at("readpixels").triangle_s, 20e-9, 1e-15);
}

// What the config fuzzer found: costs written with six digits, and a source name written
// without escaping its quotes (a file calibrate could not read back).
TEST(CostsFile, EveryCostAndNameReadsBackExactly) {
  CullerCostsFile file;
  file.machine = "llvmpipe\n\t\"x\"\x01";
  CullerCosts odd = scripted();
  odd.flush_s = 1.0 / 3.0;
  odd.pixel_s = 4.9406564584124654e-324;  // the least denormal
  odd.box_test_s = std::nextafter(1.0, 0.0);
  file.sources["a \"quoted\" \\ name"] = odd;
  file.sources["tab\tname"] = scripted();
  const CullerCostsFile back = parseCullerCosts(formatCullerCosts(file), "round trip");
  EXPECT_EQ(back.machine, file.machine);
  ASSERT_EQ(back.sources.size(), file.sources.size());
  for (const auto& [name, costs] : file.sources) {
    ASSERT_EQ(back.sources.count(name), 1u) << name;
    const CullerCosts& b = back.sources.at(name);
    EXPECT_EQ(b.flush_s, costs.flush_s) << name;
    EXPECT_EQ(b.pixel_s, costs.pixel_s) << name;
    EXPECT_EQ(b.box_test_s, costs.box_test_s) << name;
    EXPECT_EQ(b.triangle_s, costs.triangle_s) << name;
    EXPECT_EQ(b.draw_s, costs.draw_s) << name;
    EXPECT_EQ(b.query_s, costs.query_s) << name;
  }
}

void expectBad(const std::string& text, const std::string& says) {
  try {
    parseCullerCosts(text, "c.json");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadInput);
    const std::string what = e.what();
    EXPECT_NE(what.find("c.json"), std::string::npos) << what;
    EXPECT_NE(what.find(says), std::string::npos) << what;
  }
}

TEST(CostsFile, BadFilesAreRefusedWithTheReason) {
  const std::string good_set =
      "{\"flush_s\": 1e-4, \"pixel_s\": 2e-9, \"box_test_s\": 5e-7, \"triangle_s\": 2e-8, "
      "\"draw_s\": 2e-6, \"query_s\": 2e-5}";
  const auto file = [](const std::string& sources) {
    return "{\"format\": \"logrid-costs\", \"version\": 1, \"sources\": " + sources + "}";
  };
  parseCullerCosts(file("{\"readpixels\": " + good_set + "}"), "c.json");  // the base is good
  expectBad("", "not a costs file");
  expectBad("{\"format\": \"logrid-costs\", ", "not a costs file");
  expectBad("[1, 2]", "one JSON object");
  expectBad("{\"format\": \"other\", \"version\": 1}", "\"format\"");
  expectBad("{\"format\": \"logrid-costs\", \"version\": 2, \"sources\": {}}", "\"version\"");
  expectBad(file("{}"), "no depth source");
  expectBad(file("{\"readpixels\": {\"flush_s\": 1e-4}}"), "has no \"pixel_s\"");
  std::string negative = good_set;
  negative.replace(negative.find("1e-4"), 4, "-1e-4");
  expectBad(file("{\"readpixels\": " + negative + "}"), "flush_s = -0.0001");
  std::string text = good_set;
  text.replace(text.find("2e-9"), 4, "\"fast\"");
  expectBad(file("{\"pbo\": " + text + "}"), "\"pixel_s\" is not a number");
  // A source given twice (the configuration reader and this one would disagree on which
  // counts): refused, as every key given twice in one object.
  expectBad(file("{\"pbo\": " + good_set + ", \"pbo\": " + good_set + "}"),
            "the key \"pbo\" twice");
}

TEST(CostsFile, AnUnreadableFileOrAMissingSourceSaysWhat) {
  try {
    loadCullerCosts("/nonexistent/costs.json", "readpixels");
    ADD_FAILURE() << "a missing file was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Environment);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/costs.json"), std::string::npos);
  }
  CullerCostsFile file;
  file.sources["pbo"] = scripted();
  const std::string path = testing::TempDir() + "logrid_costs_test.json";
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const std::string text = formatCullerCosts(file);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  EXPECT_NEAR(loadCullerCosts(path, "pbo").flush_s, 100e-6, 1e-12);
  try {
    loadCullerCosts(path, "readpixels");
    ADD_FAILURE() << "a source the file lacks was given";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the file has pbo"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(CostsFile, TheCullerRefusesInvalidCosts) {
  CullerDesc d;
  d.method = Method::Auto;
  d.costs.triangle_s = 0;
  EXPECT_NE(validateCullerDesc(d).find("triangle_s"), std::string::npos);
  EXPECT_THROW(Culler{d}, Error);
}

// ---- auto in the box world ----

// Every frame, both conventions, each source kind: auto draws every visible box, and
// its choices show in FrameStats::setting.
TEST(AutoCuller, NoVisibleBoxIsCulledWhateverItChooses) {
  const test::BoxWorld world = test::makeBoxWorld(3);
  for (DepthConvention conv : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (test::SourceKind kind : {test::SourceKind::Software, test::SourceKind::Batched}) {
      for (double box_test_s : {1e-7, 1e-2}) {  // tests cheap, tests dear
        SCOPED_TRACE(std::string(toString(conv)) + " " + test::toString(kind) + " test " +
                     std::to_string(box_test_s));
        CullerDesc d;
        d.method = Method::Auto;
        d.tile_size = 8;
        d.costs.box_test_s = box_test_s;
        Culler culler(d);
        std::uint64_t tested = 0, untested = 0, occluded = 0, probes = 0;
        std::set<Method> methods;
        for (int frame = 0; frame < 24; ++frame) {
          const Camera cam = test::boxCamera(160, 120, conv, -0.4 + 0.035 * frame);
          cpu::SoftwareDepthBuffer depth(cam.width, cam.height, conv);
          const test::CulledFrame f = test::cullBoxes(culler, world, cam, depth, kind);
          for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
            EXPECT_TRUE(f.drawn.count(id)) << "frame " << frame << ": visible box " << id
                                           << " culled with K = " << f.stats.setting.lookahead;
          }
          tested += f.stats.boxes_tested;
          untested += f.stats.boxes_untested;
          occluded += f.stats.boxes_occluded;
          methods.insert(f.stats.setting.method);
          probes += f.stats.setting.probe;
          EXPECT_TRUE(f.stats.setting.method == Method::LogState ||
                      f.stats.setting.method == Method::LogZfar);
        }
        if (box_test_s < 1e-6) {
          // Tests nearly free: auto tests and culls.
          EXPECT_GT(occluded, 0u);
        } else {
          // 10 ms a test against boxes of an assumed 1000 triangles each: testing
          // switches itself off but for the largest subtrees (the online estimate may
          // find the software rasteriser's drawing dear enough for the root's test).
          EXPECT_GT(untested, 10 * tested);
        }
        // The estimate learns from every frame but auto's probes.
        EXPECT_GT(probes, 0u);
        EXPECT_EQ(culler.costEstimate().frames(), 24u - probes);
      }
    }
  }
}

TEST(AutoCuller, CountsTheVisibleNodesTheFrameBeforeSawToo) {
  // The same view twice: every visible node with objects is kept; a first frame keeps
  // none; a method that keeps no visible set counts nothing.
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0.1);
  for (Method method : {Method::Auto, Method::LogState}) {
    SCOPED_TRACE(toString(method));
    CullerDesc d;
    d.method = method;
    d.tile_size = 8;
    Culler culler(d);
    std::vector<FrameStats> frames;
    for (int frame = 0; frame < 2; ++frame) {
      cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
      frames.push_back(
          test::cullBoxes(culler, world, cam, depth, test::SourceKind::Software).stats);
    }
    EXPECT_EQ(frames[0].visible_kept, 0u);
    if (method == Method::Auto) {
      EXPECT_GT(frames[0].visible_leaves, 0u);
      EXPECT_EQ(frames[1].visible_kept, frames[1].visible_leaves);
      EXPECT_EQ(frames[1].visible_leaves, frames[0].visible_leaves);
    } else {
      EXPECT_EQ(frames[1].visible_leaves, 0u);
      EXPECT_EQ(frames[1].visible_kept, 0u);
    }
  }
}

TEST(AutoCuller, TakesNoApproximateKnob) {
  CullerDesc d;
  d.method = Method::Auto;
  d.approximation.visible_pixels = 4;
  EXPECT_NE(validateCullerDesc(d), "");
  d.approximation = {};
  d.approximation.row_stride = 2;
  EXPECT_NE(validateCullerDesc(d), "");
}

}  // namespace
}  // namespace logrid
