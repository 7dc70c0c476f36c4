#include "budget.hpp"

#include <algorithm>
#include <array>
#include <cassert>

namespace logrid::detail {
namespace {

constexpr double kMinRatio = 0.05;

}  // namespace

BudgetController::BudgetController(double budget_s, std::vector<BudgetRung> ladder)
    : budget_s_(budget_s), ladder_(std::move(ladder)) {
  assert(budget_s_ > 0 && !ladder_.empty() && ladder_.front().approximation.exact());
  ladder_.front().ratio = 1;
}

void BudgetController::moveTo(std::size_t rung) {
  came_down_ = rung < rung_;
  from_ = rung_;
  from_seconds_ = last_seconds_;
  rung_ = rung;
  held_ = 0;
}

// The first frame on a new rung against the last one on the rung before: the ratio
// between the two, frames apart by one (the scene barely moved in between). The newest
// such measurement replaces the rung's ratio: a prior that was wrong is not kept half.
void BudgetController::learn(double seconds) {
  if (rung_ == 0 || from_seconds_ <= 0 || seconds <= 0) return;
  const double implied = ladder_[from_].ratio * seconds / from_seconds_;
  double& r = ladder_[rung_].ratio;
  // Sceptical of a rung that seems to buy more than believed (a slow frame before the
  // change makes it so), not of one that buys less.
  const double weight = implied < r ? kLearnFaster : 1.0;
  r = std::clamp(r + weight * (implied - r), kMinRatio, 1.0);
  // The ladder stays ordered: a rung is no slower than the rungs before it.
  for (std::size_t i = rung_ + 1; i < ladder_.size(); ++i) {
    ladder_[i].ratio = std::min(ladder_[i].ratio, r);
  }
  for (std::size_t i = 1; i < rung_; ++i) ladder_[i].ratio = std::max(ladder_[i].ratio, r);
}

// The least approximate rung predicted under the budget with the up margin; where none
// is, the fastest, if it buys anything over the rung now.
std::size_t BudgetController::rungFor(double level) const {
  for (std::size_t i = 0; i < ladder_.size(); ++i) {
    if (level * ladder_[i].ratio <= (1 - kUpMargin) * budget_s_) return i;
  }
  const std::size_t last = ladder_.size() - 1;
  return ladder_[last].ratio < (1 - kGain) * ladder_[rung_].ratio ? last : rung_;
}

double BudgetController::medianOfRecent() const {
  const std::size_t n = std::min<std::size_t>(recent_count_, recent_.size());
  std::array<double, 3> v = recent_;
  std::sort(v.begin(), v.begin() + n);
  return n == 3 ? v[1] : n == 2 ? 0.5 * (v[0] + v[1]) : v[0];
}

void BudgetController::endFrame(double seconds) {
  if (held_ == 0 && rung_ != from_) learn(seconds);
  last_seconds_ = seconds;
  // The level follows the median of the last three frames: one slow frame (a hitch of
  // the machine) moves nothing, two in a row do.
  recent_[recent_count_++ % recent_.size()] = seconds / ladder_[rung_].ratio;
  const double typical = medianOfRecent();
  level_ = level_ > 0 ? level_ + kRate * (typical - level_) : typical;
  ++held_;
  if (came_down_ && held_ == hold_) {
    hold_ = std::max(kHold, hold_ / 2);  // the step down held
    came_down_ = false;
  }
  const bool held = held_ >= hold_;
  const double below = rung_ > 0 ? ladder_[rung_ - 1].ratio : 1;
  // A rung that buys nothing over the one below is not paid for in accuracy, over the
  // budget or not.
  if (rung_ > 0 && held && ladder_[rung_].ratio >= (1 - kGain) * below) {
    moveTo(rung_ - 1);
    return;
  }
  if (level_ * ladder_[rung_].ratio > budget_s_) {
    const std::size_t to = rungFor(level_);
    if (to > rung_) {
      // A step towards exact that did not hold: wait longer before the next.
      if (came_down_) hold_ = std::min(kMaxHold, 2 * hold_);
      moveTo(to);
    }
    return;
  }
  if (rung_ > 0 && held && level_ * below <= (1 - kDownMargin) * budget_s_) moveTo(rung_ - 1);
}

std::vector<BudgetRung> budgetLadder(const MethodInfo& info, bool temporal_coherence) {
  if (!info.grid) return {};
  std::vector<BudgetRung> ladder(1);
  auto add = [&](double ratio, auto set) {
    BudgetRung r;
    r.ratio = ratio;
    set(r.approximation);
    ladder.push_back(r);
  };
  // docs/TRADEOFF.md, 640x480, frame time over the conservative setting's. Without
  // coherence (the forest and the city, K = 1): the full-tile fraction 0.01 to 0.25, then
  // visible pixels 256. With coherence (K = 16, consecutive frames): visible pixels 16 to
  // 256; the full-tile fraction there changes nothing.
  if (info.takes.full_fraction && !temporal_coherence) {
    add(0.95, [](GridApproximation& a) { a.full_free_fraction = 0.01f; });
    add(0.88, [](GridApproximation& a) { a.full_free_fraction = 0.05f; });
    add(0.83, [](GridApproximation& a) { a.full_free_fraction = 0.1f; });
    add(0.75, [](GridApproximation& a) { a.full_free_fraction = 0.25f; });
    if (info.takes.visible_pixels) add(0.70, [](GridApproximation& a) { a.visible_pixels = 256; });
  } else if (info.takes.visible_pixels) {
    add(0.94, [](GridApproximation& a) { a.visible_pixels = 16; });
    add(0.82, [](GridApproximation& a) { a.visible_pixels = 64; });
    add(0.71, [](GridApproximation& a) { a.visible_pixels = 256; });
  }
  if (ladder.size() == 1) ladder.clear();
  return ladder;
}

}  // namespace logrid::detail
