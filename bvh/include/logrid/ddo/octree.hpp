// The DDO octree (DDO §3.1): cubic cells over the scene's triangles, subdivided while a
// cell holds more than a threshold of triangles, and for each face of each node one
// bitmask of the view-direction regions (regions.hpp) from which the face is a valid
// occluder: hidden behind the scene's geometry from every viewpoint of the region.
//
// Nodes. The root's cell is a cube around the scene's bounds; a node's children are the
// octants of its cell that hold triangles (empty octants get no node). A triangle belongs
// to the octant holding its centroid, so it may reach out of its cell: `bounds` is the
// tight box of the triangles below a node, and it is that box the run time tests for
// visibility. Leaves list the objects (SceneMesh runs) their triangles belong to.
//
// Storage: a node is sizeof(OctreeNode) = 56 bytes of tree and, per face, one mask of
// `regions` bits held in 8 bytes (6 x 8 = 48 bytes a node); memoryBytes() counts both
// and the leaves' object lists, maskBytes() the masks alone.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/ddo/regions.hpp"
#include "logrid/types.hpp"

namespace logrid::ddo {

struct OctreeNode {
  Aabb bounds;                        // tight box of the subtree's triangles
  std::uint32_t cell[3] = {0, 0, 0};  // integer cell coordinates at `level`
  std::uint32_t first_child = 0;      // children are contiguous, in octant order
  std::uint32_t first_object = 0;     // leaves: into Octree::objects()
  std::uint32_t object_count = 0;
  std::uint32_t triangle_count = 0;  // triangles of the subtree
  std::uint8_t level = 0;
  std::uint8_t child_mask = 0;  // bit k: octant k (x high: 1, y high: 2, z high: 4) exists

  bool leaf() const { return child_mask == 0; }
  std::uint32_t childCount() const { return std::uint32_t(__builtin_popcount(child_mask)); }
};

// What the octree was built with (stored in DDO files; a file built otherwise is stale).
struct OctreeParams {
  double root_lo[3] = {0, 0, 0};
  double root_side = 1;
  std::uint32_t regions = 64;
  std::uint32_t leaf_triangles = 2048;
  std::uint32_t max_depth = 16;
  double face_margin = kFaceMargin;
};

class Octree {
 public:
  Octree() = default;
  Octree(const OctreeParams& params, std::vector<OctreeNode> nodes, std::vector<ObjectId> objects);

  const OctreeParams& params() const { return params_; }
  const RegionLayout& layout() const { return layout_; }
  const std::vector<OctreeNode>& nodes() const { return nodes_; }
  const std::vector<ObjectId>& objects() const { return objects_; }
  bool empty() const { return nodes_.empty(); }

  // Cell side at a level; the coordinate of the k-th cell plane of a level on an axis,
  // root_lo + k * side: the one expression every user of a plane goes through, so that
  // neighbouring cells and the slabs of the preprocessing agree bit for bit.
  double side(std::uint32_t level) const;
  double plane(int axis, std::uint32_t level, std::uint64_t k) const;
  void cellBox(std::uint32_t node, double* lo, double* hi) const;
  FaceFrame face(std::uint32_t node, int face) const;

  // The child of `node` in octant k, or kNone.
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  std::uint32_t child(std::uint32_t node, int octant) const;

  std::uint64_t mask(std::uint32_t node, int face) const {
    return masks_[std::size_t(node) * kFaces + std::size_t(face)];
  }
  bool valid(std::uint32_t node, int face, std::uint32_t region) const {
    return (mask(node, face) >> region) & 1u;
  }
  void setMask(std::uint32_t node, int face, std::uint64_t bits) {
    masks_[std::size_t(node) * kFaces + std::size_t(face)] = bits;
  }
  const std::vector<std::uint64_t>& masks() const { return masks_; }
  std::vector<std::uint64_t>& mutableMasks() { return masks_; }

  std::size_t memoryBytes() const;
  std::size_t maskBytes() const { return masks_.size() * sizeof(std::uint64_t); }
  std::uint32_t depth() const;

 private:
  OctreeParams params_;
  RegionLayout layout_ = *RegionLayout::forCount(64);
  std::vector<OctreeNode> nodes_;
  std::vector<ObjectId> objects_;
  std::vector<std::uint64_t> masks_;  // kFaces per node
};

}  // namespace logrid::ddo
