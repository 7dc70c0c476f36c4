// What a hardware-query schedule works with (log/src/query_*.cpp, one file per method):
// nodes projected for the frame, the decisions that need no query, queries issued and
// answered through the application's OcclusionQueries, draws through the culler, and a
// per-node memory that lasts across frames. Internal to logrid::core.
//
// The schedules decide *when* to query and what to do with the answers; everything that
// makes an answer conservative is here: boxes that cross the near plane (or whose widened,
// biased query box would) are visible without a query, a query draws the box that
// Projector::queryBox() widened, and an answer issued before a mid-frame depth clear
// counts as visible.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "logrid/culler.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/occlusion_queries.hpp"
#include "logrid/projection.hpp"
#include "logrid/query_schedule.hpp"
#include "logrid/stats.hpp"
#include "testers.hpp"

namespace logrid::detail {

// A node as a schedule handles it in one frame.
struct QueryNode {
  NodeId id = kNoNode;
  Aabb bounds;
  BoxProjection projection;
  float order = 0;              // nearest key - margin: the front-to-back order
  std::optional<QueryBox> box;  // set by QueryFrame::withoutQuery() when a query must decide
};

// Comparator for std::push_heap / pop_heap: the nearest node on top.
inline bool fartherFirst(const QueryNode& a, const QueryNode& b) { return a.order > b.order; }

// What a schedule remembers of each node across frames, by NodeId: a dense array for the
// small ids a flat hierarchy uses, a hash map beyond. Forgotten with the hierarchy.
template <typename Record>
class NodeMemory {
 public:
  Record& operator[](NodeId id) {
    if (id < kDense) {
      if (id >= dense_.size()) dense_.resize(std::max<std::size_t>(id + 1, dense_.size() * 2));
      return dense_[id];
    }
    return sparse_[id];
  }
  void clear() {
    dense_.clear();
    sparse_.clear();
  }

 private:
  static constexpr NodeId kDense = NodeId{1} << 20;
  std::vector<Record> dense_;
  std::unordered_map<NodeId, Record> sparse_;
};

// log+hwq (query_prefilter.cpp): the lazy grid's records decide what they can.
class GridPrefilter;
class Schedule;

class QueryFrame {
 public:
  struct Wiring {
    const Hierarchy* hierarchy = nullptr;
    const Projector* projector = nullptr;
    OcclusionQueries* queries = nullptr;
    GridPrefilter* prefilter = nullptr;  // log+hwq only
    QueryShape shape = QueryShape::Box;
    FrameStats* stats = nullptr;
    const std::uint64_t* clear_epoch = nullptr;  // advanced by each mid-frame depth clear
    std::function<void(const QueryNode&)> draw;  // the culler's draw of a node's objects
    std::function<void(const QueryNode&, Visibility)> observe;  // CullObserver::onTested
    // Objects handed out to draw and not drawn yet (the culler's batch): a query issued
    // now waits until they are drawn (flushDeferred()).
    const std::vector<ObjectId>* undrawn = nullptr;
  };
  QueryFrame(const Wiring& wiring, std::uint32_t frame);

  // 1, 2, ...: the frame count of the schedule (stamps in its node memory).
  std::uint32_t frame() const { return frame_; }
  const Hierarchy& hierarchy() const { return *w_.hierarchy; }
  bool isLeaf(NodeId node) const { return w_.hierarchy->childCount(node) == 0; }
  std::uint32_t viewportPixels() const { return pixels_; }

  // A node projected for this frame (counts nothing).
  QueryNode project(NodeId node) const;
  // The root, unless the hierarchy is empty or the root lies outside the frustum.
  std::optional<QueryNode> root();
  // Appends the children of `node` that are not view-culled, nearest first; counts the
  // others in FrameStats::boxes_view_culled (their subtrees are never visited).
  void children(NodeId node, std::vector<QueryNode>& out);

  // What needs no query, for a node taken up by the traversal (counted as visited):
  // ViewCulled outside the frustum; Visible for a box that crosses the near plane, is
  // invalid, or has no query box; Visible or Occluded where log+hwq's records decide
  // (counted as a test). Nothing if a query must decide; then n.box is set.
  std::optional<Visibility> withoutQuery(QueryNode& n);

  // Issues one query over the given nodes (each with its box set by withoutQuery()). While
  // objects handed out to draw are not drawn yet, the query is only recorded and goes to
  // the renderer once they are (flushDeferred()), so that it sees them as it would in
  // draw order. The handle is the frame's own.
  QueryHandle issue(const QueryNode* const* nodes, std::size_t count);
  QueryHandle issue(const QueryNode& n) {
    const QueryNode* p = &n;
    return issue(&p, 1);
  }
  // Is the answer there without waiting? (Never for a query not issued yet.)
  bool ready(QueryHandle handle);
  // Can answer() be called now? Only once the objects handed out are drawn: what the
  // answer decides comes after them in the frame (a depth clear while they are drawn
  // makes earlier answers "visible"). If not, the schedule returns from resume() and is
  // resumed once they are.
  bool answerable(QueryHandle handle);
  // The answer, waited for if needed: Visible where any sample passed, or where the
  // depth buffer was cleared after the query was issued (its answer no longer holds).
  // Precondition: answerable(handle).
  Visibility answer(QueryHandle handle);
  // The objects handed out are drawn: the recorded queries go to the renderer, in order.
  void flushDeferred();
  // A depth clear while the objects handed out are drawn: the nodes log+hwq's records
  // found hidden while they waited go back to the schedule (Schedule::reconsider).
  // Whether there were any.
  bool reconsiderCulled(Schedule& schedule);

  // Draws the node's objects (culler: callback, statistics, drawn area).
  void draw(const QueryNode& n) { w_.draw(n); }
  // A test's outcome: FrameStats::boxes_tested and boxes_occluded, and the observer.
  void tested(const QueryNode& n, Visibility v);

 private:
  bool undrawn() const { return w_.undrawn && !w_.undrawn->empty(); }
  // Sends the recorded query `local` to the renderer.
  void send(QueryHandle local);

  // A query of this frame, by the frame's handle.
  struct Slot {
    QueryHandle handle = 0;  // the renderer's, once sent
    bool sent = false;
    std::uint64_t epoch = 0;  // the clear epoch it was sent in
    std::size_t first = 0;    // its boxes or rectangles in boxes_ / rects_ until sent
    std::size_t count = 0;
  };
  Wiring w_;
  std::uint32_t frame_;
  std::uint32_t pixels_;
  std::vector<Slot> slots_;
  std::vector<QueryHandle> deferred_;      // recorded, not sent, in issue order
  std::vector<QueryNode> culled_undrawn_;  // hidden by log+hwq's records while undrawn
  std::vector<QueryBox> boxes_;            // of the recorded queries (QueryShape::Box)
  std::vector<RectQuery> rects_;           // of the recorded queries (QueryShape::Rect)
};

// A query schedule at work: a query method's traversal. One object per Culler; it keeps
// its node memory across frames. A frame is begun, then resumed until it is done: a
// schedule returns from resume() (false) where it must wait for an answer that needs the
// objects handed out to be drawn first (QueryFrame::answerable), and is resumed in the
// same state once they are; so its state between calls lives in its members.
class Schedule {
 public:
  virtual ~Schedule() = default;
  virtual void begin(QueryFrame& frame) = 0;
  // True when the frame is done.
  virtual bool resume(QueryFrame& frame) = 0;
  // A node found hidden earlier in the frame is to be taken up again (a depth clear took
  // away what hid it): back into the schedule's queue.
  virtual void reconsider(QueryFrame& frame, QueryNode node) = 0;
  // The hierarchy changed (another object or revision): forget every node.
  virtual void forget() = 0;
};

// The schedule's implementation (query_schedule.cpp's table).
std::unique_ptr<Schedule> makeSchedule(QuerySchedule schedule, const QueryScheduleDesc& desc);

}  // namespace logrid::detail
