#include "query_frame.hpp"

#include <cassert>

#include "query_prefilter.hpp"

namespace logrid::detail {

QueryFrame::QueryFrame(const Wiring& wiring, std::uint32_t frame)
    : w_(wiring),
      frame_(frame),
      pixels_(wiring.projector->camera().width * wiring.projector->camera().height) {}

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
      if (*decided == Visibility::Occluded && undrawn()) culled_undrawn_.push_back(n);
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
  Slot slot;
  if (w_.shape == QueryShape::Box) {
    slot.first = boxes_.size();
    for (std::size_t i = 0; i < count; ++i) {
      assert(nodes[i]->box && "QueryFrame::issue: call withoutQuery() first");
      boxes_.push_back(*nodes[i]->box);
    }
  } else {
    slot.first = rects_.size();
    for (std::size_t i = 0; i < count; ++i) {
      const BoxProjection& p = nodes[i]->projection;
      rects_.push_back({p.rect, p.occlusionThreshold()});
    }
  }
  slot.count = count;
  if (count > 1) ++w_.stats->multi_queries;
  const QueryHandle local = QueryHandle(slots_.size());
  slots_.push_back(slot);
  deferred_.push_back(local);
  if (!undrawn()) flushDeferred();
  return local;
}

void QueryFrame::send(QueryHandle local) {
  Slot& slot = slots_[local];
  slot.handle = w_.shape == QueryShape::Box
                    ? w_.queries->issueBoxes(boxes_.data() + slot.first, slot.count)
                    : w_.queries->issueRects(rects_.data() + slot.first, slot.count);
  slot.sent = true;
  slot.epoch = *w_.clear_epoch;
}

void QueryFrame::flushDeferred() {
  for (QueryHandle local : deferred_) send(local);
  deferred_.clear();
  boxes_.clear();  // nothing recorded waits any more
  rects_.clear();
  culled_undrawn_.clear();
}

bool QueryFrame::reconsiderCulled(Schedule& schedule) {
  const bool any = !culled_undrawn_.empty();
  for (QueryNode& n : culled_undrawn_) schedule.reconsider(*this, std::move(n));
  culled_undrawn_.clear();
  return any;
}

bool QueryFrame::ready(QueryHandle local) {
  const Slot& slot = slots_[local];
  return slot.sent && w_.queries->ready(slot.handle);
}

bool QueryFrame::answerable(QueryHandle local) {
  (void)local;
  if (undrawn()) return false;
  flushDeferred();
  return true;
}

Visibility QueryFrame::answer(QueryHandle local) {
  assert(answerable(local) && "QueryFrame::answer: the objects handed out must be drawn first");
  // log+hwq: the wait flushes the renderer anyway; bring the records the schedule asked
  // about up to date first, so that the boxes after this wait find them decided.
  if (w_.prefilter) w_.prefilter->refresh();
  const Slot& slot = slots_[local];
  const std::uint32_t count = w_.queries->result(slot.handle);
  if (slot.epoch != *w_.clear_epoch) return Visibility::Visible;  // cleared since
  return count > 0 ? Visibility::Visible : Visibility::Occluded;
}

void QueryFrame::tested(const QueryNode& n, Visibility v) {
  ++w_.stats->boxes_tested;
  if (v == Visibility::Occluded) ++w_.stats->boxes_occluded;
  if (w_.observe) w_.observe(n, v);
}

}  // namespace logrid::detail
