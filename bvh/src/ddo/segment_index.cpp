#include "segment_index.hpp"

#include <algorithm>
#include <cmath>

namespace logrid::ddo::detail {

SegmentIndex::SegmentIndex(const SceneMesh& mesh, unsigned threads) : mesh_(mesh) {
  bvh::BuildArgs args;
  args.max_leaf_size = 8;
  args.max_children = 2;
  args.threads = threads;
  tree_ = bvh::buildOverTriangles(*mesh.positions, *mesh.indices, args);
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

namespace {

// Does the segment a + s (b - a), s in [0, 1], meet the box (grown by a relative hair so
// that rounding never loses a triangle)?
bool segmentMeetsBox(const double* a, const double* d, const Aabb& box) {
  const double lo[3] = {box.min.x, box.min.y, box.min.z};
  const double hi[3] = {box.max.x, box.max.y, box.max.z};
  double s0 = 0, s1 = 1;
  for (int k = 0; k < 3; ++k) {
    const double pad = 1e-6 * (std::fabs(lo[k]) + std::fabs(hi[k]) + (hi[k] - lo[k])) + 1e-30;
    const double l = lo[k] - pad, h = hi[k] + pad;
    if (d[k] == 0) {
      if (a[k] < l || a[k] > h) return false;
      continue;
    }
    double ta = (l - a[k]) / d[k], tb = (h - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    s0 = std::max(s0, ta);
    s1 = std::min(s1, tb);
    if (s0 > s1) return false;
  }
  return true;
}

}  // namespace

bool SegmentIndex::crossings(const double* a, const double* b, const Slab& slab,
                             const MeshTopology& topology, std::vector<SegmentHit>& out,
                             std::vector<std::uint32_t>& stack) const {
  const auto& nodes = tree_.hierarchy.nodes();
  if (nodes.empty()) return true;
  const double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  stack.clear();
  stack.push_back(0);
  while (!stack.empty()) {
    const std::uint32_t n = stack.back();
    stack.pop_back();
    const bvh::FlatHierarchy::Node& node = nodes[n];
    if (!segmentMeetsBox(a, d, node.box)) continue;
    if (node.child_count > 0) {
      for (std::uint32_t c = 0; c < node.child_count; ++c) stack.push_back(node.first_child + c);
      continue;
    }
    const std::uint32_t chunk = tree_.hierarchy.objects()[node.first_object];
    for (std::uint32_t i = tree_.chunk_first[chunk]; i < tree_.chunk_first[chunk + 1]; ++i) {
      const std::uint32_t t = tree_.triangle_order[i];
      if (topology.degenerate(t) || !insideSlab(t, slab)) continue;
      double v[3][3];
      for (int k = 0; k < 3; ++k) {
        const float* p = mesh_.vertex(mesh_.corner(t, k));
        v[k][0] = p[0], v[k][1] = p[1], v[k][2] = p[2];
      }
      const Crossing c = segmentCrossesTriangle(a, b, v[0], v[1], v[2]);
      if (c == Crossing::Miss) continue;
      out.push_back({t, c});
      if (c == Crossing::Degenerate) return false;
    }
  }
  return true;
}

}  // namespace logrid::ddo::detail
