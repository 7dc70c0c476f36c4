// nohc: near-optimal hierarchical culling, Guthe, Balázs & Klein (EGSR 2006).
//
// Traversal (§4, figure 4): front to back through a distance queue, with a query queue
// whose head is taken whenever its query is finished. Unlike CHC, any node may be
// queried, on any level, and only where a query is reasonable (§4.1, §4.2, figure 5):
//   * never where drawing the node is cheaper than querying it (t_r < t_o), nor where
//     querying its children costs less than querying it (sum of C(child) < C(node));
//   * always where the node was occluded in the previous frame;
//   * a previously visible node only once C(H) <= n B(H), n the frames it has gone
//     without a query: the cost of a query C = t_o against its expected benefit
//     B = p_o (t_r - t_o) / log2(N_h + 1), spread over the levels of the hierarchy;
//   * a node that was outside the view frustum (or not visited) in the previous frame
//     only if the expected time with a query, t_o + (1 - p_o) t_r, is below t_r;
//   * an interior node if some child is cheaper to draw than to query (it is the last
//     level whose whole subtree can be queried), or if its benefit exceeds its children's
//     and T_o^o N_leaves > t_o (querying the leaves while drawing costs more).
// A leaf has no children to weigh against: the granularity rules of §4.2 are read as
// applying to interior nodes, and a leaf that passes §4.1 is queried.
// Latency (§4.3): the children of a queried node are queued at once if the node was
// visible or outside the frustum in the previous frame, and only after its answer if it
// was occluded; an answer "occluded" for a node whose children were queued removes them
// (and what they queued) again. A query counts as finished when it answered an
// availability poll, which is used only where the calibration found a poll no dearer than
// issuing a query, or when N_q = ceil(T_o^l / min(T_o^s, T_o^o + T_r^s)) + 1 queries are in
// flight.
//
// The model (§3): the occlusion probability of a node from its screen coverage c_bb
// (here its projected rectangle's share of the viewport; the paper's formula needs a field
// of view, and logrid takes any matrix), the coverage of what was drawn before it,
// c_scr, accumulated as c_scr += (1 - c_scr) c of each object drawn, c = R_cov c_bb with
// R_cov = pi/4 (a sphere-like object that fills its box; logrid does not know the
// objects' surface areas), and p_cov = (sqrt(c_scr) - sqrt(c_bb))^2 where c_bb < c_scr,
// else 0; p_o = p_cov^2 / 2 if the node was visible last frame, p_cov if it was outside
// the frustum or not visited, 1 if it was occluded. Times (§3.2, Table 2, measured by
// zread/calibration.hpp): t_r = max(calls T_r^s, triangles T_r^Δ, 2 w h c T_r^f) over
// the subtree's objects and triangles (Hierarchy::objectTriangles, 1000 where unknown,
// the paper's largest object), t_o = max(T_o^s, w h c_bb T_o^f).
#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "query_frame.hpp"
#include "subtree_loads.hpp"

namespace logrid::detail {
namespace {

constexpr double kRcov = 0.785398163397448;  // pi / 4

class NohcSchedule final : public Schedule {
 public:
  explicit NohcSchedule(const HardwareParameters& hw) : hw_(hw) {
    const double per_query = std::min(hw.query_setup, hw.query_overhead + hw.render_setup);
    const double nq = per_query > 0 ? std::ceil(hw.query_latency / per_query) + 1 : 1;
    max_in_flight_ = std::size_t(std::clamp(nq, 1.0, 1024.0));
    use_poll_ = hw.poll <= hw.query_setup;
  }

  void begin(QueryFrame& f) override {
    if (!subtrees_ready_) measureSubtrees(f.hierarchy());
    distance_.clear();
    queries_.clear();
    c_scr_ = 0;
    pixels_ = double(f.viewportPixels());
    if (auto root = f.root()) {
      memory_[root->id].parent = kNoNode;
      distance_.push_back(std::move(*root));
    }
  }

  bool resume(QueryFrame& f) override {
    while (!distance_.empty() || !queries_.empty()) {
      while (!queries_.empty() && (distance_.empty() || firstFinished(f))) {
        if (!answer(f)) return false;
      }
      if (distance_.empty()) continue;
      std::pop_heap(distance_.begin(), distance_.end(), fartherFirst);
      QueryNode n = std::move(distance_.back());
      distance_.pop_back();
      if (cancelled(f, n.id)) continue;
      visit(f, n);
    }
    return true;
  }

  void reconsider(QueryFrame&, QueryNode node) override {
    distance_.push_back(std::move(node));
    std::push_heap(distance_.begin(), distance_.end(), fartherFirst);
  }
  void forget() override {
    memory_.clear();
    subtrees_ready_ = false;
  }

 private:
  enum class State : std::uint8_t { Unknown, Visible, Occluded, Outside };
  struct Record {
    std::uint32_t state_frame = 0;  // frame `state` was set in
    State state = State::Unknown;
    std::uint32_t last_query = 0;  // frame of its last query (0: never)
    std::uint32_t cancelled = 0;   // frame its subtree was withdrawn in
    NodeId parent = kNoNode;       // this frame's
    // Subtree totals (per hierarchy): draw calls, triangles, leaves.
    std::uint64_t calls = 0, triangles = 0, leaves = 0;
  };
  struct Pending {
    QueryHandle handle;
    QueryNode node;
    bool wait;  // children queued only after the answer
  };

  // Subtree totals (once per hierarchy), and N_h.
  void measureSubtrees(const Hierarchy& h) {
    const std::unordered_map<NodeId, SubtreeLoad> loads = subtreeLoads(h);
    nodes_ = loads.size();
    for (const auto& [node, load] : loads) {
      Record& r = memory_[node];
      r.calls = load.objects;
      r.triangles = load.triangles;
      r.leaves = load.leaves;
    }
    levels_ = std::log2(double(nodes_) + 1.0);
    subtrees_ready_ = true;
  }

  bool firstFinished(QueryFrame& f) {
    return queries_.size() >= max_in_flight_ || (use_poll_ && f.ready(queries_.front().handle));
  }

  State previous(const QueryFrame& f, const Record& r) const {
    return r.state_frame + 1 == f.frame() ? r.state : State::Unknown;
  }

  bool cancelled(const QueryFrame& f, NodeId node) {
    for (; node != kNoNode; node = memory_[node].parent) {
      if (memory_[node].cancelled == f.frame()) return true;
    }
    return false;
  }

  // The model of one node (§3).
  struct Estimate {
    double coverage;  // c_bb
    double render;    // t_r
    double query;     // t_o
    double occluded;  // p_o
    double cost() const { return query; }
  };
  Estimate estimate(const QueryNode& n, State prev) {
    const Record& r = memory_[n.id];
    Estimate e;
    e.coverage = std::min(1.0, double(n.projection.rect.area()) / pixels_);
    const double fragments = 2.0 * pixels_ * kRcov * e.coverage;  // two per pixel (§3.2.1)
    e.render =
        std::max({double(r.calls) * hw_.render_setup, double(r.triangles) * hw_.render_triangle,
                  fragments * hw_.render_fragment});
    e.query = std::max(hw_.query_setup, pixels_ * e.coverage * hw_.query_fragment);
    const double p_cov =
        e.coverage < c_scr_ ? std::pow(std::sqrt(c_scr_) - std::sqrt(e.coverage), 2.0) : 0.0;
    e.occluded = prev == State::Occluded  ? 1.0
                 : prev == State::Visible ? 0.5 * p_cov * p_cov
                                          : p_cov;
    return e;
  }
  double benefit(const Estimate& e) const {
    return e.occluded * (e.render - e.query) / std::max(levels_, 1.0);
  }

  // Figure 5, with §4.1's rule for nodes outside the frustum last frame.
  bool reasonable(QueryFrame& f, const QueryNode& n, State prev) {
    const Estimate e = estimate(n, prev);
    if (e.render < e.query) return false;
    const bool leaf = f.isLeaf(n.id);
    double children_cost = 0, children_benefit = 0;
    bool cheap_child = false;
    if (!leaf) {
      kids_.clear();
      const std::uint32_t count = f.hierarchy().childCount(n.id);
      for (std::uint32_t i = 0; i < count; ++i) {
        const QueryNode c = f.project(f.hierarchy().child(n.id, i));
        if (c.projection.cls == ProjectionClass::Outside) continue;  // costs nothing
        const Estimate ce = estimate(c, previous(f, memory_[c.id]));
        children_cost += ce.cost();
        children_benefit += benefit(ce);
        cheap_child |= ce.render < ce.query;
      }
      if (children_cost < e.cost()) return false;
    }
    if (prev == State::Occluded) return true;
    const Record& r = memory_[n.id];
    if (prev == State::Visible) {
      const double frames = r.last_query ? double(f.frame() - r.last_query) : 1e9;
      if (e.cost() > frames * benefit(e)) return false;
    } else {
      // Outside the frustum or not visited: query only if it is expected to pay now.
      return e.query + (1.0 - e.occluded) * e.render < e.render;
    }
    if (leaf || cheap_child) return true;
    return benefit(e) > children_benefit && hw_.query_overhead * double(r.leaves) > e.query;
  }

  void visit(QueryFrame& f, QueryNode& n) {
    Record& r = memory_[n.id];
    const State prev = previous(f, r);
    r.state = State::Occluded;  // SetVisible(false): pulled up by visible leaves
    r.state_frame = f.frame();
    if (const std::optional<Visibility> v = f.withoutQuery(n)) {
      if (*v == Visibility::Visible) {
        process(f, n, true);
      } else {
        memory_[n.id].state = *v == Visibility::ViewCulled ? State::Outside : State::Occluded;
      }
      return;
    }
    if (reasonable(f, n, prev)) {
      const bool wait = prev == State::Occluded;
      memory_[n.id].last_query = f.frame();
      queries_.push_back({f.issue(n), n, wait});
      if (!wait) process(f, n, false);
    } else {
      process(f, n, true);
    }
  }

  // Process(): a node's objects drawn, its children queued. `assume_visible`: no query
  // decides its visibility, so a leaf drawn counts as visible (and so do its ancestors).
  void process(QueryFrame& f, const QueryNode& n, bool assume_visible) {
    if (f.hierarchy().objectCount(n.id) > 0) {
      f.draw(n);
      const double c = kRcov * std::min(1.0, double(n.projection.rect.area()) / pixels_);
      c_scr_ += (1.0 - c_scr_) * c;
    }
    if (assume_visible && f.isLeaf(n.id)) setVisible(f, n.id);
    const std::size_t first = distance_.size();
    f.children(n.id, distance_);
    for (std::size_t i = first; i < distance_.size(); ++i) {
      memory_[distance_[i].id].parent = n.id;
      std::push_heap(distance_.begin(), distance_.begin() + std::ptrdiff_t(i) + 1, fartherFirst);
    }
  }

  // Visible this frame, with every ancestor (SetParentsVisible).
  void setVisible(const QueryFrame& f, NodeId node) {
    for (; node != kNoNode; node = memory_[node].parent) {
      Record& r = memory_[node];
      if (r.state_frame == f.frame() && r.state == State::Visible) break;
      r.state = State::Visible;
      r.state_frame = f.frame();
    }
  }

  // The answer of the oldest query; false (nothing done) if it must wait for the objects
  // handed out to be drawn.
  bool answer(QueryFrame& f) {
    if (!f.answerable(queries_.front().handle)) return false;
    Pending p = std::move(queries_.front());
    queries_.pop_front();
    const Visibility v = f.answer(p.handle);
    if (cancelled(f, p.node.id)) return true;  // an ancestor was found occluded meanwhile
    f.tested(p.node, v);
    if (v == Visibility::Visible) {
      memory_[p.node.id].state = State::Visible;
      if (f.isLeaf(p.node.id)) setVisible(f, p.node.id);
      if (p.wait) process(f, p.node, false);
    } else {
      memory_[p.node.id].state = State::Occluded;
      // Its subtree was queued at once: withdraw what is still queued of it.
      if (!p.wait) memory_[p.node.id].cancelled = f.frame();
    }
    return true;
  }

  HardwareParameters hw_;
  std::size_t max_in_flight_ = 1;
  bool use_poll_ = false;
  bool subtrees_ready_ = false;
  std::uint64_t nodes_ = 0;
  double levels_ = 1;
  double c_scr_ = 0;
  double pixels_ = 1;
  NodeMemory<Record> memory_;
  std::vector<QueryNode> distance_;  // min-heap on QueryNode::order
  std::deque<Pending> queries_;
  std::vector<QueryNode> kids_;
};

}  // namespace

std::unique_ptr<Schedule> makeNohcSchedule(const QueryScheduleDesc& d) {
  return std::make_unique<NohcSchedule>(d.hardware);
}

}  // namespace logrid::detail
