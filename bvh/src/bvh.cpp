#include "logrid/bvh/bvh.hpp"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <functional>
#include <future>
#include <limits>
#include <sstream>
#include <thread>
#include <utility>

#include "boxes.hpp"
#include "logrid/error.hpp"

namespace logrid::bvh {

std::uint64_t FlatHierarchy::nextRevision() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

std::string validateBuildArgs(const BuildArgs& args) {
  std::ostringstream out;
  if (args.max_leaf_size < 1) {
    out << "bvh: max_leaf_size " << args.max_leaf_size << " is invalid; use 1 or more";
  } else if (args.max_children != 2 && args.max_children != 4 && args.max_children != 8) {
    out << "bvh: max_children " << args.max_children << " is invalid; use 2, 4 or 8";
  } else if (args.threads > 1024) {
    out << "bvh: threads " << args.threads
        << " is out of range; use 0 (one per hardware thread) up to 1024";
  }
  return out.str();
}

namespace {

using detail::checkBox;
using detail::emptyBox;
using detail::grow;
using detail::kInf;

void grow(Aabb& a, const float* p) {
  a.min.x = std::min(a.min.x, p[0]), a.min.y = std::min(a.min.y, p[1]);
  a.min.z = std::min(a.min.z, p[2]), a.max.x = std::max(a.max.x, p[0]);
  a.max.y = std::max(a.max.y, p[1]), a.max.z = std::max(a.max.z, p[2]);
}

// A primitive's centroid beside its number, so that the partition below compares and
// moves contiguous memory (with numbers into a separate centroid array, every
// comparison was a cache miss at the city's 35 million triangles).
struct Item {
  float centroid[3];
  std::uint32_t id;
};

// Phase 1: partition `items` in place by recursive object-median splits. The shape of
// the split tree depends only on the counts (left half = count / 2), so the layout phase
// can recompute it without recording anything.
class Partitioner {
 public:
  Partitioner(std::vector<Item>& items, std::uint32_t leaf_size, unsigned parallel_depth)
      : items_(items), leaf_(leaf_size), parallel_depth_(parallel_depth) {}

  void run(std::size_t begin, std::size_t end, unsigned depth) {
    if (end - begin <= leaf_) return;
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    for (std::size_t i = begin; i < end; ++i) {
      const float* c = items_[i].centroid;
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    }
    const std::size_t mid = begin + (end - begin) / 2;
    // Ties broken by number: deterministic whatever the standard library's nth_element.
    std::nth_element(items_.begin() + std::ptrdiff_t(begin), items_.begin() + std::ptrdiff_t(mid),
                     items_.begin() + std::ptrdiff_t(end), [axis](const Item& a, const Item& b) {
                       const float ka = a.centroid[axis], kb = b.centroid[axis];
                       return ka < kb || (ka == kb && a.id < b.id);
                     });
    if (depth < parallel_depth_ && end - begin > 100000) {
      auto left = std::async(std::launch::async, [&] { run(begin, mid, depth + 1); });
      run(mid, end, depth + 1);
      left.get();
    } else {
      run(begin, mid, depth + 1);
      run(mid, end, depth + 1);
    }
  }

 private:
  std::vector<Item>& items_;
  std::uint32_t leaf_;
  unsigned parallel_depth_;
};

struct Range {
  std::size_t begin;
  std::size_t end;
};

// The children of a node over `r`: the binary split tree below it, collapsed
// log2(max_children) levels deep (a child is a binary leaf or at that depth).
void childRanges(Range r, std::uint32_t leaf, std::uint32_t max_children, std::vector<Range>& out) {
  out.clear();
  out.push_back(r);
  for (std::uint32_t k = 1; k < max_children; k *= 2) {
    std::vector<Range> next;
    for (Range c : out) {
      if (c.end - c.begin <= leaf) {
        next.push_back(c);
      } else {
        const std::size_t mid = c.begin + (c.end - c.begin) / 2;
        next.push_back({c.begin, mid});
        next.push_back({mid, c.end});
      }
    }
    out.swap(next);
  }
}

// Phase 2: lays out nodes breadth first (children contiguous, after their parent) and
// records each leaf's primitive range.
struct Layout {
  std::vector<FlatHierarchy::Node> nodes;
  std::vector<Range> leaf_ranges;  // indexed by node; empty range for inner nodes
};

Layout layOut(std::size_t count, std::uint32_t leaf, std::uint32_t max_children) {
  Layout l;
  if (count == 0) return l;
  l.nodes.push_back({});
  l.leaf_ranges.push_back({0, count});
  std::vector<Range> children;
  for (std::size_t n = 0; n < l.nodes.size(); ++n) {
    const Range r = l.leaf_ranges[n];
    if (r.end - r.begin <= leaf) continue;  // a leaf keeps its range
    childRanges(r, leaf, max_children, children);
    l.nodes[n].first_child = static_cast<std::uint32_t>(l.nodes.size());
    l.nodes[n].child_count = static_cast<std::uint32_t>(children.size());
    l.leaf_ranges[n] = {0, 0};
    for (Range c : children) {
      l.nodes.push_back({});
      l.leaf_ranges.push_back(c);
    }
  }
  return l;
}

unsigned parallelDepth(const BuildArgs& args) {
  unsigned threads =
      args.threads ? args.threads : std::max(1u, std::thread::hardware_concurrency());
  unsigned depth = 0;
  while ((1u << depth) < threads) ++depth;
  return depth;
}

// The primitives' numbers in the order of the partitioned items; `items` is spent.
std::vector<std::uint32_t> partitionedOrder(std::vector<Item>& items, const BuildArgs& args) {
  Partitioner(items, args.max_leaf_size, parallelDepth(args)).run(0, items.size(), 0);
  std::vector<std::uint32_t> order;
  order.reserve(items.size());
  for (const Item& item : items) order.push_back(item.id);
  items = {};
  return order;
}

// Phase 3: boxes bottom-up; children have larger indices than parents.
template <typename LeafBox>
void computeBoxes(std::vector<FlatHierarchy::Node>& nodes, LeafBox leafBox) {
  for (std::size_t n = nodes.size(); n-- > 0;) {
    FlatHierarchy::Node& node = nodes[n];
    Aabb box = emptyBox();
    if (node.child_count == 0) {
      box = leafBox(n);
    } else {
      for (std::uint32_t c = 0; c < node.child_count; ++c)
        grow(box, nodes[node.first_child + c].box);
    }
    node.box = box;
  }
}

}  // namespace

std::size_t FlatHierarchy::memoryBytes() const {
  return nodes_.capacity() * sizeof(Node) + objects_.capacity() * sizeof(ObjectId) +
         object_triangles_.capacity() * sizeof(std::uint32_t);
}

std::uint32_t FlatHierarchy::depth() const {
  if (nodes_.empty()) return 0;
  std::vector<std::uint32_t> level(nodes_.size(), 1);
  std::uint32_t deepest = 1;
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    for (std::uint32_t c = 0; c < nodes_[n].child_count; ++c) {
      level[nodes_[n].first_child + c] = level[n] + 1;
    }
    deepest = std::max(deepest, level[n]);
  }
  return deepest;
}

Status FlatHierarchy::tryRefit(const std::vector<Aabb>& object_boxes) {
  for (ObjectId id : objects_) {
    if (id >= object_boxes.size()) {
      std::ostringstream out;
      out << "FlatHierarchy::refit: object " << id << " has no box (" << object_boxes.size()
          << " boxes given)";
      return Status(ErrorCode::InvalidArgument, out.str());
    }
  }
  // Checked before anything changes: a NaN box would otherwise vanish from the union
  // (std::min and std::max skip NaN) and its object could be culled with its leaf.
  for (ObjectId id : objects_) {
    if (Status s = checkBox("FlatHierarchy::refit", id, object_boxes[id]); !s) return s;
  }
  computeBoxes(nodes_, [&](std::size_t n) {
    Aabb box = emptyBox();
    for (std::uint32_t i = 0; i < nodes_[n].object_count; ++i) {
      grow(box, object_boxes[objects_[nodes_[n].first_object + i]]);
    }
    return box;
  });
  return {};
}

void FlatHierarchy::buildLinks() const {
  if (links_revision_ == revision_ && parent_.size() == nodes_.size()) return;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  parent_.assign(nodes_.size(), kNone);
  std::uint32_t max_object = 0;
  for (ObjectId id : objects_) max_object = std::max(max_object, id);
  leaf_of_.assign(objects_.empty() ? 0 : std::size_t(max_object) + 1, kNone);
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    const Node& node = nodes_[n];
    for (std::uint32_t c = 0; c < node.child_count; ++c) {
      parent_[node.first_child + c] = static_cast<std::uint32_t>(n);
    }
    for (std::uint32_t i = 0; i < node.object_count; ++i) {
      leaf_of_[objects_[node.first_object + i]] = static_cast<std::uint32_t>(n);
    }
  }
  links_revision_ = revision_;
}

Result<std::size_t> FlatHierarchy::tryRefit(const std::vector<Aabb>& object_boxes,
                                            const std::vector<ObjectId>& moved) {
  buildLinks();
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  for (ObjectId id : moved) {
    if (id >= object_boxes.size() || id >= leaf_of_.size() || leaf_of_[id] == kNone) {
      std::ostringstream out;
      out << "FlatHierarchy::refit: moved object " << id << " is not in the hierarchy or has no "
          << "box (" << object_boxes.size() << " boxes given)";
      return Status(ErrorCode::InvalidArgument, out.str());
    }
    if (Status s = checkBox("FlatHierarchy::refit", id, object_boxes[id]); !s) return s;
  }
  // The nodes to recompute: the moved objects' leaves and their ancestors, each once.
  std::vector<std::uint32_t> dirty;
  std::vector<std::uint8_t> seen(nodes_.size(), 0);
  for (ObjectId id : moved) {
    for (std::uint32_t n = leaf_of_[id]; n != kNone && !seen[n]; n = parent_[n]) {
      seen[n] = 1;
      dirty.push_back(n);
    }
  }
  // Children have larger indices than their parents: recompute from the largest down.
  std::sort(dirty.begin(), dirty.end(), std::greater<>());
  for (std::uint32_t n : dirty) {
    Node& node = nodes_[n];
    Aabb box = emptyBox();
    for (std::uint32_t i = 0; i < node.object_count; ++i) {
      grow(box, object_boxes[objects_[node.first_object + i]]);
    }
    for (std::uint32_t c = 0; c < node.child_count; ++c)
      grow(box, nodes_[node.first_child + c].box);
    node.box = box;
  }
  return dirty.size();
}

double FlatHierarchy::surfaceAreaSum() const {
  double sum = 0;
  for (const Node& n : nodes_) {
    const double dx = double(n.box.max.x) - n.box.min.x, dy = double(n.box.max.y) - n.box.min.y,
                 dz = double(n.box.max.z) - n.box.min.z;
    sum += 2 * (dx * dy + dy * dz + dz * dx);
  }
  return sum;
}

Result<FlatHierarchy> tryBuildOverBoxes(const std::vector<Aabb>& boxes, const BuildArgs& args) {
  std::string problem = validateBuildArgs(args);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  if (boxes.size() >= std::numeric_limits<std::uint32_t>::max()) {
    return Status(ErrorCode::BadInput, "bvh: too many objects (at most 2^32 - 2)");
  }
  std::vector<Item> items;
  items.reserve(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Aabb& b = boxes[i];
    if (Status s = checkBox("bvh", i, b); !s) return s;
    items.push_back({{0.5f * b.min.x + 0.5f * b.max.x, 0.5f * b.min.y + 0.5f * b.max.y,
                      0.5f * b.min.z + 0.5f * b.max.z},
                     static_cast<std::uint32_t>(i)});
  }
  const std::vector<std::uint32_t> order = partitionedOrder(items, args);

  Layout layout = layOut(boxes.size(), args.max_leaf_size, args.max_children);
  FlatHierarchy h;
  auto& nodes = h.mutableNodes();
  auto& objects = h.mutableObjects();
  nodes = std::move(layout.nodes);
  objects.reserve(boxes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const Range r = layout.leaf_ranges[n];
    if (nodes[n].child_count != 0) continue;
    nodes[n].first_object = static_cast<std::uint32_t>(objects.size());
    nodes[n].object_count = static_cast<std::uint32_t>(r.end - r.begin);
    objects.insert(objects.end(), order.begin() + std::ptrdiff_t(r.begin),
                   order.begin() + std::ptrdiff_t(r.end));
  }
  // The boxes were checked above: the refit cannot fail.
  const Status refitted = h.tryRefit(boxes);
  assert(refitted.ok() && "buildOverBoxes: the refit of checked boxes failed");
  (void)refitted;
  return h;
}

Result<TriangleHierarchy> tryBuildOverTriangles(const std::vector<float>& positions,
                                                const std::vector<std::uint32_t>& indices,
                                                BuildArgs args) {
  std::string problem = validateBuildArgs(args);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  if (positions.size() % 3 != 0 || indices.size() % 3 != 0) {
    return Status(ErrorCode::BadInput,
                  "bvh: positions and indices must come in threes (xyz, and three per triangle)");
  }
  const std::size_t vertices = positions.size() / 3, triangles = indices.size() / 3;
  if (triangles >= std::numeric_limits<std::uint32_t>::max()) {
    return Status(ErrorCode::BadInput, "bvh: too many triangles (at most 2^32 - 2)");
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!std::isfinite(positions[v])) {
      std::ostringstream out;
      out << "bvh: vertex " << v / 3 << " has a non-finite coordinate ("
          << "xyz"[v % 3] << " = " << positions[v]
          << "); positions must be finite: fix or drop the triangles using it";
      return Status(ErrorCode::BadInput, out.str());
    }
  }
  std::vector<Item> items;
  items.reserve(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (indices[t * 3 + std::size_t(k)] >= vertices) {
        std::ostringstream out;
        out << "bvh: triangle " << t << " uses vertex " << indices[t * 3 + std::size_t(k)]
            << " but there are only " << vertices << " vertices";
        return Status(ErrorCode::BadInput, out.str());
      }
    }
    const float* a = &positions[std::size_t(indices[t * 3 + 0]) * 3];
    const float* b = &positions[std::size_t(indices[t * 3 + 1]) * 3];
    const float* c = &positions[std::size_t(indices[t * 3 + 2]) * 3];
    items.push_back(
        {{(a[0] + b[0] + c[0]) / 3.0f, (a[1] + b[1] + c[1]) / 3.0f, (a[2] + b[2] + c[2]) / 3.0f},
         static_cast<std::uint32_t>(t)});
  }
  std::vector<std::uint32_t> order = partitionedOrder(items, args);

  Layout layout = layOut(triangles, args.max_leaf_size, args.max_children);
  TriangleHierarchy out;
  auto& nodes = out.hierarchy.mutableNodes();
  nodes = std::move(layout.nodes);
  // Chunks numbered in triangle order, so chunk c covers [chunk_first[c], chunk_first[c+1]).
  std::vector<std::uint32_t> leaves;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (nodes[n].child_count == 0) leaves.push_back(static_cast<std::uint32_t>(n));
  }
  std::sort(leaves.begin(), leaves.end(), [&](std::uint32_t a, std::uint32_t b) {
    return layout.leaf_ranges[a].begin < layout.leaf_ranges[b].begin;
  });
  auto& objects = out.hierarchy.mutableObjects();
  objects.resize(leaves.size());
  out.chunk_first.reserve(leaves.size() + 1);
  for (std::size_t c = 0; c < leaves.size(); ++c) {
    FlatHierarchy::Node& leaf = nodes[leaves[c]];
    objects[c] = static_cast<ObjectId>(c);
    leaf.first_object = static_cast<std::uint32_t>(c);
    leaf.object_count = 1;
    out.chunk_first.push_back(static_cast<std::uint32_t>(layout.leaf_ranges[leaves[c]].begin));
  }
  out.chunk_first.push_back(static_cast<std::uint32_t>(triangles));
  computeBoxes(nodes, [&](std::size_t n) {
    Aabb box = emptyBox();
    const Range r = layout.leaf_ranges[n];
    for (std::size_t i = r.begin; i < r.end; ++i) {
      const std::size_t t = order[i];
      for (int k = 0; k < 3; ++k)
        grow(box, &positions[std::size_t(indices[t * 3 + std::size_t(k)]) * 3]);
    }
    return box;
  });
  out.triangle_order = std::move(order);
  return out;
}

}  // namespace logrid::bvh
