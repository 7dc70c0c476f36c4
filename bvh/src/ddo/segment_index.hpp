// Which triangles a segment crosses: a bounding-volume hierarchy with small leaves over
// every triangle of the scene, walked along the segment. Internal to the preprocessing
// (the validity test's seeds and crossing counts).
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/ddo/mesh.hpp"
#include "predicates.hpp"
#include "topology.hpp"

namespace logrid::ddo::detail {

// Triangles strictly between two planes of an axis (lo < every vertex's coordinate < hi).
struct Slab {
  int axis = 0;
  double lo = 0;
  double hi = 0;
};

struct SegmentHit {
  std::uint32_t triangle;
  Crossing crossing;  // Cross or Degenerate
};

class SegmentIndex {
 public:
  // The index over `mesh`'s triangles, or the BVH build's error (a triangle it refuses).
  static Result<SegmentIndex> create(const SceneMesh& mesh, unsigned threads);

  // Appends to `out` every non-degenerate triangle inside `slab` that the segment a-b
  // crosses or grazes. Returns false as soon as one grazes (Degenerate), leaving `out`
  // incomplete.
  bool crossings(const double* a, const double* b, const Slab& slab, const MeshTopology& topology,
                 std::vector<SegmentHit>& out, std::vector<std::uint32_t>& stack) const;

  // True unless the segment a-b clearly misses every non-degenerate triangle inside
  // `slab` (a graze counts as meeting one). Stops at the first.
  bool meetsAny(const double* a, const double* b, const Slab& slab, const MeshTopology& topology,
                std::vector<std::uint32_t>& stack) const;

  bool insideSlab(std::uint32_t triangle, const Slab& slab) const;
  std::size_t memoryBytes() const;

 private:
  SegmentIndex(const SceneMesh& mesh, bvh::TriangleHierarchy tree);
  // Triangle t's corners, in double.
  void corners(std::uint32_t t, double v[3][3]) const;
  // Runs visit(triangle, inside_slab_known) for the triangles of every leaf whose box the
  // segment meets; visit returns false to stop.
  template <typename Visit>
  void walk(const double* a, const double* b, const Slab& slab, std::vector<std::uint32_t>& stack,
            const Visit& visit) const;

  const SceneMesh& mesh_;
  bvh::TriangleHierarchy tree_;
  double pad_ = 0;  // box padding against rounding, from the scene's extent
};

}  // namespace logrid::ddo::detail
