// The frame-time budget (CullerDesc::budget_ms; log/src/budget.hpp) against scripted frame
// times: it meets a reachable budget, returns to exact when there is time, does not
// oscillate between two rungs that straddle the budget, and stays at the last rung of
// an unreachable one; and the culler with a budget records the knobs it ran with.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "box_world.hpp"
#include "budget.hpp"
#include "logrid/culler.hpp"

namespace logrid {
namespace {

using detail::BudgetController;

struct Scripted {
  std::size_t over = 0;     // frames over the budget
  std::size_t changes = 0;  // rung changes
  std::vector<std::size_t> rungs;
};

// `frames` frames whose time is rung_ms[rung] x (1 + noise) (uniform in +-noise).
Scripted script(BudgetController& c, const std::vector<double>& rung_ms, double budget_ms,
                std::size_t frames, double noise = 0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  Scripted r;
  for (std::size_t f = 0; f < frames; ++f) {
    const std::size_t rung = c.rung();
    const double ms = rung_ms[rung] * (1 + jitter(rng));
    r.over += ms > budget_ms;
    r.rungs.push_back(rung);
    c.endFrame(ms * 1e-3);
    r.changes += c.rung() != rung;
  }
  return r;
}

TEST(Budget, TheLadderIsThePaperFrontOfTheFullTileFraction) {
  const auto ladder = detail::budgetLadder(true);
  ASSERT_EQ(ladder.size(), 5u);
  EXPECT_TRUE(ladder.front().exact());
  for (std::size_t i = 1; i < ladder.size(); ++i) {
    EXPECT_GT(ladder[i].full_free_fraction, ladder[i - 1].full_free_fraction);
    EXPECT_EQ(ladder[i].visible_pixels, 0u);  // counting tests would end batching
  }
  EXPECT_TRUE(detail::budgetLadder(false).empty());
}

TEST(Budget, MeetsAReachableBudgetAndSettles) {
  const std::vector<double> ms = {10, 9, 8, 7, 6};
  BudgetController c(7.5e-3, detail::budgetLadder(true));
  const Scripted r = script(c, ms, 7.5, 400);
  // Up one rung every 4 frames until under the budget: rung 3 (7 ms) from frame 12 on.
  EXPECT_EQ(r.rungs.back(), 3u);
  EXPECT_EQ(r.rungs[20], 3u);
  // Tries towards exact are rare and each costs a few frames over the budget.
  EXPECT_LE(r.over, 400u / 20);  // at least 95 % of frames within the budget
  EXPECT_LE(r.changes, 3u + 2u * 8u);
}

TEST(Budget, ReturnsToExactWhenThereIsTime) {
  BudgetController c(7.5e-3, detail::budgetLadder(true));
  script(c, {10, 9, 8, 7, 6}, 7.5, 100);
  ASSERT_GT(c.rung(), 0u);
  // The scene became cheaper: every rung now under (1 - margin) x budget.
  const Scripted r = script(c, {5, 4.8, 4.6, 4.4, 4.2}, 7.5, 200);
  EXPECT_EQ(r.rungs.back(), 0u);
  EXPECT_TRUE(c.current().exact());
  EXPECT_EQ(r.over, 0u);
}

TEST(Budget, DoesNotOscillateBetweenRungsThatStraddleTheBudget) {
  // Rung 0 over the budget, rung 1 well under it: a naive controller would flip every
  // few frames. The hold doubles after each step down that had to be undone.
  BudgetController c(8e-3, detail::budgetLadder(true));
  const Scripted r = script(c, {10, 6, 5.5, 5, 4.5}, 8, 2000);
  // Two changes per try: one per doubling of the hold (4 to 256: 7), then one try per
  // 256 frames (under 8 in 2000).
  EXPECT_LE(r.changes, 1u + 2u * (7u + 8u));
  EXPECT_LE(r.over, 2000u / 20);
  for (std::size_t f = 100; f < r.rungs.size(); ++f) EXPECT_LE(r.rungs[f], 1u);
}

TEST(Budget, NoisyFramesStillSettle) {
  BudgetController c(8.5e-3, detail::budgetLadder(true));
  const Scripted r = script(c, {10, 9.2, 8.4, 7.6, 6.8}, 8.5, 1000, 0.1, 7);
  EXPECT_LE(r.changes, 40u);
  std::size_t exact_late = 0;
  for (std::size_t f = 500; f < r.rungs.size(); ++f) exact_late += r.rungs[f] == 0;
  EXPECT_LT(exact_late, 50u);  // 10 ms frames are over 8.5 ms even with the noise
}

TEST(Budget, AnUnreachableBudgetStaysAtTheLastRung) {
  BudgetController c(1e-3, detail::budgetLadder(true));
  const Scripted r = script(c, {10, 9, 8, 7, 6}, 1, 100);
  EXPECT_EQ(r.rungs.back(), 4u);
  EXPECT_EQ(r.changes, 4u);
}

TEST(BudgetCuller, ValidatesAndRecordsTheKnobsEachFrameRan) {
  CullerDesc d;
  d.method = Method::LogState;
  d.budget_ms = -1;
  EXPECT_NE(validateCullerDesc(d).find("budget -1 ms is invalid"), std::string::npos);
  d.budget_ms = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(validateCullerDesc(d), "");
  d.budget_ms = 5;
  d.method = Method::LogZfar;  // takes no full-tile fraction
  EXPECT_NE(validateCullerDesc(d).find("cannot meet a frame-time budget"), std::string::npos);
  d.method = Method::LogState;
  d.approximation.row_stride = 2;
  EXPECT_NE(validateCullerDesc(d).find("leave CullerDesc::approximation exact"), std::string::npos);
  d.approximation = {};
  EXPECT_EQ(validateCullerDesc(d), "");

  // A budget no frame can meet: the culler climbs the whole ladder, one rung per 4
  // frames, and each frame's FrameStats::setting says what it ran.
  d.budget_ms = 1e-9;
  d.tile_size = 8;
  Culler culler(d);
  const test::BoxWorld world = test::makeBoxWorld(3);
  const Camera cam = test::boxCamera(160, 120, DepthConvention::Standard, 0);
  std::vector<float> fractions;
  for (int frame = 0; frame < 24; ++frame) {
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
    const test::CulledFrame f =
        test::cullBoxes(culler, world, cam, depth, test::SourceKind::Software);
    fractions.push_back(f.stats.setting.approximation.full_free_fraction);
  }
  EXPECT_EQ(fractions.front(), 0.0f);
  EXPECT_EQ(fractions[4], 0.01f);
  EXPECT_EQ(fractions.back(), 0.25f);
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);

  // A budget every frame meets: always exact, and every visible box drawn.
  d.budget_ms = 1e6;
  Culler easy(d);
  for (int frame = 0; frame < 12; ++frame) {
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, DepthConvention::Standard);
    const test::CulledFrame f =
        test::cullBoxes(easy, world, cam, depth, test::SourceKind::Software);
    EXPECT_TRUE(f.stats.setting.approximation.exact());
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) EXPECT_TRUE(f.drawn.count(id));
  }
}

}  // namespace
}  // namespace logrid
