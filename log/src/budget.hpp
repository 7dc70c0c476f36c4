// The frame-time budget (CullerDesc::budget_ms, docs/BUDGET.md): a controller that moves
// along a ladder of approximate settings, from exact towards the most approximate, so
// that the frames meet the budget, and back towards exact when there is time.
// Internal to logrid::core; tested against scripted frame times (tests/unit/budget_test.cpp).
//
// Each rung has a ratio: its frame time over the exact setting's on the same frame,
// starting at the figure measured in docs/TRADEOFF.md and learnt from the two frames
// around each change of rung (at once where the rung turns out slower than its ratio
// said, a quarter of the way where faster: a slow frame before the change makes it look
// so). Dividing a frame's time by its rung's ratio gives the frame's
// exact-equivalent time; a running average of it (the level) predicts every rung's time.
//
// Up (more approximate) at once when the level puts this rung over the budget: to the
// least approximate rung predicted under (1 - kUpMargin) x budget. The level follows the
// median of the last three frames, so one slow frame (a hitch) moves nothing.
// Down (towards exact) one rung after `hold` frames when the rung below is predicted under
// (1 - kDownMargin) x budget, or when it is predicted no slower (a rung that buys nothing
// is not paid for in accuracy). A step down that is undone before its hold is over
// doubles `hold` (up to kMaxHold); one that holds halves it again. So a budget between
// two rungs costs a frame over it per doubling, not a flicker.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "logrid/grid_settings.hpp"
#include "logrid/method.hpp"

namespace logrid::detail {

struct BudgetRung {
  GridApproximation approximation;
  double ratio = 1;  // frame time over the exact setting's, as measured
};

class BudgetController {
 public:
  static constexpr std::uint32_t kHold = 4;
  static constexpr std::uint32_t kMaxHold = 256;
  static constexpr double kUpMargin = 0.05;
  static constexpr double kDownMargin = 0.15;
  // Weight of the newest frames' median in the level.
  static constexpr double kRate = 0.5;
  // Weight of a transition that finds a rung faster than its ratio said (slower: 1).
  static constexpr double kLearnFaster = 0.25;
  // A rung whose ratio is not this much below the rung before it buys nothing.
  static constexpr double kGain = 0.02;

  // `ladder`: rungs from exact (first, ratio 1) to the most approximate; `budget_s` > 0.
  BudgetController(double budget_s, std::vector<BudgetRung> ladder);

  const GridApproximation& current() const { return ladder_[rung_].approximation; }
  std::size_t rung() const { return rung_; }
  std::size_t rungs() const { return ladder_.size(); }
  double ratio(std::size_t rung) const { return ladder_[rung].ratio; }
  // Takes the seconds of the frame that ran current().
  void endFrame(double seconds);

 private:
  void learn(double seconds);
  std::size_t rungFor(double level) const;
  double medianOfRecent() const;
  void moveTo(std::size_t rung);

  double budget_s_;
  std::vector<BudgetRung> ladder_;
  std::size_t rung_ = 0;
  double level_ = 0;                // exact-equivalent seconds, running average; 0 before a frame
  std::array<double, 3> recent_{};  // the last frames' exact-equivalent seconds
  std::uint64_t recent_count_ = 0;
  std::uint32_t held_ = 0;  // frames on this rung since the last change
  std::uint32_t hold_ = kHold;
  bool came_down_ = false;   // the last change was a step towards exact
  std::size_t from_ = 0;     // the rung before the last change
  double from_seconds_ = 0;  // the last frame's seconds on it
  double last_seconds_ = 0;
};

// The ladder a method's budget moves along: the Pareto front of the approximate knobs
// measured in docs/TRADEOFF.md at the culler's setting, for the knobs the method takes;
// empty if it takes none that the budget uses. Without temporal coherence the front is
// the full-tile fraction, then visible pixels; with it (drawn out of order, the occlusion
// state gives way to depth tests, on which the full-tile fraction acts not at all) it is
// visible pixels alone.
std::vector<BudgetRung> budgetLadder(const MethodInfo& info, bool temporal_coherence);

}  // namespace logrid::detail
