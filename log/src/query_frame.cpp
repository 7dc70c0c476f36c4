#include "query_frame.hpp"

#include <cassert>

#include "query_prefilter.hpp"

namespace logrid::detail {

QueryFrame::QueryFrame(const Wiring& wiring, std::uint32_t frame)
    : w_(wiring),
      frame_(frame),
      pixels_(wiring.projector->camera().width * wiring.projector->camera().height),
      epoch_at_start_(*wiring.clear_epoch) {}

QueryNode QueryFrame::project(NodeId node) const {
  QueryNode n;
  n.id = node;
  n.bounds = w_.hierarchy->bounds(node);
  n.projection = w_.projector->project(n.bounds);
  n.order = n.projection.near_key - n.projection.margin;
  return n;
}

std::optional<QueryNode> QueryFrame::root() {
  const NodeId r = w_.hierarchy->root();
  if (r == kNoNode) return std::nullopt;
  QueryNode n = project(r);
  if (n.projection.cls == ProjectionClass::Outside) {
    ++w_.stats->boxes_view_culled;
    return std::nullopt;
  }
  return n;
}

void QueryFrame::children(NodeId node, std::vector<QueryNode>& out) {
  const std::size_t first = out.size();
  const std::uint32_t count = w_.hierarchy->childCount(node);
  for (std::uint32_t i = 0; i < count; ++i) {
    QueryNode c = project(w_.hierarchy->child(node, i));
    if (c.projection.cls == ProjectionClass::Outside) {
      ++w_.stats->boxes_view_culled;  // children never visited
      continue;
    }
    out.push_back(std::move(c));
  }
  std::sort(out.begin() + std::ptrdiff_t(first), out.end(),
            [](const QueryNode& a, const QueryNode& b) { return a.order < b.order; });
}

std::optional<Visibility> QueryFrame::withoutQuery(QueryNode& n) {
  ++w_.stats->nodes_visited;
  switch (n.projection.cls) {
    case ProjectionClass::Outside: return Visibility::ViewCulled;
    case ProjectionClass::Invalid: ++w_.stats->invalid_boxes; return Visibility::Visible;
    case ProjectionClass::CrossesNear: ++w_.stats->boxes_near; return Visibility::Visible;
    case ProjectionClass::Inside: break;
  }
  if (w_.prefilter) {
    if (const auto decided = w_.prefilter->decide(n.projection)) {
      ++w_.stats->records_decided;
      tested(n, *decided);
      return decided;
    }
  }
  if (w_.shape == QueryShape::Box) {
    n.box = w_.projector->queryBox(n.bounds);
    // Its widened, biased faces would reach the near plane: visible, as a box crossing it.
    if (!n.box) {
      ++w_.stats->boxes_near;
      return Visibility::Visible;
    }
  } else {
    n.box = QueryBox{n.bounds, 0};  // the rectangle at the nearest depth needs no widening
  }
  return std::nullopt;
}

QueryHandle QueryFrame::issue(const QueryNode* const* nodes, std::size_t count) {
  assert(count > 0 && "QueryFrame::issue: a query needs a node");
  QueryHandle h;
  if (w_.shape == QueryShape::Box) {
    boxes_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      assert(nodes[i]->box && "QueryFrame::issue: call withoutQuery() first");
      boxes_.push_back(*nodes[i]->box);
    }
    h = w_.queries->issueBoxes(boxes_.data(), boxes_.size());
  } else {
    rects_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const BoxProjection& p = nodes[i]->projection;
      rects_.push_back({p.rect, p.occlusionThreshold()});
    }
    h = w_.queries->issueRects(rects_.data(), rects_.size());
  }
  if (count > 1) ++w_.stats->multi_queries;
  if (*w_.clear_epoch != epoch_at_start_) issued_epoch_[h] = *w_.clear_epoch;
  return h;
}

bool QueryFrame::ready(QueryHandle handle) { return w_.queries->ready(handle); }

Visibility QueryFrame::answer(QueryHandle handle) {
  // log+hwq: the wait flushes the renderer anyway; bring the records the schedule asked
  // about up to date first, so that the boxes after this wait find them decided.
  if (w_.prefilter) w_.prefilter->refresh();
  const std::uint32_t count = w_.queries->result(handle);
  if (*w_.clear_epoch != epoch_at_start_) {
    const auto it = issued_epoch_.find(handle);
    const std::uint64_t issued = it == issued_epoch_.end() ? epoch_at_start_ : it->second;
    if (it != issued_epoch_.end()) issued_epoch_.erase(it);
    if (issued != *w_.clear_epoch) return Visibility::Visible;  // cleared since
  }
  return count > 0 ? Visibility::Visible : Visibility::Occluded;
}

void QueryFrame::tested(const QueryNode& n, Visibility v) {
  ++w_.stats->boxes_tested;
  if (v == Visibility::Occluded) ++w_.stats->boxes_occluded;
  if (w_.observe) w_.observe(n, v);
}

}  // namespace logrid::detail
