#include "segment_index.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace logrid::ddo::detail {

Result<SegmentIndex> SegmentIndex::create(const SceneMesh& mesh, unsigned threads) {
  bvh::BuildArgs args;
  args.max_leaf_size = 8;
  args.max_children = 2;
  args.threads = threads;
  Result<bvh::TriangleHierarchy> tree =
      bvh::tryBuildOverTriangles(*mesh.positions, *mesh.indices, args);
  if (!tree) return tree.status();
  return SegmentIndex(mesh, std::move(tree).value());
}

SegmentIndex::SegmentIndex(const SceneMesh& mesh, bvh::TriangleHierarchy tree)
    : mesh_(mesh), tree_(std::move(tree)) {
  if (!tree_.hierarchy.nodes().empty()) {
    const Aabb& root = tree_.hierarchy.nodes().front().box;
    const double extent =
        std::max({std::fabs(root.min.x), std::fabs(root.min.y), std::fabs(root.min.z),
                  std::fabs(root.max.x), std::fabs(root.max.y), std::fabs(root.max.z)});
    pad_ = 1e-9 * extent + 1e-30;  // rounding of the slab test is ~1e-16 relative
  }
}

std::size_t SegmentIndex::memoryBytes() const {
  return tree_.hierarchy.memoryBytes() + tree_.triangle_order.capacity() * 4 +
         tree_.chunk_first.capacity() * 4;
}

bool SegmentIndex::insideSlab(std::uint32_t t, const Slab& slab) const {
  for (int k = 0; k < 3; ++k) {
    const double x = mesh_.vertex(mesh_.corner(t, k))[slab.axis];
    if (!(x > slab.lo && x < slab.hi)) return false;
  }
  return true;
}

template <typename Visit>
void SegmentIndex::walk(const double* a, const double* b, const Slab& slab,
                        std::vector<std::uint32_t>& stack, const Visit& visit) const {
  const auto& nodes = tree_.hierarchy.nodes();
  if (nodes.empty()) return;
  double inv[3];
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    inv[k] = d != 0 ? 1.0 / d : HUGE_VAL;
  }
  stack.clear();
  stack.push_back(0);
  while (!stack.empty()) {
    const bvh::FlatHierarchy::Node& node = nodes[stack.back()];
    stack.pop_back();
    // Slab test of a + s (b - a), s in [0, 1], against the box grown by pad_.
    const double lo[3] = {double(node.box.min.x) - pad_, double(node.box.min.y) - pad_,
                          double(node.box.min.z) - pad_};
    const double hi[3] = {double(node.box.max.x) + pad_, double(node.box.max.y) + pad_,
                          double(node.box.max.z) + pad_};
    double s0 = 0, s1 = 1;
    bool meets = true;
    for (int k = 0; k < 3 && meets; ++k) {
      if (inv[k] == HUGE_VAL) {
        meets = a[k] >= lo[k] && a[k] <= hi[k];
        continue;
      }
      double ta = (lo[k] - a[k]) * inv[k], tb = (hi[k] - a[k]) * inv[k];
      if (ta > tb) std::swap(ta, tb);
      s0 = std::max(s0, ta);
      s1 = std::min(s1, tb);
      meets = s0 <= s1;
    }
    if (!meets) continue;
    if (node.child_count > 0) {
      for (std::uint32_t c = 0; c < node.child_count; ++c) stack.push_back(node.first_child + c);
      continue;
    }
    // A leaf whose (unpadded) box lies strictly inside the slab holds only slab triangles.
    const double box_lo = slab.axis == 0   ? node.box.min.x
                          : slab.axis == 1 ? node.box.min.y
                                           : node.box.min.z;
    const double box_hi = slab.axis == 0   ? node.box.max.x
                          : slab.axis == 1 ? node.box.max.y
                                           : node.box.max.z;
    const bool all_inside = box_lo > slab.lo && box_hi < slab.hi;
    if (box_hi <= slab.lo || box_lo >= slab.hi) continue;  // none inside
    const std::uint32_t chunk = tree_.hierarchy.objects()[node.first_object];
    for (std::uint32_t i = tree_.chunk_first[chunk]; i < tree_.chunk_first[chunk + 1]; ++i) {
      if (!visit(tree_.triangle_order[i], all_inside)) {
        stack.clear();
        return;
      }
    }
  }
}

void SegmentIndex::corners(std::uint32_t t, double v[3][3]) const {
  for (int k = 0; k < 3; ++k) {
    const float* p = mesh_.vertex(mesh_.corner(t, k));
    v[k][0] = p[0], v[k][1] = p[1], v[k][2] = p[2];
  }
}

bool SegmentIndex::meetsAny(const double* a, const double* b, const Slab& slab,
                            const MeshTopology& topology, std::vector<std::uint32_t>& stack) const {
  bool met = false;
  walk(a, b, slab, stack, [&](std::uint32_t t, bool inside) {
    if (topology.degenerate(t) || (!inside && !insideSlab(t, slab))) return true;
    double v[3][3];
    corners(t, v);
    met = segmentCrossesTriangle(a, b, v[0], v[1], v[2]) != Crossing::Miss;
    return !met;
  });
  return met;
}

bool SegmentIndex::crossings(const double* a, const double* b, const Slab& slab,
                             const MeshTopology& topology, std::vector<SegmentHit>& out,
                             std::vector<std::uint32_t>& stack) const {
  bool clean = true;
  walk(a, b, slab, stack, [&](std::uint32_t t, bool inside) {
    if (topology.degenerate(t) || (!inside && !insideSlab(t, slab))) return true;
    double v[3][3];
    corners(t, v);
    const Crossing c = segmentCrossesTriangle(a, b, v[0], v[1], v[2]);
    if (c == Crossing::Miss) return true;
    out.push_back({t, c});
    clean = c != Crossing::Degenerate;
    return clean;
  });
  return clean;
}

}  // namespace logrid::ddo::detail
