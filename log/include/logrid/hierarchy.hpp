// The bounding-volume hierarchy logrid walks: an interface, so a renderer hands over
// its own tree (binary or n-ary, any storage) through a thin adapter. bvh/ has a
// builder whose FlatHierarchy implements it directly.
//
// Contract (not checked per frame; tests/unit/bvh_test.cpp checks the builder's):
//   * bounds(n) contains the bounds of every child of n and all geometry of n's objects;
//   * node and object ids are the application's own; logrid only hands them back;
//   * a node may have children, objects, or both.
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
