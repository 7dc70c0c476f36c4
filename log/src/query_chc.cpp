// chc: coherent hierarchical culling in its CHC++ form, Mattausch, Bittner & Wimmer,
// "CHC++: Coherent Hierarchical Culling Revisited" (Eurographics 2008), on the CHC of
// Bittner et al. (2004). Written from the papers' descriptions.
//
// Traversal (CHC §4, CHC++ §3): front to back through a distance queue. A node that
// was visible in the previous frame is not queried before it is processed: an interior
// node's children are queued at once, a leaf is drawn at once. A node that was not
// visible (or not visited) in the previous frame is queried, and its subtree waits for
// the answer. Visibility is pulled up: an interior node is visible when a leaf below it
// is, so next frame's "previously visible" front is where the visible leaves end.
// Queries are interleaved with rendering: while the answer at the head of the query
// queue is not there, the traversal goes on with the distance queue.
//
// The CHC++ refinements:
//   §3.1 queries of previously visible leaves (whose answers only matter for the next
//        frame) wait in a v-queue and are issued when the traversal would otherwise wait
//        for the renderer, and the rest at the end of the frame;
//   §3.2 previously invisible nodes are gathered in an i-queue and issued as a batch
//        once `chc_batch` of them are waiting or the distance queue runs dry;
//   §4.1 each batch is issued as multi-queries: one query for several nodes expected to
//        stay invisible. A node invisible for i frames stays invisible with probability
//        p(i) = 0.99 - 0.7 e^-i (the paper's fit); a multi-query of the nodes M costs
//        1 + (1 - prod p) |M| queries (if it fails, each node is queried on its own; a
//        single node's query is final and costs 1) and answers |M| nodes, so nodes sorted
//        by p are added to a multi-query while its value |M| / cost grows. A failed
//        multi-query is followed by a query per node;
//   §4.2 a visible leaf is queried only every n_av = `chc_visible_interval` frames, the
//        first time after a random 1..n_av frames, so that the leaves that turn visible
//        together are not all queried in the same frame again.
// Not done: tight bounding volumes (§4.3) and state sorting of the render queue (the
// application draws each object through the callback).
#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "query_frame.hpp"

namespace logrid::detail {
namespace {

// Deterministic pseudo-random number for (node, frame): reproducible runs.
std::uint32_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return std::uint32_t(x ^ (x >> 31));
}

class ChcSchedule final : public Schedule {
 public:
  ChcSchedule(std::uint32_t batch, std::uint32_t visible_interval)
      : batch_(batch), interval_(visible_interval) {}

  void begin(QueryFrame& f) override {
    distance_.clear();
    queries_.clear();
    v_queue_.clear();
    i_queue_.clear();
    if (auto root = f.root()) {
      memory_[root->id].parent = kNoNode;
      distance_.push_back(std::move(*root));
    }
  }

  bool resume(QueryFrame& f) override {
    while (!distance_.empty() || !queries_.empty() || !i_queue_.empty() || !v_queue_.empty()) {
      // Answers that are there; while waiting with nothing to traverse, issue what waits.
      while (!queries_.empty()) {
        if (f.ready(queries_.front().handle)) {
          if (!handle(f)) return false;
        } else if (!distance_.empty()) {
          break;  // traverse meanwhile
        } else if (!i_queue_.empty()) {
          issueBatch(f);
        } else if (!v_queue_.empty()) {
          issueVisible(f, 1);     // §3.1: fill the wait
        } else if (!handle(f)) {  // nothing left to do but wait
          return false;
        }
      }
      if (!distance_.empty()) {
        std::pop_heap(distance_.begin(), distance_.end(), fartherFirst);
        QueryNode n = std::move(distance_.back());
        distance_.pop_back();
        process(f, n);
      } else if (!i_queue_.empty()) {
        issueBatch(f);
      } else if (queries_.empty() && !v_queue_.empty()) {
        issueVisible(f, v_queue_.size());  // the end of the frame
      }
    }
    return true;
  }

  void reconsider(QueryFrame&, QueryNode node) override {
    distance_.push_back(std::move(node));
    std::push_heap(distance_.begin(), distance_.end(), fartherFirst);
  }
  void forget() override { memory_.clear(); }

 private:
  struct Record {
    std::uint32_t visited = 0;     // frame the node was last processed
    std::uint32_t next_query = 0;  // a visible leaf: the frame of its next query
    std::uint32_t invisible = 0;   // frames in a row found invisible
    NodeId parent = kNoNode;       // this frame's
    bool visible = false;          // this frame's once visited, else the last visit's
  };
  struct Pending {
    QueryHandle handle;
    std::vector<QueryNode> nodes;  // more than one: a multi-query
    bool visible_leaf = false;     // a v-queue query: the leaf is drawn already
  };

  bool wasVisible(const QueryFrame& f, const Record& r) const {
    return r.visible && r.visited + 1 == f.frame();
  }

  void process(QueryFrame& f, QueryNode& n) {
    Record& r = memory_[n.id];
    const bool was_visible = wasVisible(f, r);
    r.visited = f.frame();
    r.visible = false;
    if (const std::optional<Visibility> v = f.withoutQuery(n)) {
      if (*v == Visibility::Visible) {
        traverse(f, n);
        pullUp(n.id);
      } else if (*v == Visibility::Occluded) {
        ++memory_[n.id].invisible;
      }
      return;
    }
    if (!was_visible) {
      i_queue_.push_back(std::move(n));
      if (i_queue_.size() >= batch_) issueBatch(f);
      return;
    }
    const bool leaf = f.isLeaf(n.id);
    const bool query = leaf && f.frame() >= r.next_query;
    traverse(f, n);
    if (query) {
      v_queue_.push_back(std::move(n));
    } else if (leaf) {
      pullUp(n.id);  // assumed visible still
    }
  }

  // Draws the node's objects and queues its children.
  void traverse(QueryFrame& f, const QueryNode& n) {
    if (f.hierarchy().objectCount(n.id) > 0) f.draw(n);
    const std::size_t first = distance_.size();
    f.children(n.id, distance_);
    for (std::size_t i = first; i < distance_.size(); ++i) {
      memory_[distance_[i].id].parent = n.id;
      std::push_heap(distance_.begin(), distance_.begin() + std::ptrdiff_t(i) + 1, fartherFirst);
    }
  }

  void pullUp(NodeId node) {
    while (node != kNoNode) {
      Record& r = memory_[node];
      if (r.visible) break;
      r.visible = true;
      r.invisible = 0;
      node = r.parent;
    }
  }

  // The answer of the oldest query; false (nothing done) if it must wait for the objects
  // handed out to be drawn.
  bool handle(QueryFrame& f) {
    if (!f.answerable(queries_.front().handle)) return false;
    Pending p = std::move(queries_.front());
    queries_.pop_front();
    const Visibility v = f.answer(p.handle);
    if (p.nodes.size() > 1) {
      if (v == Visibility::Visible) {
        for (QueryNode& n : p.nodes) issue(f, {std::move(n)}, false);  // §4.1: one by one
      } else {
        for (const QueryNode& n : p.nodes) occluded(f, n);
      }
      return true;
    }
    QueryNode& n = p.nodes.front();
    if (v != Visibility::Visible) {
      occluded(f, n);
      return true;
    }
    f.tested(n, v);
    Record& r = memory_[n.id];
    if (p.visible_leaf) {
      r.next_query = f.frame() + interval_;
    } else {
      // Turned visible: first query after a random 1..n_av frames (§4.2).
      r.next_query = f.frame() + 1 + mix((std::uint64_t(n.id) << 32) | f.frame()) % interval_;
      traverse(f, n);
    }
    pullUp(n.id);
    return true;
  }

  void occluded(QueryFrame& f, const QueryNode& n) {
    f.tested(n, Visibility::Occluded);
    Record& r = memory_[n.id];
    r.visible = false;
    ++r.invisible;
  }

  void issue(QueryFrame& f, std::vector<QueryNode> nodes, bool visible_leaf) {
    ptrs_.clear();
    for (const QueryNode& n : nodes) ptrs_.push_back(&n);
    const QueryHandle h = f.issue(ptrs_.data(), ptrs_.size());
    queries_.push_back({h, std::move(nodes), visible_leaf});
  }

  void issueVisible(QueryFrame& f, std::size_t count) {
    for (std::size_t k = 0; k < count && !v_queue_.empty(); ++k) {
      QueryNode n = std::move(v_queue_.front());
      v_queue_.pop_front();
      issue(f, {std::move(n)}, true);
    }
  }

  // §4.1: the i-queue as multi-queries, grouped greedily by the probability of staying
  // invisible.
  void issueBatch(QueryFrame& f) {
    auto stay = [&](const QueryNode& n) {
      return 0.99 - 0.7 * std::exp(-double(memory_[n.id].invisible));
    };
    std::stable_sort(i_queue_.begin(), i_queue_.end(),
                     [&](const QueryNode& a, const QueryNode& b) { return stay(a) > stay(b); });
    // A single node's query is final; a multi-query that fails is followed by |M| more.
    auto value = [](double size, double all_stay) {
      return size == 1 ? 1.0 : size / (1.0 + (1.0 - all_stay) * size);
    };
    std::vector<QueryNode> group;
    double all_stay = 1;
    for (QueryNode& n : i_queue_) {
      const double p = stay(n);
      if (!group.empty() &&
          value(double(group.size() + 1), all_stay * p) < value(double(group.size()), all_stay)) {
        issue(f, std::move(group), false);
        group.clear();
        all_stay = 1;
      }
      group.push_back(std::move(n));
      all_stay *= p;
    }
    if (!group.empty()) issue(f, std::move(group), false);
    i_queue_.clear();
  }

  std::uint32_t batch_;
  std::uint32_t interval_;
  NodeMemory<Record> memory_;
  std::vector<QueryNode> distance_;  // min-heap on QueryNode::order
  std::deque<Pending> queries_;
  std::deque<QueryNode> v_queue_;
  std::vector<QueryNode> i_queue_;
  std::vector<const QueryNode*> ptrs_;
};

}  // namespace

std::unique_ptr<Schedule> makeChcSchedule(const QueryScheduleDesc& d) {
  return std::make_unique<ChcSchedule>(d.chc_batch, d.chc_visible_interval);
}

}  // namespace logrid::detail
