// The frame-time budget (CullerDesc::budget_ms, docs/BUDGET.md): a controller that moves
// along a ladder of approximate settings, from exact towards the most approximate, so
// that the culled pass meets the budget, and back towards exact when there is time.
// Internal to logrid::core; tested against scripted frame times (tests/unit/budget_test.cpp).
//
// Up (more approximate) is quick: after kHold frames whose average is over the budget.
// Down (towards exact) is tried after `hold` frames under (1 - kDownMargin) x budget;
// a step down that had to be undone doubles `hold` (up to kMaxHold), and a step down
// that held halves it again. So a budget between two rungs costs a handful of frames
// over it per doubling, not a flicker every frame.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/grid_settings.hpp"

namespace logrid::detail {

class BudgetController {
 public:
  static constexpr std::uint32_t kHold = 4;
  static constexpr std::uint32_t kMaxHold = 256;
  static constexpr double kDownMargin = 0.15;
  // Weight of the newest frame in the average of the current rung's frames.
  static constexpr double kRate = 0.3;

  // `ladder`: settings from exact (first) to the most approximate; `budget_s` > 0.
  BudgetController(double budget_s, std::vector<GridApproximation> ladder);

  const GridApproximation& current() const { return ladder_[rung_]; }
  std::size_t rung() const { return rung_; }
  std::size_t rungs() const { return ladder_.size(); }
  // Takes the seconds of the frame that ran current().
  void endFrame(double seconds);

 private:
  void moveTo(std::size_t rung);

  double budget_s_;
  std::vector<GridApproximation> ladder_;
  std::size_t rung_ = 0;
  double average_ = 0;      // of this rung's frames since the last change
  std::uint32_t held_ = 0;  // frames on this rung since the last change
  std::uint32_t hold_ = kHold;
  bool came_down_ = false;  // the last change was a step towards exact
};

// The ladder a method's budget moves along: the Pareto front of the approximate knobs
// measured in docs/TRADEOFF.md, for the knobs the method takes; empty if it takes none
// that the budget uses.
std::vector<GridApproximation> budgetLadder(bool takes_full_fraction);

}  // namespace logrid::detail
