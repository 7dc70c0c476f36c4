// The frame-time budget (CullerDesc::budget_ms; log/src/budget.hpp) against scripted frame
// times: it meets a reachable budget, returns to exact when there is time, does not
// oscillate between two rungs that straddle the budget, and stays at the last rung of
// an unreachable one; and the culler with a budget records the knobs it ran with.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "box_world.hpp"
#include "budget.hpp"
#include "expect_error.hpp"
#include "logrid/culler.hpp"

namespace logrid {
namespace {

using detail::BudgetController;
using detail::BudgetRung;

// A ladder of `priors.size()` rungs (the first exact), each with its prior ratio.
std::vector<BudgetRung> ladderOf(const std::vector<double>& priors) {
  std::vector<BudgetRung> ladder(priors.size());
  for (std::size_t i = 0; i < priors.size(); ++i) {
    ladder[i].approximation.full_free_fraction = float(i) * 0.05f;
    ladder[i].ratio = priors[i];
  }
  return ladder;
}

struct Scripted {
  std::size_t over = 0;     // frames over the budget
  std::size_t changes = 0;  // rung changes
  std::vector<std::size_t> rungs;
};

// `frames` frames whose time is exact_ms x truth[rung] x (1 + noise) (uniform in +-noise).
Scripted script(BudgetController& c, double exact_ms, const std::vector<double>& truth,
                double budget_ms, std::size_t frames, double noise = 0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  Scripted r;
  for (std::size_t f = 0; f < frames; ++f) {
    const std::size_t rung = c.rung();
    const double ms = exact_ms * truth[rung] * (1 + jitter(rng));
    r.over += ms > budget_ms;
    r.rungs.push_back(rung);
    c.endFrame(ms * 1e-3);
    r.changes += c.rung() != rung;
  }
  return r;
}

const std::vector<double> kRatios = {1, 0.9, 0.8, 0.7, 0.6};

TEST(Budget, TheLaddersAreTheMeasuredFrontsAtTheCullersSetting) {
  const MethodInfo& state = methodInfo(Method::LogState);
  // Without coherence: the full-tile fraction, then visible pixels.
  const auto plain = detail::budgetLadder(state, false);
  ASSERT_EQ(plain.size(), 6u);
  EXPECT_TRUE(plain.front().approximation.exact());
  EXPECT_EQ(plain.front().ratio, 1.0);
  for (std::size_t i = 1; i < plain.size(); ++i) {
    EXPECT_LT(plain[i].ratio, plain[i - 1].ratio);
    EXPECT_FALSE(plain[i].approximation.exact());
  }
  EXPECT_GT(plain[4].approximation.full_free_fraction, plain[1].approximation.full_free_fraction);
  EXPECT_EQ(plain.back().approximation.visible_pixels, 256u);
  // With coherence the full-tile fraction buys nothing (depth tests): visible pixels only.
  const auto coherent = detail::budgetLadder(state, true);
  ASSERT_EQ(coherent.size(), 4u);
  for (std::size_t i = 1; i < coherent.size(); ++i) {
    EXPECT_EQ(coherent[i].approximation.full_free_fraction, 0.0f);
    EXPECT_GT(coherent[i].approximation.visible_pixels,
              coherent[i - 1].approximation.visible_pixels);
  }
  // log-zfar takes visible pixels only; methods without a grid take no budget.
  EXPECT_EQ(detail::budgetLadder(methodInfo(Method::LogZfar), false).size(), 4u);
  EXPECT_TRUE(detail::budgetLadder(methodInfo(Method::Vfc), false).empty());
  EXPECT_TRUE(detail::budgetLadder(methodInfo(Method::Hwq), false).empty());
}

TEST(Budget, MeetsAReachableBudgetFromTheFirstFrameOverIt) {
  BudgetController c(7.5e-3, ladderOf(kRatios));
  const Scripted r = script(c, 10, kRatios, 7.5, 400);
  // 10 ms over 7.5: the rung predicted under 0.95 x 7.5 ms is the 7 ms one, at once.
  EXPECT_EQ(r.rungs[1], 3u);
  EXPECT_EQ(r.rungs.back(), 3u);
  // Tries towards exact are rare and each costs a frame over the budget.
  EXPECT_LE(r.over, 400u / 20);  // at least 95 % of frames within the budget
  EXPECT_LE(r.changes, 1u + 2u * 8u);
}

TEST(Budget, LearnsTheRatiosItsPriorsGotWrong) {
  // The priors promise 0.9 ... 0.6; the frames give 0.97 ... 0.88.
  const std::vector<double> truth = {1, 0.97, 0.94, 0.91, 0.88};
  BudgetController c(9.2e-3, ladderOf(kRatios));
  const Scripted r = script(c, 10, truth, 9.2, 400);
  // 9.1 ms is the only rung under 9.2 ms but the last: found within a few frames.
  for (std::size_t f = 20; f < r.rungs.size(); ++f) EXPECT_GE(r.rungs[f], 3u) << "frame " << f;
  EXPECT_LE(r.over, 400u / 20);
  EXPECT_EQ(r.rungs.back(), 3u);  // not the last rung, which it does not need
}

TEST(Budget, ReturnsToExactWhenThereIsTime) {
  BudgetController c(7.5e-3, ladderOf(kRatios));
  script(c, 10, kRatios, 7.5, 100);
  ASSERT_GT(c.rung(), 0u);
  // The scene became cheaper: exact now under (1 - margin) x budget.
  const Scripted r = script(c, 5, kRatios, 7.5, 200);
  EXPECT_EQ(r.rungs.back(), 0u);
  EXPECT_TRUE(c.current().exact());
  EXPECT_EQ(r.over, 0u);
}

TEST(Budget, DoesNotOscillateBetweenRungsThatStraddleTheBudget) {
  // Exact over the budget, the first rung well under it: a naive controller would flip
  // every few frames. The hold doubles after each step down that had to be undone.
  const std::vector<double> truth = {1, 0.6, 0.55, 0.5, 0.45};
  BudgetController c(8e-3, ladderOf(truth));
  const Scripted r = script(c, 10, truth, 8, 2000);
  // Two changes per try: one per doubling of the hold (4 to 256: 7), then one try per
  // 256 frames (under 8 in 2000).
  EXPECT_LE(r.changes, 1u + 2u * (7u + 8u));
  EXPECT_LE(r.over, 2000u / 20);
  for (std::size_t f = 100; f < r.rungs.size(); ++f) EXPECT_LE(r.rungs[f], 1u);
}

TEST(Budget, NoisyFramesStillSettle) {
  const std::vector<double> truth = {1, 0.92, 0.84, 0.76, 0.68};
  BudgetController c(8.5e-3, ladderOf(truth));
  const Scripted r = script(c, 10, truth, 8.5, 1000, 0.1, 7);
  EXPECT_LE(r.changes, 60u);
  std::size_t exact_late = 0;
  for (std::size_t f = 500; f < r.rungs.size(); ++f) exact_late += r.rungs[f] == 0;
  EXPECT_LT(exact_late, 50u);  // 10 ms frames are over 8.5 ms even with the noise
  EXPECT_LE(r.over, 1000u / 10);
}

TEST(Budget, OneSlowFrameMovesNothingTwoInARowDo) {
  BudgetController c(12e-3, ladderOf(kRatios));
  for (int f = 0; f < 200; ++f) {
    c.endFrame(f % 50 == 25 ? 30e-3 : 10e-3);  // a hitch every 50 frames
    EXPECT_EQ(c.rung(), 0u) << "frame " << f;
  }
  c.endFrame(30e-3);
  c.endFrame(30e-3);
  EXPECT_GT(c.rung(), 0u);
}

TEST(Budget, AnUnreachableBudgetGoesToTheFastestRungAtOnceAndStays) {
  BudgetController c(1e-3, ladderOf(kRatios));
  const Scripted r = script(c, 10, kRatios, 1, 100);
  EXPECT_EQ(r.rungs[1], 4u);
  EXPECT_EQ(r.rungs.back(), 4u);
  EXPECT_EQ(r.changes, 1u);
}

TEST(Budget, ARungThatBuysNothingIsNotPaidForInAccuracy) {
  // The knob has no reach at this setting (every rung as slow as exact): the controller
  // tries the ladder, learns that, and spends its frames exact.
  const std::vector<double> truth = {1, 1, 1, 1, 1};
  BudgetController c(8e-3, ladderOf(kRatios));
  const Scripted r = script(c, 10, truth, 8, 1000);
  std::size_t exact_late = 0;
  for (std::size_t f = 500; f < r.rungs.size(); ++f) exact_late += r.rungs[f] == 0;
  EXPECT_GT(exact_late, 450u);
  EXPECT_LE(r.changes, 40u);
}

TEST(BudgetCuller, ValidatesAndRecordsTheKnobsEachFrameRan) {
  CullerDesc d;
  d.method = Method::LogState;
  d.budget_ms = -1;
  EXPECT_NE(validateCullerDesc(d).find("budget -1 ms is invalid"), std::string::npos);
  d.budget_ms = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(validateCullerDesc(d), "");
  d.budget_ms = 5;
  d.method = Method::Vfc;  // has no grid
  EXPECT_NE(validateCullerDesc(d).find("cannot meet a frame-time budget"), std::string::npos);
  d.method = Method::LogZfar;  // visible pixels
  EXPECT_EQ(validateCullerDesc(d), "");
  d.method = Method::LogState;
  d.approximation.row_stride = 2;
  EXPECT_NE(validateCullerDesc(d).find("leave CullerDesc::approximation exact"), std::string::npos);
  d.approximation = {};
  EXPECT_EQ(validateCullerDesc(d), "");

  // A budget no frame can meet: the culler goes to the fastest rung after the first frame,
  // and each frame's FrameStats::setting says what it ran. The application reports the
  // frame times (deterministic, unlike the culled pass's own): 10 ms x the rung's ratio.
  d.budget_ms = 1e-9;
  d.frame_clock = FrameClock::ReportedFrame;
  d.tile_size = 8;
  Culler culler(d);
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0);
  const std::vector<BudgetRung> ladder = detail::budgetLadder(methodInfo(Method::LogState), false);
  for (int frame = 0; frame < 12; ++frame) {
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
    const test::CulledFrame f =
        test::cullBoxes(culler, world, cam, depth, test::SourceKind::Software);
    const GridApproximation& ran = f.stats.setting.approximation;
    const auto rung = std::find_if(ladder.begin(), ladder.end(), [&](const BudgetRung& r) {
      return r.approximation.visible_pixels == ran.visible_pixels &&
             r.approximation.full_free_fraction == ran.full_free_fraction &&
             r.approximation.row_stride == ran.row_stride;
    });
    ASSERT_NE(rung, ladder.end()) << "frame " << frame << " ran a setting off the ladder";
    EXPECT_EQ(rung - ladder.begin(), frame == 0 ? 0 : std::ptrdiff_t(ladder.size() - 1))
        << "frame " << frame;
    culler.reportFrameTime(0.01 * rung->ratio);
  }

  // A budget every frame meets: always exact, and every visible box drawn.
  d.budget_ms = 1e6;
  d.frame_clock = FrameClock::CulledPass;
  Culler easy(d);
  for (int frame = 0; frame < 12; ++frame) {
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
    const test::CulledFrame f =
        test::cullBoxes(easy, world, cam, depth, test::SourceKind::Software);
    EXPECT_TRUE(f.stats.setting.approximation.exact());
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) EXPECT_TRUE(f.drawn.count(id));
  }
}

// One frame of a 3 x 3 box world at 160x120 through the software rasteriser.
FrameStats boxFrame(Culler& culler) {
  static const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
  return test::cullBoxes(culler, world, cam, depth, test::SourceKind::Software).stats;
}

TEST(BudgetCuller, AReportedFrameClockTakesTheApplicationsTimes) {
  CullerDesc d;
  d.method = Method::LogState;
  d.tile_size = 8;
  // The culled pass of the box world takes milliseconds; the budget is far above what
  // it could take on a loaded machine (the own-clock part below reads the wall clock).
  d.budget_ms = 2000;
  d.frame_clock = FrameClock::ReportedFrame;
  // Whole frames of 5 s (say, a slow present): over the budget, so it approximates,
  // though the culled pass alone is well within it.
  Culler reported(d);
  for (int i = 0; i < 3; ++i) {
    boxFrame(reported);
    reported.reportFrameTime(5.0);
  }
  EXPECT_FALSE(boxFrame(reported).setting.approximation.exact());
  // The culled pass's own clock with the same reports: they are ignored, it stays exact.
  d.frame_clock = FrameClock::CulledPass;
  Culler own(d);
  for (int i = 0; i < 3; ++i) {
    boxFrame(own);
    own.reportFrameTime(5.0);
  }
  EXPECT_TRUE(boxFrame(own).setting.approximation.exact());
  // Bad times are refused, naming the call.
  test::expectError([&] { own.reportFrameTime(-1); }, ErrorCode::InvalidArgument,
                    {"Culler::reportFrameTime", "not a frame time"});
  test::expectError([&] { own.reportFrameTime(std::numeric_limits<double>::infinity()); },
                    ErrorCode::InvalidArgument, {"not a frame time"});
  // With ReportedFrame: each frame once, after its endFrame.
  d.frame_clock = FrameClock::ReportedFrame;
  Culler strict(d);
  test::expectError([&] { strict.reportFrameTime(0.01); }, ErrorCode::InvalidArgument,
                    {"no frame ended"});
  boxFrame(strict);
  strict.reportFrameTime(0.01);
  test::expectError([&] { strict.reportFrameTime(0.01); }, ErrorCode::InvalidArgument,
                    {"report each frame once"});
  d.frame_clock = FrameClock(7);
  EXPECT_NE(validateCullerDesc(d).find("frame_clock 7"), std::string::npos);
}

TEST(FrameClockCuller, TheCostEstimateLearnsFromTheReportedTimeOrTheCulledPass) {
  CullerDesc d;
  d.method = Method::LogState;
  d.tile_size = 8;
  d.frame_clock = FrameClock::ReportedFrame;
  // Learnt from when the time comes: the report, or the next frame's start without one.
  // The same frames reported at 15 ms and at 5 ms: the estimates follow the reports (the
  // culled passes, alike for both, do not enter), deterministically.
  Culler slow(d), fast(d);
  FrameStats last = boxFrame(slow);
  EXPECT_EQ(slow.costEstimate().frames(), 0u);
  slow.reportFrameTime(0.015);
  EXPECT_EQ(slow.costEstimate().frames(), 1u);
  for (int i = 0; i < 30; ++i) {
    last = boxFrame(slow);
    slow.reportFrameTime(0.015);
    boxFrame(fast);
    fast.reportFrameTime(0.005);
  }
  EXPECT_EQ(slow.costEstimate().frames(), 31u);
  EXPECT_GT(slow.costEstimate().predict(last), 1.5 * fast.costEstimate().predict(last));
  boxFrame(slow);
  boxFrame(slow);  // the frame before, unreported, was taken at its culled pass's time
  EXPECT_EQ(slow.costEstimate().frames(), 32u);
}

}  // namespace
}  // namespace logrid
