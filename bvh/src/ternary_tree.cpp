#include "logrid/bvh/ternary_tree.hpp"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "boxes.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::bvh {
namespace {

using detail::checkBox;
using detail::emptyBox;
using detail::grow;

float lo(const Aabb& b, int axis) { return axis == 0 ? b.min.x : axis == 1 ? b.min.y : b.min.z; }
float hi(const Aabb& b, int axis) { return axis == 0 ? b.max.x : axis == 1 ? b.max.y : b.max.z; }
void setLo(Aabb& b, int axis, float v) {
  (axis == 0 ? b.min.x : axis == 1 ? b.min.y : b.min.z) = v;
}
void setHi(Aabb& b, int axis, float v) {
  (axis == 0 ? b.max.x : axis == 1 ? b.max.y : b.max.z) = v;
}

// inner lies within outer (closed boxes).
bool contains(const Aabb& outer, const Aabb& inner) {
  return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
         inner.max.x <= outer.max.x && inner.max.y <= outer.max.y && inner.max.z <= outer.max.z;
}

bool sameBox(const Aabb& a, const Aabb& b) {
  return a.min.x == b.min.x && a.min.y == b.min.y && a.min.z == b.min.z && a.max.x == b.max.x &&
         a.max.y == b.max.y && a.max.z == b.max.z;
}

std::uint64_t nextTreeRevision() {
  // Distinct from every FlatHierarchy revision as well: the top bit is set.
  static std::atomic<std::uint64_t> counter{0};
  return (std::uint64_t{1} << 63) | ++counter;
}

// Rows of a tall rectangle a pixel-reading source counts for the statistics (measure()).
constexpr std::int32_t kSampledRows = 8;

}  // namespace

// Records what the culler tested in the frame after an update: the boxes' projections
// and answers, for measure().
class TernaryTree::Recorder final : public CullObserver {
 public:
  struct Entry {
    NodeId node;
    BoxProjection projection;
    Visibility visibility;
  };
  std::vector<Entry> entries;
  void onTested(NodeId node, const BoxProjection& p, Visibility v) override {
    entries.push_back({node, p, v});
  }
};

Result<TernaryTree> TernaryTree::create(const std::vector<Aabb>& boxes, const TernaryDesc& desc) {
  MotionDesc check;
  check.ternary = desc;
  std::string problem = validateMotionDesc(check);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  if (boxes.size() >= std::size_t(kObjectNode)) {
    return Status(ErrorCode::BadInput, "TernaryTree: too many objects (at most 2^31 - 1)");
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (Status s = checkBox("TernaryTree", i, boxes[i]); !s) return s;
  }
  return TernaryTree(Checked{}, boxes, desc);
}

TernaryTree::TernaryTree(Checked, const std::vector<Aabb>& boxes, const TernaryDesc& desc)
    : desc_(desc), revision_(nextTreeRevision()), recorder_(std::make_unique<Recorder>()) {
  if (desc_.build_leaf == 0) desc_.build_leaf = desc_.o_split;
  touched_.resize(std::size_t(desc_.still_frames) + 1);
  objects_.resize(boxes.size());
  Aabb bounds = emptyBox();
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    objects_[i].box = boxes[i];
    grow(bounds, boxes[i]);
  }
  Node root;
  root.cell = boxes.empty() ? Aabb{} : bounds;
  root_ = allocate(root);
  for (std::size_t i = 0; i < boxes.size(); ++i) insert(static_cast<ObjectId>(i), root_);
  buildRecursive(root_);
  // Nothing has moved yet: every node may have its tight box from the start.
  std::vector<std::uint32_t> all;
  for (std::uint32_t n = 0; n < nodes_.size(); ++n) {
    if (!nodes_[n].alive) continue;
    nodes_[n].last_change = -std::int64_t(desc_.still_frames) - 1;
    nodes_[n].created = -1;
    all.push_back(n);
  }
  for (auto& list : touched_) list.clear();
  std::sort(all.begin(), all.end(),
            [&](std::uint32_t a, std::uint32_t b) { return nodes_[a].depth > nodes_[b].depth; });
  for (std::uint32_t n : all) computeBox(n);
}

TernaryTree::TernaryTree(TernaryTree&&) noexcept = default;
TernaryTree& TernaryTree::operator=(TernaryTree&&) noexcept = default;
TernaryTree::~TernaryTree() = default;

std::uint32_t TernaryTree::allocate(const Node& node) {
  std::uint32_t id;
  if (!free_.empty()) {
    id = free_.back();
    free_.pop_back();
    nodes_[id] = node;
  } else {
    id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(node);
  }
  nodes_[id].alive = true;
  nodes_[id].created = frame_;
  nodes_[id].last_change = frame_;
  nodes_[id].measured = -1;
  nodes_[id].box = nodes_[id].cell;
  touch(id);
  return id;
}

void TernaryTree::release(std::uint32_t node) {
  assert(nodes_[node].objects.empty() && "TernaryTree::release: node still holds objects");
  nodes_[node].alive = false;
  nodes_[node].objects.clear();
  nodes_[node].objects.shrink_to_fit();
  nodes_[node].subtree_objects = 0;
  free_.push_back(node);
}

NodeId TernaryTree::root() const {
  return root_ != kNone && nodes_[root_].subtree_objects > 0 ? root_ : kNoNode;
}

std::uint32_t TernaryTree::childCount(NodeId node) const {
  if (node & kObjectNode) return 0;
  const Node& n = nodes_[node];
  std::uint32_t count = desc_.object_nodes ? static_cast<std::uint32_t>(n.objects.size()) : 0;
  if (n.kind != Kind::Inner) return count;
  for (std::uint32_t c : n.child) count += c != kNone && nodes_[c].subtree_objects > 0;
  return count;
}

NodeId TernaryTree::child(NodeId node, std::uint32_t index) const {
  const Node& n = nodes_[node];
  if (n.kind == Kind::Inner) {
    for (std::uint32_t c : n.child) {
      if (c != kNone && nodes_[c].subtree_objects > 0 && index-- == 0) return c;
    }
  }
  assert(desc_.object_nodes && index < n.objects.size() &&
         "TernaryTree::child: index out of range");
  return kObjectNode | n.objects[index];
}

double TernaryTree::measuredRatio(NodeId node) const {
  const Node& n = nodes_[node];
  return n.measured >= 0 ? double(n.ratio) : -1.0;
}

void TernaryTree::setMeasuredRatio(NodeId node, double ratio) {
  nodes_[node].measured = frame_;
  nodes_[node].ratio = static_cast<float>(ratio);
  last_measure_ = frame_;
}

// Marks a node and its ancestors as changed in this update.
void TernaryTree::touch(std::uint32_t node) {
  std::vector<std::uint32_t>& list = touched_[std::size_t(frame_) % touched_.size()];
  for (std::uint32_t n = node; n != kNone; n = nodes_[n].parent) {
    if (nodes_[n].last_change == frame_ && n != node) break;  // the rest is marked
    nodes_[n].last_change = frame_;
    list.push_back(n);
  }
}

void TernaryTree::insert(ObjectId id, std::uint32_t node) {
  ObjectSlot& slot = objects_[id];
  slot.node = node;
  slot.index = static_cast<std::uint32_t>(nodes_[node].objects.size());
  nodes_[node].objects.push_back(id);
  for (std::uint32_t n = node; n != kNone; n = nodes_[n].parent) ++nodes_[n].subtree_objects;
  touch(node);
}

void TernaryTree::remove(ObjectId id) {
  ObjectSlot& slot = objects_[id];
  Node& node = nodes_[slot.node];
  const ObjectId last = node.objects.back();
  node.objects[slot.index] = last;
  objects_[last].index = slot.index;
  node.objects.pop_back();
  for (std::uint32_t n = slot.node; n != kNone; n = nodes_[n].parent) --nodes_[n].subtree_objects;
  touch(slot.node);
  slot.node = kNone;
}

bool TernaryTree::belongs(std::uint32_t node, const Aabb& box) const {
  const Node& n = nodes_[node];
  // An object outside the root's cell stays with the root.
  if (node == root_ && !contains(n.cell, box)) return true;
  auto straddles = [&](const Node& inner) {
    return !(hi(box, inner.axis) <= inner.plane) && !(lo(box, inner.axis) >= inner.plane);
  };
  switch (n.kind) {
    case Kind::Leaf: return contains(n.cell, box);
    case Kind::Straddle: {
      const Node& p = nodes_[n.parent];
      return contains(p.cell, box) && straddles(p);
    }
    case Kind::Inner: return !desc_.third_child && contains(n.cell, box) && straddles(n);
  }
  return false;
}

std::uint32_t TernaryTree::descend(std::uint32_t from, const Aabb& box) const {
  std::uint32_t n = from;
  for (;;) {
    const Node& node = nodes_[n];
    if (node.kind != Kind::Inner) return n;
    if (hi(box, node.axis) <= node.plane) {
      n = node.child[0];
    } else if (lo(box, node.axis) >= node.plane) {
      n = node.child[1];
    } else {
      return desc_.third_child ? node.child[2] : n;
    }
  }
}

void TernaryTree::buildRecursive(std::uint32_t leaf) {
  const Node& n = nodes_[leaf];
  if (n.objects.size() < desc_.build_leaf || n.depth >= desc_.max_depth) return;
  const int axis = chooseAxis(n.cell, {});
  const float plane = 0.5f * lo(n.cell, axis) + 0.5f * hi(n.cell, axis);
  if (!splitWorthwhile(leaf, axis, plane)) return;
  split(leaf, {});
  const std::uint32_t below = nodes_[leaf].child[0], above = nodes_[leaf].child[1];
  buildRecursive(below);
  buildRecursive(above);
}

int TernaryTree::chooseAxis(const Aabb& cell, const DVec3& view) const {
  const double extent[3] = {double(cell.max.x) - cell.min.x, double(cell.max.y) - cell.min.y,
                            double(cell.max.z) - cell.min.z};
  int longest = 0;
  for (int a = 1; a < 3; ++a) {
    if (extent[a] > extent[longest]) longest = a;
  }
  const double v[3] = {std::fabs(view.x), std::fabs(view.y), std::fabs(view.z)};
  if (!desc_.view_dependent_split || !(v[0] + v[1] + v[2] > 0)) return longest;
  // §3.4: the plane parallel to the cell's side whose normal is most aligned with the
  // view, i.e. the axis along which the viewer looks; not when that side is very short.
  int facing = 0;
  for (int a = 1; a < 3; ++a) {
    if (v[a] > v[facing]) facing = a;
  }
  return extent[facing] >= extent[longest] / 8 ? facing : longest;
}

bool TernaryTree::splitWorthwhile(std::uint32_t leaf, int axis, float plane) const {
  const Node& n = nodes_[leaf];
  if (!(lo(n.cell, axis) < plane && plane < hi(n.cell, axis))) return false;  // too thin
  for (ObjectId id : n.objects) {
    const Aabb& b = objects_[id].box;
    if (!contains(n.cell, b)) continue;  // the root's outside objects stay
    if (hi(b, axis) <= plane || lo(b, axis) >= plane) return true;
  }
  return false;  // everything would straddle: nothing gained
}

void TernaryTree::split(std::uint32_t leaf, const DVec3& view) {
  const int axis = chooseAxis(nodes_[leaf].cell, view);
  const float plane = 0.5f * lo(nodes_[leaf].cell, axis) + 0.5f * hi(nodes_[leaf].cell, axis);
  Node below, above, straddle;
  below.cell = above.cell = straddle.cell = nodes_[leaf].cell;
  setHi(below.cell, axis, plane);
  setLo(above.cell, axis, plane);
  below.parent = above.parent = straddle.parent = leaf;
  below.depth = above.depth = straddle.depth = nodes_[leaf].depth + 1;
  straddle.kind = Kind::Straddle;
  const std::uint32_t c0 = allocate(below);
  const std::uint32_t c1 = allocate(above);
  const std::uint32_t c2 = desc_.third_child ? allocate(straddle) : kNone;
  Node& n = nodes_[leaf];
  n.kind = Kind::Inner;
  n.axis = static_cast<std::uint8_t>(axis);
  n.plane = plane;
  n.child[0] = c0;
  n.child[1] = c1;
  n.child[2] = c2;
  const std::vector<ObjectId> held = n.objects;
  for (ObjectId id : held) {
    const Aabb& b = objects_[id].box;
    if (!contains(nodes_[leaf].cell, b)) continue;  // the root keeps what lies outside it
    const std::uint32_t target = descend(leaf, b);
    if (target == leaf) continue;
    remove(id);
    insert(id, target);
  }
  touch(leaf);
}

void TernaryTree::merge(std::uint32_t inner) {
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t c = nodes_[inner].child[k];
    if (c == kNone) continue;
    const std::vector<ObjectId> held = nodes_[c].objects;
    for (ObjectId id : held) {
      remove(id);
      insert(id, inner);
    }
    nodes_[inner].child[k] = kNone;
    release(c);
  }
  Node& n = nodes_[inner];
  n.kind = Kind::Leaf;
  n.created = frame_;
  n.measured = -1;
  touch(inner);
}

void TernaryTree::splitMerge(const DVec3& view, UpdateStats& stats) {
  // Statistics of the last culled frame, taken after the previous update. Nodes that
  // existed then and were not measured were not reached by the traversal: ratio 0.
  if (last_measure_ != frame_ - 1) return;
  auto existed = [&](const Node& n) { return n.alive && n.created < frame_; };
  auto ratio = [&](const Node& n) { return n.measured == frame_ - 1 ? double(n.ratio) : 0.0; };
  std::vector<std::uint32_t> to_split, to_merge;
  for (std::uint32_t id = 0; id < nodes_.size(); ++id) {
    const Node& n = nodes_[id];
    if (!existed(n)) continue;
    if (n.kind == Kind::Leaf) {
      if (n.objects.size() >= desc_.o_split && ratio(n) >= desc_.r_split &&
          n.depth < desc_.max_depth) {
        to_split.push_back(id);
      }
      continue;
    }
    if (n.kind != Kind::Inner) continue;
    bool all = true;
    std::size_t total = n.objects.size();
    for (std::uint32_t c : n.child) {
      if (c == kNone) continue;
      const Node& k = nodes_[c];
      if (k.kind == Kind::Inner || !existed(k) || k.objects.size() > desc_.o_merge ||
          ratio(k) > desc_.r_merge) {
        all = false;
        break;
      }
      total += k.objects.size();
    }
    // Our guard against the split/merge cycle the paper's constants allow (see header).
    if (all && total < desc_.o_split) to_merge.push_back(id);
  }
  for (std::uint32_t id : to_merge) {
    merge(id);
    ++stats.merges;
  }
  for (std::uint32_t id : to_split) {
    const Node& n = nodes_[id];
    const int axis = chooseAxis(n.cell, view);
    const float plane = 0.5f * lo(n.cell, axis) + 0.5f * hi(n.cell, axis);
    if (!splitWorthwhile(id, axis, plane)) continue;
    split(id, view);
    ++stats.splits;
  }
  if (stats.merges + stats.splits > 0) revision_ = nextTreeRevision();
}

bool TernaryTree::eligibleForTight(const Node& n) const {
  return desc_.tight_boxes && n.subtree_objects > 0 &&
         frame_ - n.last_change >= std::int64_t(desc_.still_frames);
}

void TernaryTree::computeBox(std::uint32_t id) {
  Node& n = nodes_[id];
  Aabb box = emptyBox();
  n.tight = eligibleForTight(n);
  if (n.tight || n.kind == Kind::Straddle) {
    // §3.2 TightBox (children are tight too: they changed no later than this node), or
    // the third child's box of its objects (§3.1).
    for (ObjectId o : n.objects) grow(box, objects_[o].box);
    for (std::uint32_t c : n.child) {
      if (c != kNone && nodes_[c].subtree_objects > 0) grow(box, nodes_[c].box);
    }
  } else {
    box = n.cell;
    for (ObjectId o : n.objects) {
      if (!contains(n.cell, objects_[o].box)) grow(box, objects_[o].box);  // the root's
    }
  }
  n.box = box;
}

void TernaryTree::recomputeBoxes(UpdateStats& stats) {
  // The nodes changed in this update, and those whose subtree has now been still for
  // still_frames updates (they get their tight box).
  recompute_.clear();
  const std::size_t ring = touched_.size();
  for (std::uint32_t n : touched_[std::size_t(frame_) % ring]) {
    if (nodes_[n].alive) recompute_.push_back(n);
  }
  const std::int64_t ripe = frame_ - std::int64_t(desc_.still_frames);
  if (desc_.tight_boxes && ripe >= 0 && desc_.still_frames > 0) {
    for (std::uint32_t n : touched_[std::size_t(ripe) % ring]) {
      if (nodes_[n].alive && nodes_[n].last_change == ripe) recompute_.push_back(n);
    }
  }
  std::sort(recompute_.begin(), recompute_.end(), [&](std::uint32_t a, std::uint32_t b) {
    return nodes_[a].depth != nodes_[b].depth ? nodes_[a].depth > nodes_[b].depth : a < b;
  });
  recompute_.erase(std::unique(recompute_.begin(), recompute_.end()), recompute_.end());
  for (std::uint32_t n : recompute_) {
    computeBox(n);
    stats.tight_boxes += nodes_[n].tight;
  }
}

Result<UpdateStats> TernaryTree::tryUpdate(const MotionUpdate& u) {
  const auto start = std::chrono::steady_clock::now();
  UpdateStats stats;
  if (!u.boxes || !u.moved) {
    return Status(ErrorCode::InvalidArgument, "TernaryTree::update: boxes and moved must be given");
  }
  const std::vector<Aabb>& boxes = *u.boxes;
  // Checked before anything changes.
  for (ObjectId id : *u.moved) {
    if (id >= objects_.size() || id >= boxes.size()) {
      std::ostringstream out;
      out << "TernaryTree::update: moved object " << id << " is out of range (" << objects_.size()
          << " objects, " << boxes.size() << " boxes)";
      return Status(ErrorCode::InvalidArgument, out.str());
    }
    if (Status s = checkBox("TernaryTree::update", id, boxes[id]); !s) return s;
  }
  ++frame_;
  touched_[std::size_t(frame_) % touched_.size()].clear();
  for (ObjectId id : *u.moved) {
    const Aabb& box = boxes[id];
    ObjectSlot& slot = objects_[id];
    if (sameBox(box, slot.box)) continue;
    ++stats.moved;
    slot.box = box;
    if (belongs(slot.node, box)) {
      touch(slot.node);
      continue;
    }
    // Re-insert from the lowest ancestor whose cell holds the new box.
    std::uint32_t a = slot.node;
    if (nodes_[a].kind == Kind::Straddle) a = nodes_[a].parent;
    while (a != root_ && !contains(nodes_[a].cell, box)) a = nodes_[a].parent;
    const std::uint32_t target = contains(nodes_[a].cell, box) ? descend(a, box) : root_;
    if (target != slot.node) {
      remove(id);
      insert(id, target);
      ++stats.relocated;
    } else {
      touch(target);
    }
  }
  if (desc_.split_merge) splitMerge(u.view_direction, stats);
  recomputeBoxes(stats);
  recorder_->entries.clear();
  stats.seconds = secondsSince(start);
  return stats;
}

CullObserver* TernaryTree::observer() { return desc_.split_merge ? recorder_.get() : nullptr; }

MeasureStats TernaryTree::measure(const Camera& camera, DepthSource& depth) {
  (void)camera;  // the culler's projections of this frame are recorded
  MeasureStats out;
  if (!desc_.split_merge) return out;
  const auto start = std::chrono::steady_clock::now();
  const ReadCounters before = depth.counters();
  // A source that reads pixels pays per pixel: it counts every row of rectangles up to
  // kSampledRows rows and kSampledRows evenly spaced rows of taller ones (an estimate,
  // scaled to the rectangle). A hardware query pays per request: it counts the whole
  // rectangle at once.
  const bool sample_rows = depth.traits().reads_depth;
  std::vector<AreaRequest> requests;
  std::vector<std::uint32_t> asked;          // per Count request: its node
  std::vector<std::uint64_t> sampled;        // per node asked: pixels its requests cover
  std::vector<std::uint32_t> first_request;  // per node asked: its first request
  for (const Recorder::Entry& e : recorder_->entries) {
    if ((e.node & kObjectNode) || e.node >= nodes_.size() || !nodes_[e.node].alive) continue;
    Node& n = nodes_[e.node];
    if (n.kind == Kind::Inner) continue;  // only leaves are split or merged
    ++out.nodes;
    n.measured = frame_;
    if (e.visibility == Visibility::Occluded) {
      n.ratio = 0;
    } else if (e.projection.cls != ProjectionClass::Inside || e.projection.rect.empty()) {
      n.ratio = 1;  // crossing the near plane (or an invalid box): counts as fully visible
    } else {
      const PixelRect& r = e.projection.rect;
      const float threshold = e.projection.occlusionThreshold();
      first_request.push_back(static_cast<std::uint32_t>(requests.size()));
      asked.push_back(e.node);
      const std::int32_t rows = r.y1 - r.y0;
      if (!sample_rows || rows <= kSampledRows) {
        requests.push_back({r, AreaAsk::Count, threshold});
        sampled.push_back(std::uint64_t(r.area()));
      } else {
        for (std::int32_t k = 0; k < kSampledRows; ++k) {
          const std::int32_t y =
              r.y0 + std::int32_t((std::int64_t(2 * k + 1) * rows) / (2 * kSampledRows));
          requests.push_back({{r.x0, y, r.x1, y + 1}, AreaAsk::Count, threshold});
        }
        sampled.push_back(std::uint64_t(r.x1 - r.x0) * kSampledRows);
      }
    }
  }
  first_request.push_back(static_cast<std::uint32_t>(requests.size()));
  std::vector<AreaAnswer> answers(requests.size());
  if (!requests.empty()) {
    depth.submit(requests.data(), requests.size(), answers.data());
    depth.collect();
  }
  for (std::size_t i = 0; i < asked.size(); ++i) {
    std::uint64_t visible = 0;
    for (std::uint32_t q = first_request[i]; q < first_request[i + 1]; ++q) {
      visible += answers[q].count;
    }
    nodes_[asked[i]].ratio =
        static_cast<float>(std::min(1.0, double(visible) / double(sampled[i])));
  }
  last_measure_ = frame_;
  recorder_->entries.clear();
  const ReadCounters& after = depth.counters();
  out.requests = requests.size();
  out.counted = asked.size();
  out.pixels = after.pixels - before.pixels;
  out.queries = after.queries - before.queries;
  out.seconds = secondsSince(start);
  return out;
}

}  // namespace logrid::bvh
