// Bounding-box hierarchies for logrid: built over objects (one box each, e.g. the trees
// of a forest) or over triangles (e.g. a city, LOG §5: subdivided until a box holds at
// most 1500 triangles), refitted when objects move. The result, FlatHierarchy, is a
// logrid::Hierarchy the culler walks directly.
//
// Building splits the primitives' centroids at the median of the longest axis of their
// bounds (an object-median split): O(n log n), no per-primitive boxes kept for
// triangles, and deterministic. Node boxes are computed bottom-up from the primitives.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "logrid/error.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/types.hpp"

namespace logrid::bvh {

struct BuildArgs {
  std::uint32_t max_leaf_size = 1;  // primitives per leaf at most (objects or triangles)
  std::uint32_t max_children = 2;   // children per inner node: 2, 4 or 8 (splits applied
                                    // recursively within a node)
  std::uint32_t threads = 0;        // worker threads for large builds (0: hardware)
};

// Returns an empty string if the arguments are usable, else a message naming the field.
std::string validateBuildArgs(const BuildArgs& args);

// A hierarchy stored as arrays. Children of a node are contiguous, and every child has
// a larger index than its parent, so refitting walks the nodes backwards.
class FlatHierarchy : public Hierarchy {
 public:
  struct Node {
    Aabb box;
    std::uint32_t first_child = 0;
    std::uint32_t child_count = 0;
    std::uint32_t first_object = 0;  // into objects()
    std::uint32_t object_count = 0;
  };

  NodeId root() const override { return nodes_.empty() ? kNoNode : 0; }
  Aabb bounds(NodeId node) const override { return nodes_[node].box; }
  std::uint32_t childCount(NodeId node) const override { return nodes_[node].child_count; }
  NodeId child(NodeId node, std::uint32_t i) const override { return nodes_[node].first_child + i; }
  std::uint32_t children(NodeId node, NodeId* ids, Aabb* boxes) const override {
    const Node& n = nodes_[node];
    for (std::uint32_t i = 0; i < n.child_count; ++i) {
      ids[i] = n.first_child + i;
      boxes[i] = nodes_[n.first_child + i].box;
    }
    return n.child_count;
  }
  std::uint32_t objectCount(NodeId node) const override { return nodes_[node].object_count; }
  ObjectId object(NodeId node, std::uint32_t i) const override {
    return objects_[nodes_[node].first_object + i];
  }

  // Triangles of an object (ObjectId), as setObjectTriangles() gave them; 0: unknown.
  std::uint32_t objectTriangles(ObjectId object) const override {
    return object < object_triangles_.size() ? object_triangles_[object] : 0;
  }
  // Triangles per object, indexed by ObjectId, for methods that weigh drawing against
  // querying (nohc). The builders leave it empty (unknown). Node ids stay: no new revision.
  void setObjectTriangles(std::vector<std::uint32_t> triangles) {
    object_triangles_ = std::move(triangles);
  }

  // Unique to each build: every FlatHierarchy gets a new value when built or mutated
  // (mutableNodes(), mutableObjects()), and copies keep their source's.
  std::uint64_t revision() const override { return revision_; }

  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<ObjectId>& objects() const { return objects_; }
  std::size_t memoryBytes() const;
  std::uint32_t depth() const;

  // Both refits come in both forms (logrid/error.hpp): tryRefit() returns the error,
  // refit() throws it as logrid::Error.
  //
  // Recomputes every box after objects moved: a leaf's box becomes the union of its
  // objects' boxes (object_boxes indexed by ObjectId), an inner node's the union of its
  // children's. The topology stays; quality degrades if objects move far (rebuild then).
  // Fails, leaving the boxes unchanged, if an object id is out of range of object_boxes
  // (ErrorCode::InvalidArgument) or an object's box is not finite with min <= max
  // (ErrorCode::BadInput), naming the first.
  Status tryRefit(const std::vector<Aabb>& object_boxes);
  void refit(const std::vector<Aabb>& object_boxes);
  // Refits only the leaves holding the `moved` objects and their ancestors; every other
  // object's box must be as at the last build or refit. Same checks as refit() for the
  // moved objects (duplicates are fine). Returns the number of boxes recomputed.
  Result<std::size_t> tryRefit(const std::vector<Aabb>& object_boxes,
                               const std::vector<ObjectId>& moved);
  std::size_t refit(const std::vector<Aabb>& object_boxes, const std::vector<ObjectId>& moved);
  // The sum of the surface areas of all node boxes: the SAH cost of the tree with unit
  // traversal and intersection costs, times the root's area. Grows as refitted boxes
  // loosen; MotionHierarchy "refit" rebuilds on it (motion.hpp).
  double surfaceAreaSum() const;

  // Construction (used by the builders; also for tests and adapters).
  std::vector<Node>& mutableNodes() {
    revision_ = nextRevision();
    return nodes_;
  }
  std::vector<ObjectId>& mutableObjects() {
    revision_ = nextRevision();
    return objects_;
  }

 private:
  static std::uint64_t nextRevision();
  void buildLinks() const;
  std::vector<Node> nodes_;
  std::vector<ObjectId> objects_;
  std::vector<std::uint32_t> object_triangles_;
  std::uint64_t revision_ = nextRevision();
  // For the partial refit: parents and the leaf of each object, built on first use
  // for the revision they describe.
  mutable std::vector<std::uint32_t> parent_;
  mutable std::vector<std::uint32_t> leaf_of_;
  mutable std::uint64_t links_revision_ = 0;
};

// The builders come in both forms (logrid/error.hpp): tryBuildOver...() returns the
// hierarchy or the error, buildOver...() throws the error as logrid::Error. Either fails
// with ErrorCode::InvalidArgument for arguments validateBuildArgs() refuses.
//
// One leaf per at most max_leaf_size objects; object i has box boxes[i]. Boxes must be
// valid (finite, min <= max): ErrorCode::BadInput naming the first bad one.
Result<FlatHierarchy> tryBuildOverBoxes(const std::vector<Aabb>& boxes, const BuildArgs& args = {});
FlatHierarchy buildOverBoxes(const std::vector<Aabb>& boxes, const BuildArgs& args = {});

// The result of building over triangles: the hierarchy, whose leaves each hold one
// object (the leaf's chunk of triangles, ObjectId = chunk index), and the triangles
// reordered so that chunk c is triangles [chunk_first[c], chunk_first[c + 1]).
struct TriangleHierarchy {
  FlatHierarchy hierarchy;
  std::vector<std::uint32_t> triangle_order;  // new position -> original triangle index
  std::vector<std::uint32_t> chunk_first;     // chunks + 1 entries
};

// positions: xyz per vertex; indices: three per triangle. ErrorCode::BadInput for an
// index out of range or a non-finite position (naming the first one).
Result<TriangleHierarchy> tryBuildOverTriangles(const std::vector<float>& positions,
                                                const std::vector<std::uint32_t>& indices,
                                                BuildArgs args = {1500, 2, 0});
TriangleHierarchy buildOverTriangles(const std::vector<float>& positions,
                                     const std::vector<std::uint32_t>& indices,
                                     BuildArgs args = {1500, 2, 0});

#if LOGRID_HAS_EXCEPTIONS
inline void FlatHierarchy::refit(const std::vector<Aabb>& object_boxes) {
  logrid::orThrow(tryRefit(object_boxes));
}
inline std::size_t FlatHierarchy::refit(const std::vector<Aabb>& object_boxes,
                                        const std::vector<ObjectId>& moved) {
  return logrid::orThrow(tryRefit(object_boxes, moved));
}
inline FlatHierarchy buildOverBoxes(const std::vector<Aabb>& boxes, const BuildArgs& args) {
  return logrid::orThrow(tryBuildOverBoxes(boxes, args));
}
inline TriangleHierarchy buildOverTriangles(const std::vector<float>& positions,
                                            const std::vector<std::uint32_t>& indices,
                                            BuildArgs args) {
  return logrid::orThrow(tryBuildOverTriangles(positions, indices, args));
}
#endif

}  // namespace logrid::bvh
