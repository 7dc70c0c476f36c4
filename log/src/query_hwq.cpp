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
#include <optional>
#include <vector>

#include "query_frame.hpp"

namespace logrid::detail {
namespace {

class HwqSchedule final : public Schedule {
 public:
  void begin(QueryFrame& f) override {
    queue_.clear();
    waiting_.reset();
    if (auto root = f.root()) queue_.push_back(std::move(*root));
  }
  bool resume(QueryFrame& f) override {
    for (;;) {
      if (waiting_) {
        if (!f.answerable(waiting_->handle)) return false;
        const Visibility v = f.answer(waiting_->handle);
        f.tested(waiting_->node, v);
        const QueryNode n = std::move(waiting_->node);
        waiting_.reset();
        if (v == Visibility::Visible) open(f, n);
        continue;
      }
      if (queue_.empty()) return true;
      std::pop_heap(queue_.begin(), queue_.end(), fartherFirst);
      QueryNode n = std::move(queue_.back());
      queue_.pop_back();
      const std::optional<Visibility> v = f.withoutQuery(n);
      if (!v) {
        const QueryHandle h = f.issue(n);
        waiting_ = Waiting{std::move(n), h};
      } else if (*v == Visibility::Visible) {
        open(f, n);
      }
    }
  }
  void reconsider(QueryFrame&, QueryNode node) override {
    queue_.push_back(std::move(node));
    std::push_heap(queue_.begin(), queue_.end(), fartherFirst);
  }
  void forget() override {}

 private:
  struct Waiting {
    QueryNode node;
    QueryHandle handle;
  };

  // A visible node: its objects drawn, its children queued.
  void open(QueryFrame& f, const QueryNode& n) {
    if (f.hierarchy().objectCount(n.id) > 0) f.draw(n);
    const std::size_t first = queue_.size();
    f.children(n.id, queue_);
    for (std::size_t i = first; i < queue_.size(); ++i) {
      std::push_heap(queue_.begin(), queue_.begin() + std::ptrdiff_t(i) + 1, fartherFirst);
    }
  }

  std::vector<QueryNode> queue_;    // min-heap on QueryNode::order
  std::optional<Waiting> waiting_;  // the query whose answer the walk waits for
};

}  // namespace

std::unique_ptr<Schedule> makeHwqSchedule(const QueryScheduleDesc&) {
  return std::make_unique<HwqSchedule>();
}

}  // namespace logrid::detail
