// The bounding-volume hierarchy logrid walks: an interface, so a renderer hands over
// its own tree (binary or n-ary, any storage) through a thin adapter. bvh/ has a
// builder whose FlatHierarchy implements it directly.
//
// Contract (not checked per frame; tests/unit/bvh_test.cpp checks the builder's):
//   * bounds(n) contains the bounds of every child of n and all geometry of n's objects;
//   * node and object ids are the application's own; logrid only hands them back;
//   * a node may have children, objects, or both. A leaf is a node without children;
//     the culler speaks of "nodes with objects" for those it draws (in bvh/'s
//     hierarchies every node with objects is a leaf, but an adapter's need not be).
#pragma once

#include <cstdint>

#include "logrid/types.hpp"

namespace logrid {

inline constexpr NodeId kNoNode = ~NodeId{0};

class Hierarchy {
 public:
  virtual ~Hierarchy() = default;

  // The root, or kNoNode for an empty hierarchy.
  virtual NodeId root() const = 0;
  virtual Aabb bounds(NodeId node) const = 0;
  virtual std::uint32_t childCount(NodeId node) const = 0;
  virtual NodeId child(NodeId node, std::uint32_t index) const = 0;
  // The children of `node` with their boxes in one call, in child() order:
  // ids[i] = child(node, i) and boxes[i] = bounds(ids[i]) for i < childCount(node),
  // which both arrays must hold. Returns that count. The traversal asks this once per
  // node instead of two calls per child; the default makes those calls, and a hierarchy
  // that keeps a node's children together overrides it.
  virtual std::uint32_t children(NodeId node, NodeId* ids, Aabb* boxes) const {
    const std::uint32_t count = childCount(node);
    for (std::uint32_t i = 0; i < count; ++i) {
      ids[i] = child(node, i);
      boxes[i] = bounds(ids[i]);
    }
    return count;
  }
  // The objects drawn when `node` is found visible ("BVols that have objects as direct
  // children", LOG §3).
  virtual std::uint32_t objectCount(NodeId node) const = 0;
  virtual ObjectId object(NodeId node, std::uint32_t index) const = 0;
  // Changes whenever node ids are reassigned (a rebuild, a restructuring), so that what
  // a culler remembers about nodes from earlier frames (temporal coherence, culler.hpp)
  // is dropped. Boxes may change without it (refitting). A hierarchy that never
  // reassigns its ids keeps the default.
  virtual std::uint64_t revision() const { return 0; }
  // The triangles of an object, for methods that weigh drawing against querying (nohc);
  // 0 when unknown (the default), which such methods replace by an assumed count.
  virtual std::uint32_t objectTriangles(ObjectId object) const {
    (void)object;
    return 0;
  }
};

}  // namespace logrid
