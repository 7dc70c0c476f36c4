// Occlusion-query sources for testing the query schedules without GL, with a
// deterministic latency: time is counted in ticks (one per query issued and per object
// drawn), and a query's answer is there `latency` ticks after its issue. result() before
// that waits (counted) and moves time on to the answer.
//
//   ScriptedQueries  answers by node: the test says which nodes are visible. Queries are
//                    mapped back to nodes through the boxes they draw (every query box
//                    contains its node's box, and the test trees keep boxes apart).
//   SoftwareQueries  answers from a software depth buffer as it is when the query is
//                    issued (as a GPU executes in order): a box counts the pixels of its
//                    projected rectangle at or beyond its nearest key minus its bias.
//                    Honest and conservative, for end-to-end tests against the oracle.
// Both log every issue, poll, result and draw, with the frame, for the scheduling tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "logrid/cpu/software_depth.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/occlusion_queries.hpp"
#include "logrid/projection.hpp"

namespace logrid::test {

// A hierarchy built by hand: boxes, children and objects per node (object id = node id).
class TestTree : public Hierarchy {
 public:
  struct Node {
    Aabb box;
    std::vector<NodeId> children;
    bool has_object = false;
  };
  std::vector<Node> nodes;
  std::uint64_t rev = 1;

  NodeId add(const Aabb& box, bool has_object) {
    nodes.push_back({box, {}, has_object});
    return NodeId(nodes.size() - 1);
  }
  void link(NodeId parent, NodeId child) { nodes[parent].children.push_back(child); }
  // Parent boxes as the union of their children's, bottom-up from the leaves.
  void fitBoxes() {
    for (std::size_t i = nodes.size(); i-- > 0;) {
      Node& n = nodes[i];
      for (NodeId c : n.children) {
        const Aabb& b = nodes[c].box;
        n.box.min = {std::min(n.box.min.x, b.min.x), std::min(n.box.min.y, b.min.y),
                     std::min(n.box.min.z, b.min.z)};
        n.box.max = {std::max(n.box.max.x, b.max.x), std::max(n.box.max.y, b.max.y),
                     std::max(n.box.max.z, b.max.z)};
      }
    }
  }
  bool isLeaf(NodeId n) const { return nodes[n].children.empty(); }

  NodeId root() const override { return nodes.empty() ? kNoNode : 0; }
  Aabb bounds(NodeId n) const override { return nodes[n].box; }
  std::uint32_t childCount(NodeId n) const override {
    return std::uint32_t(nodes[n].children.size());
  }
  NodeId child(NodeId n, std::uint32_t i) const override { return nodes[n].children[i]; }
  std::uint32_t objectCount(NodeId n) const override { return nodes[n].has_object ? 1 : 0; }
  ObjectId object(NodeId n, std::uint32_t) const override { return n; }
  std::uint64_t revision() const override { return rev; }
};

struct QueryEvent {
  enum Kind { Issue, Poll, Result, Draw } kind;
  std::uint32_t frame;
  std::vector<NodeId> nodes;  // Issue: the nodes queried; Draw: the object (= node) drawn
  QueryHandle handle = 0;
  bool waited = false;  // Result: had to wait
  std::uint32_t count = 0;
};

class LoggingQueries : public OcclusionQueries {
 public:
  std::uint32_t latency = 3;  // ticks
  std::uint32_t frame = 0;    // set by the test before each frame (for the log)
  std::vector<QueryEvent> log;
  std::size_t max_in_flight = 0;

  const char* queryName() const override { return "test"; }
  Status beginQueryFrame(const Camera& camera) override {
    camera_ = camera;
    return {};
  }
  Status endQueryFrame() override {
    EXPECT_TRUE(open_.empty()) << "frame " << frame << ": " << open_.size()
                               << " queries were never read";
    return {};
  }
  void noteDraw() override { ++tick_; }
  // The test's draw callback calls this (the log shows draws among the queries).
  void drawn(ObjectId id) { log.push_back({QueryEvent::Draw, frame, {id}, 0, false, 0}); }

  QueryHandle issueBoxes(const QueryBox* boxes, std::size_t count) override {
    std::vector<NodeId> nodes;
    std::uint32_t samples = 0;
    for (std::size_t i = 0; i < count; ++i) samples += answerBox(boxes[i], nodes);
    return open(nodes, samples, count);
  }
  QueryHandle issueRects(const RectQuery* rects, std::size_t count) override {
    std::uint32_t samples = 0;
    for (std::size_t i = 0; i < count; ++i) samples += answerRect(rects[i]);
    return open({}, samples, count);
  }
  bool ready(QueryHandle h) override {
    ++query_counters_.polls;
    log.push_back({QueryEvent::Poll, frame, {}, h, false, 0});
    return tick_ >= find(h).ready_at;
  }
  std::uint32_t result(QueryHandle h) override {
    const Open q = find(h);
    const bool waited = tick_ < q.ready_at;
    if (waited) {
      ++query_counters_.waits;
      tick_ = q.ready_at;
    }
    open_.erase(h);
    log.push_back({QueryEvent::Result, frame, q.nodes, h, waited, q.samples});
    return q.samples;
  }

  // Issue events of `frame` that include `node`.
  std::size_t issuesOf(NodeId node, std::uint32_t in_frame) const {
    std::size_t n = 0;
    for (const QueryEvent& e : log) {
      if (e.kind == QueryEvent::Issue && e.frame == in_frame &&
          std::count(e.nodes.begin(), e.nodes.end(), node) > 0) {
        ++n;
      }
    }
    return n;
  }
  std::vector<const QueryEvent*> events(std::uint32_t in_frame) const {
    std::vector<const QueryEvent*> out;
    for (const QueryEvent& e : log) {
      if (e.frame == in_frame) out.push_back(&e);
    }
    return out;
  }

 protected:
  virtual std::uint32_t answerBox(const QueryBox& box, std::vector<NodeId>& nodes) = 0;
  virtual std::uint32_t answerRect(const RectQuery& rect) = 0;
  const Camera& camera() const { return camera_; }

 private:
  struct Open {
    std::vector<NodeId> nodes;
    std::uint32_t samples = 0;
    std::uint64_t ready_at = 0;
  };
  QueryHandle open(std::vector<NodeId> nodes, std::uint32_t samples, std::size_t count) {
    const QueryHandle h = next_++;
    ++query_counters_.queries;
    query_counters_.boxes += count;
    log.push_back({QueryEvent::Issue, frame, nodes, h, false, samples});
    open_[h] = {std::move(nodes), samples, tick_ + latency};
    ++tick_;
    max_in_flight = std::max(max_in_flight, open_.size());
    return h;
  }
  const Open& find(QueryHandle h) {
    const auto it = open_.find(h);
    EXPECT_NE(it, open_.end()) << "handle " << h << " is not open";
    static const Open none;
    return it == open_.end() ? none : it->second;
  }

  Camera camera_;
  std::map<QueryHandle, Open> open_;
  QueryHandle next_ = 1;
  std::uint64_t tick_ = 0;
};

// Visibility scripted per node. A query box is mapped back to the node whose box centre
// it contains (TestTree's boxes keep the nodes of one level apart; the deepest match wins).
class ScriptedQueries : public LoggingQueries {
 public:
  explicit ScriptedQueries(const TestTree& tree) : tree_(tree) {}
  std::set<NodeId> visible;  // nodes whose queries find samples

 protected:
  std::uint32_t answerBox(const QueryBox& q, std::vector<NodeId>& nodes) override {
    const NodeId node = nodeOf(q.box);
    nodes.push_back(node);
    return visible.count(node) ? 1u : 0u;
  }
  std::uint32_t answerRect(const RectQuery&) override {
    ADD_FAILURE() << "ScriptedQueries answers box queries only";
    return 1;
  }

 private:
  NodeId nodeOf(const Aabb& q) const {
    // The node whose box is contained in the query box and is largest (a query box is
    // its node's box widened a little): children are smaller than their parents.
    NodeId best = kNoNode;
    double best_volume = -1;
    for (NodeId i = 0; i < tree_.nodes.size(); ++i) {
      const Aabb& b = tree_.nodes[i].box;
      if (b.min.x < q.min.x || b.min.y < q.min.y || b.min.z < q.min.z || b.max.x > q.max.x ||
          b.max.y > q.max.y || b.max.z > q.max.z) {
        continue;
      }
      const double v = double(b.max.x - b.min.x) * (b.max.y - b.min.y) * double(b.max.z - b.min.z);
      if (v > best_volume) {
        best = i;
        best_volume = v;
      }
    }
    EXPECT_NE(best, kNoNode) << "a query box that holds no node's box";
    return best;
  }
  const TestTree& tree_;
};

// Answers from a software depth buffer at issue time (see the top of the file).
class SoftwareQueries : public LoggingQueries {
 public:
  explicit SoftwareQueries(cpu::SoftwareDepthBuffer& buffer) : buffer_(buffer) {}

 protected:
  std::uint32_t answerBox(const QueryBox& q, std::vector<NodeId>&) override {
    const Projector projector(camera());
    const BoxProjection p = projector.project(q.box);
    if (p.cls == ProjectionClass::Outside) return 0;
    EXPECT_EQ(p.cls, ProjectionClass::Inside) << "a query box that crosses the near plane";
    return count(p.rect, p.occlusionThreshold() - q.depth_bias);
  }
  std::uint32_t answerRect(const RectQuery& r) override { return count(r.rect, r.threshold); }

 private:
  std::uint32_t count(const PixelRect& rect, float threshold) {
    std::uint32_t n = 0;
    buffer_.countAtOrBeyond(&rect, 1, threshold, &n);
    return n;
  }
  cpu::SoftwareDepthBuffer& buffer_;
};

}  // namespace logrid::test
