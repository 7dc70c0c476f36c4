// stat: occlusion culling with statistically optimised occlusion queries, Kovalčík &
// Sochor (WSCG 2005), §3 "Algorithm" and its pseudocode.
//
// The traversal keeps a queue of nodes, the root first. Each node taken from the queue
// gets an action (CalcNodeAction, §3 "Optimizations"):
//   SKIP    outside the view frustum;
//   RENDER  the viewer is inside its box (here: the box crosses the near plane, or a
//           query box would), or its statistics say it is still visible: its objects are
//           drawn without a query and its children take its place at the front of the
//           queue, nearest first;
//   QUERY   no recent statistics ("StatisticsTooOld"), the last query found it occluded,
//           or the time since its last query exceeds BASE_TIME * (2 - 0.5^k), k being
//           the number of unoccluded results among its recent queries (here the last 8):
//           a node found visible again and again is queried less and less often.
// Queries are not waited for: the first pass goes on down the queue while they are in
// flight, until `stat_in_flight` (the paper's "about 20") are issued or the queue runs
// out; then a second pass collects them in order, saves their results as the nodes'
// statistics, draws the visible nodes and puts their children at the front of the queue,
// and the first pass starts again from there. BASE_TIME is counted in frames
// (QueryScheduleDesc::stat_base_frames; the paper's 2/3 s is 20 frames at 30 Hz), which
// keeps runs reproducible.
//
// "Statistics too old" is read as: no query result yet, the last one more than
// 2 * BASE_TIME ago (beyond that the formula above queries anyway), or the node was not
// visited in the previous frame (its statistics describe a view that is gone).
#include <cmath>
#include <deque>
#include <vector>

#include "query_frame.hpp"

namespace logrid::detail {
namespace {

class StatSchedule final : public Schedule {
 public:
  StatSchedule(std::uint32_t in_flight, std::uint32_t base_frames)
      : in_flight_limit_(in_flight), base_(base_frames) {}

  void begin(QueryFrame& f) override {
    queue_.clear();
    in_flight_.clear();
    children_.clear();
    answered_ = 0;
    if (auto root = f.root()) queue_.push_back(std::move(*root));
  }

  bool resume(QueryFrame& f) override {
    for (;;) {
      if (in_flight_.empty()) {
        if (queue_.empty()) return true;
        // First pass: down the queue until enough queries are in flight.
        while (!queue_.empty() && in_flight_.size() < in_flight_limit_) {
          QueryNode n = std::move(queue_.front());
          queue_.pop_front();
          switch (action(f, n)) {
            case Action::Skip: break;
            case Action::Render:
              render(f, n, children_);
              insertFront(children_);
              break;
            case Action::Query: {
              const QueryHandle h = f.issue(n);
              in_flight_.push_back({std::move(n), h});
              break;
            }
          }
        }
        answered_ = 0;
        children_.clear();
      }
      // Second pass: every query in flight, in the order issued.
      for (; answered_ < in_flight_.size(); ++answered_) {
        Flight& q = in_flight_[answered_];
        if (!f.answerable(q.handle)) return false;
        const Visibility v = f.answer(q.handle);
        f.tested(q.node, v);
        save(f, q.node.id, v == Visibility::Visible);
        if (v == Visibility::Visible) render(f, q.node, children_);
      }
      in_flight_.clear();
      insertFront(children_);
    }
  }

  void reconsider(QueryFrame&, QueryNode node) override { queue_.push_front(std::move(node)); }
  void forget() override { memory_.clear(); }

 private:
  enum class Action { Skip, Render, Query };
  struct Record {
    std::uint32_t visited = 0;     // frame the node was last taken from the queue
    std::uint32_t last_query = 0;  // frame of its last query result (0: none)
    std::uint8_t history = 0;      // recent results, newest in bit 0 (1: unoccluded)
    bool last_occluded = false;
  };
  struct Flight {
    QueryNode node;
    QueryHandle handle;
  };

  Action action(QueryFrame& f, QueryNode& n) {
    Record& r = memory_[n.id];
    const bool seen_last_frame = r.visited + 1 == f.frame();
    r.visited = f.frame();
    if (const std::optional<Visibility> v = f.withoutQuery(n)) {
      if (*v == Visibility::Visible) return Action::Render;  // the viewer "inside" the box
      return Action::Skip;                                   // outside, or the records hide it
    }
    if (!seen_last_frame || r.last_query == 0 || f.frame() - r.last_query > 2 * base_) {
      return Action::Query;  // statistics too old
    }
    if (r.last_occluded) return Action::Query;
    int unoccluded = 0;
    for (std::uint8_t h = r.history; h; h &= std::uint8_t(h - 1)) ++unoccluded;
    const double not_query_time = r.last_query + base_ * (2.0 - std::ldexp(1.0, -unoccluded));
    return double(f.frame()) > not_query_time ? Action::Query : Action::Render;
  }

  void save(QueryFrame& f, NodeId node, bool visible) {
    Record& r = memory_[node];
    r.last_query = f.frame();
    r.history = std::uint8_t((r.history << 1) | (visible ? 1 : 0));
    r.last_occluded = !visible;
  }

  // RenderNode: the objects, and the children (nearest first) appended to `out`.
  static void render(QueryFrame& f, const QueryNode& n, std::vector<QueryNode>& out) {
    if (f.hierarchy().objectCount(n.id) > 0) f.draw(n);
    f.children(n.id, out);
  }

  // Puts `nodes` at the front of the queue, in their order, and empties it.
  void insertFront(std::vector<QueryNode>& nodes) {
    for (auto it = nodes.rbegin(); it != nodes.rend(); ++it) queue_.push_front(std::move(*it));
    nodes.clear();
  }

  std::uint32_t in_flight_limit_;
  std::uint32_t base_;
  NodeMemory<Record> memory_;
  std::deque<QueryNode> queue_;
  std::vector<Flight> in_flight_;
  std::size_t answered_ = 0;  // of in_flight_, in the second pass
  std::vector<QueryNode> children_;
};

}  // namespace

std::unique_ptr<Schedule> makeStatSchedule(const QueryScheduleDesc& d) {
  return std::make_unique<StatSchedule>(d.stat_in_flight, d.stat_base_frames);
}

}  // namespace logrid::detail
