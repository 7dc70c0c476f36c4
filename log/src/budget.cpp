#include "budget.hpp"

#include <algorithm>
#include <cassert>

namespace logrid::detail {

BudgetController::BudgetController(double budget_s, std::vector<GridApproximation> ladder)
    : budget_s_(budget_s), ladder_(std::move(ladder)) {
  assert(budget_s_ > 0 && !ladder_.empty() && ladder_.front().exact());
}

void BudgetController::moveTo(std::size_t rung) {
  came_down_ = rung < rung_;
  rung_ = rung;
  held_ = 0;
  average_ = 0;
}

void BudgetController::endFrame(double seconds) {
  average_ = held_ == 0 ? seconds : average_ + kRate * (seconds - average_);
  ++held_;
  if (held_ < kHold) return;
  if (average_ > budget_s_) {
    if (rung_ + 1 == ladder_.size()) return;  // as approximate as it goes
    // A step towards exact that did not hold: wait longer before the next.
    if (came_down_) hold_ = std::min(kMaxHold, 2 * hold_);
    moveTo(rung_ + 1);
    return;
  }
  if (came_down_ && held_ == hold_) {
    hold_ = std::max(kHold, hold_ / 2);  // the step down held
    came_down_ = false;
  }
  if (rung_ > 0 && held_ >= hold_ && average_ <= (1 - kDownMargin) * budget_s_) moveTo(rung_ - 1);
}

std::vector<GridApproximation> budgetLadder(bool takes_full_fraction) {
  if (!takes_full_fraction) return {};
  // docs/TRADEOFF.md: on the forest and the city at 640x480 the front is full-fraction
  // 0.01 to 0.25 (0.95x to 0.75x the conservative time), then visible-pixels 256 beside
  // it; the counting tests of visible-pixels are never batched, so they stay off the
  // ladder of a culler that may batch.
  std::vector<GridApproximation> ladder(1);
  for (float f : {0.01f, 0.05f, 0.1f, 0.25f}) {
    GridApproximation a;
    a.full_free_fraction = f;
    ladder.push_back(a);
  }
  return ladder;
}

}  // namespace logrid::detail
