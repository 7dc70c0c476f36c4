#include "logrid/ddo/octree.hpp"

#include <cassert>
#include <cmath>

namespace logrid::ddo {

Octree::Octree(const OctreeParams& params, std::vector<OctreeNode> nodes,
               std::vector<ObjectId> objects)
    : params_(params),
      nodes_(std::move(nodes)),
      objects_(std::move(objects)),
      masks_(nodes_.size() * kFaces, 0) {
  const auto layout = RegionLayout::forCount(params.regions);
  assert(layout && "Octree: regions must be 32 or 64");
  layout_ = *layout;
}

double Octree::side(std::uint32_t level) const {
  return std::ldexp(params_.root_side, -int(level));
}

double Octree::plane(int axis, std::uint32_t level, std::uint64_t k) const {
  return params_.root_lo[axis] + double(k) * side(level);
}

void Octree::cellBox(std::uint32_t node, double* lo, double* hi) const {
  const OctreeNode& n = nodes_[node];
  for (int a = 0; a < 3; ++a) {
    lo[a] = plane(a, n.level, n.cell[a]);
    hi[a] = plane(a, n.level, std::uint64_t(n.cell[a]) + 1);
  }
}

FaceFrame Octree::face(std::uint32_t node, int face) const {
  double lo[3], hi[3];
  cellBox(node, lo, hi);
  return faceFrame(lo, hi, side(nodes_[node].level), face, params_.face_margin);
}

std::uint32_t Octree::child(std::uint32_t node, int octant) const {
  const OctreeNode& n = nodes_[node];
  if (!((n.child_mask >> octant) & 1u)) return kNone;
  const unsigned below = n.child_mask & ((1u << octant) - 1u);
  return n.first_child + std::uint32_t(__builtin_popcount(below));
}

std::size_t Octree::memoryBytes() const {
  return nodes_.capacity() * sizeof(OctreeNode) + objects_.capacity() * sizeof(ObjectId) +
         masks_.capacity() * sizeof(std::uint64_t);
}

std::uint32_t Octree::depth() const {
  std::uint32_t d = 0;
  for (const OctreeNode& n : nodes_) d = std::max<std::uint32_t>(d, n.level + 1u);
  return d;
}

}  // namespace logrid::ddo
