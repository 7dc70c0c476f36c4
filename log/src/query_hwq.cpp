// hwq: stop and wait, the baseline every query schedule is measured against.
//
// The hierarchy is walked front to back (nearest box first); every box that needs a test
// gets one hardware occlusion query, and the walk waits for its answer before it goes on:
// a visible node's objects are drawn and its children queued, an occluded node's subtree
// is skipped. This is the "simple OC" of Kovalčík & Sochor (§4: "Before rendering a node,
// the occlusion query is utilized to get the visibility of the node's bounding box") and
// the naive use Guthe et al. (§2.1) and Bittner et al. set out from: correct in any order,
// with one full wait for the renderer per tested box.
#include <algorithm>
#include <vector>

#include "query_frame.hpp"

namespace logrid::detail {
namespace {

class HwqSchedule final : public Schedule {
 public:
  void run(QueryFrame& f) override {
    queue_.clear();
    if (auto root = f.root()) queue_.push_back(std::move(*root));
    while (!queue_.empty()) {
      std::pop_heap(queue_.begin(), queue_.end(), fartherFirst);
      QueryNode n = std::move(queue_.back());
      queue_.pop_back();
      std::optional<Visibility> v = f.withoutQuery(n);
      if (!v) {
        v = f.answer(f.issue(n));
        f.tested(n, *v);
      }
      if (*v != Visibility::Visible) continue;
      if (f.hierarchy().objectCount(n.id) > 0) f.draw(n);
      const std::size_t first = queue_.size();
      f.children(n.id, queue_);
      for (std::size_t i = first; i < queue_.size(); ++i) {
        std::push_heap(queue_.begin(), queue_.begin() + std::ptrdiff_t(i) + 1, fartherFirst);
      }
    }
  }
  void forget() override {}

 private:
  std::vector<QueryNode> queue_;  // min-heap on QueryNode::order
};

}  // namespace

std::unique_ptr<Schedule> makeHwqSchedule(const QueryScheduleDesc&) {
  return std::make_unique<HwqSchedule>();
}

}  // namespace logrid::detail
