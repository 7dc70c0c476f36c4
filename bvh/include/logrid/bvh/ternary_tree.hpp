// The ternary tree for dynamic scenes of Kovalčík and Sochor (Eurographics 2005 short
// paper; docs/DESIGN.md, "Papers"; cited below as §3.x), as a
// MotionHierarchy (motion.hpp).
//
// Structure (§3.1). An axis-aligned BSP tree of cells: the root's cell is the bounds of
// the objects at build time; an inner node splits its cell in halves by a plane; each
// object is held by the smallest node whose cell fully surrounds it. An inner node has
// exactly three children: below the plane, above it, and the third child holding the
// objects that intersect the plane, which is never split further and whose box is the
// bounding box of its objects. With TernaryDesc::third_child off those objects stay in
// the inner node itself (the paper's binary tree, its "old" algorithm). A moving object
// is re-inserted from the lowest ancestor whose cell still holds it; an object that
// leaves the root's cell is held by the root, whose box then grows to include it.
//
// Boxes (§3.2). A node's box is its cell, which holds its objects however they move
// within it, so moving objects cost no box updates. Once nothing in a node's subtree has
// changed for TernaryDesc::still_frames updates, its box is shrunk to the union of its
// objects' boxes (a TightBox) and kept until something in the subtree changes. A parent
// changes whenever a child does, so a tight parent has tight children and its box holds
// theirs. The third child's box is always the union of its objects ("we form a bounding
// box for group of objects intersecting the cutting plane"), recomputed when they move.
//
// Statistics (§3.3). After each culled frame, measure() has the depth source count, for
// each leaf the culler found visible (Count requests), the pixels of the leaf's
// projected rectangle whose depth key is at or beyond the leaf's occlusion threshold
// (its nearest key minus the depth margin), i.e. where a surface at the box's nearest
// depth would pass the depth test against the finished frame. That is an upper bound of
// the box's visible pixels (the box covers at most its rectangle and lies at or behind
// its nearest key), from any depth source: read pixels, a compute reduction or a
// hardware occlusion query (DepthSource Count requests). The "total pixels" of the
// paper's additional query are the rectangle's area, the same upper bound of the box's
// footprint with no query at all. What a count costs differs: a hardware query is paid
// per request and counts the whole rectangle; a source that reads pixels is paid per
// pixel, so for it rectangles taller than 8 rows are counted on 8 evenly spaced rows and
// the ratio is that of the rows (an estimate for tall rectangles, exact for the rest;
// the statistics only shape the tree, never what is culled). The ratio visible / total
// is thus the fraction of the box's rectangle not hidden in front of the box. Leaves
// found occluded have ratio 0 and need no request; leaves crossing the near plane count
// as fully visible (ratio 1); leaves the traversal never reached (an ancestor was
// occluded or outside the view) have ratio 0.
//
// Split and merge (§3.4), in update(), from the last measured frame: a leaf is split if
// ratio >= r_split and objects >= o_split; the leaves under one parent are merged into
// it if for every one of them ratio <= r_merge and objects <= o_merge. The split plane
// halves the cell; with view_dependent_split it is parallel to the cell's side whose
// normal n has the largest |n . v| for the view direction v (so the halves lie one
// behind the other), otherwise it halves the longest side.
//
// Where the paper is ambiguous or inconsistent, and what this implementation does (none
// of it affects conservativeness: every box holds its objects whatever is split,
// merged or tightened; these choices only shape the tree):
//   * R_merge = 0.75 > R_split = 0.25, and the object bounds 5 < 12: read literally, a
//     leaf of 12 objects at ratio 0.5 is split, and if its three children hold at most 5
//     objects each they are merged again in the next frame, and so on. We read the
//     conditions as written (per sibling leaf) and add one guard: siblings are merged only
//     if the merged leaf would hold fewer than o_split objects, so it is not split again
//     at once. Documented in docs/MOTION.md.
//   * "Objects_node": the objects a leaf holds (its direct objects); empty siblings count
//     as satisfying the merge conditions.
//   * Leaves made in an update (by a split or merge) are judged only from the next
//     update on, with the statistics of the frame culled in between.
//   * A split that would leave every object in the third child (all straddle the plane)
//     is not made: the third child is never split, so it would only add a level.
//   * "Prefer" the side whose normal has the largest |n . v|: we take it unless that side
//     is shorter than 1/8 of the cell's longest side (slicing an already thin cell
//     further), when the longest side is halved instead.
//   * "A few frames" for TightBoxes: still_frames, 3 by default.
//   * The initial tree is not described (the old algorithm "splits the root recursively"):
//     leaves are split in halves of their longest side while they hold build_leaf objects
//     or more (default o_split), down to max_depth.
//   * §3.5 (colliding queries) is a rule of the traversal, not of the tree: it is
//     CullerDesc::detect_colliding (culler.hpp) and works with every hierarchy.
//
// Beyond the paper (TernaryDesc::object_nodes, MotionKind::TernaryObjects): the paper
// draws every object of a visible node, because each further test would cost a
// hardware query. A lazy occlusion grid tests boxes cheaply, so this variant shows each
// object of a node as a child with its own box, and the culler tests those too. The
// tree, its statistics and its rules are unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/bvh/motion.hpp"
#include "logrid/projection.hpp"

namespace logrid::bvh {

class TernaryTree final : public MotionHierarchy {
 public:
  // Builds the tree over `boxes` (object i has boxes[i]). The result form
  // (logrid/error.hpp): the tree, or ErrorCode::InvalidArgument for settings
  // validateMotionDesc() refuses, ErrorCode::BadInput for a bad box (naming it).
  static Result<TernaryTree> create(const std::vector<Aabb>& boxes, const TernaryDesc& desc = {});
  // The throwing form: throws logrid::Error where create() fails.
  TernaryTree(const std::vector<Aabb>& boxes, const TernaryDesc& desc = {});
  TernaryTree(TernaryTree&&) noexcept;
  TernaryTree& operator=(TernaryTree&&) noexcept;
  ~TernaryTree() override;

  // Hierarchy. Nodes whose subtree holds no object are not shown to the culler.
  // With TernaryDesc::object_nodes, a node's objects are shown as children instead, one
  // node per object (id kObjectNode | object) whose box is the object's own.
  static constexpr NodeId kObjectNode = NodeId{1} << 31;
  NodeId root() const override;
  Aabb bounds(NodeId node) const override {
    return node & kObjectNode ? objects_[node & ~kObjectNode].box : nodes_[node].box;
  }
  std::uint32_t childCount(NodeId node) const override;
  NodeId child(NodeId node, std::uint32_t index) const override;
  std::uint32_t objectCount(NodeId node) const override {
    if (node & kObjectNode) return 1;
    return desc_.object_nodes ? 0 : static_cast<std::uint32_t>(nodes_[node].objects.size());
  }
  ObjectId object(NodeId node, std::uint32_t index) const override {
    return node & kObjectNode ? node & ~kObjectNode : nodes_[node].objects[index];
  }
  std::uint64_t revision() const override { return revision_; }

  // MotionHierarchy.
  Result<UpdateStats> tryUpdate(const MotionUpdate& update) override;
  CullObserver* observer() override;
  MeasureStats measure(const Camera& camera, DepthSource& depth) override;
  std::size_t objectTotal() const override { return objects_.size(); }

  const TernaryDesc& desc() const { return desc_; }

  // Inspection, for tests and reports.
  enum class Kind : std::uint8_t { Leaf, Inner, Straddle };
  Kind kind(NodeId node) const { return nodes_[node].kind; }
  NodeId parent(NodeId node) const { return nodes_[node].parent; }
  // The objects a tree node holds (whether or not they are shown as object nodes).
  const std::vector<ObjectId>& heldObjects(NodeId node) const { return nodes_[node].objects; }
  Aabb cell(NodeId node) const { return nodes_[node].cell; }
  bool tight(NodeId node) const { return nodes_[node].tight; }
  // The node holding an object.
  NodeId nodeOf(ObjectId object) const { return objects_[object].node; }
  // The raw children of an inner node (below, above, straddle; kNoNode when absent),
  // including empty ones.
  NodeId rawChild(NodeId node, int which) const { return nodes_[node].child[which]; }
  int splitAxis(NodeId node) const { return nodes_[node].axis; }
  float splitPlane(NodeId node) const { return nodes_[node].plane; }
  // The pixel ratio measured for a node in the last measure() (negative: not measured).
  double measuredRatio(NodeId node) const;
  // Sets a node's statistics as measure() would (tests of the split and merge rules).
  void setMeasuredRatio(NodeId node, double ratio);
  // Live nodes, and all node ids ever allocated (some may be free).
  std::size_t nodeCount() const { return nodes_.size() - free_.size(); }
  std::size_t nodeCapacity() const { return nodes_.size(); }
  bool alive(NodeId node) const { return node < nodes_.size() && nodes_[node].alive; }
  std::uint32_t depthOf(NodeId node) const { return nodes_[node].depth; }
  std::uint32_t subtreeObjects(NodeId node) const { return nodes_[node].subtree_objects; }

 private:
  struct Checked {};  // the settings and boxes were validated
  TernaryTree(Checked, const std::vector<Aabb>& boxes, const TernaryDesc& desc);

  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  struct Node {
    Aabb cell;
    Aabb box;
    std::uint32_t parent = kNone;
    std::uint32_t child[3] = {kNone, kNone, kNone};  // below, above, straddle
    float plane = 0;
    std::uint8_t axis = 0;
    Kind kind = Kind::Leaf;
    bool alive = true;
    bool tight = false;
    std::uint32_t depth = 0;
    std::vector<ObjectId> objects;
    std::uint32_t subtree_objects = 0;
    std::int64_t last_change = 0;  // the update in which its subtree last changed
    std::int64_t created = 0;      // the update that made it
    std::int64_t measured = -1;    // the update after which it was last measured
    float ratio = 0;               // visible / total pixels then
  };
  struct ObjectSlot {
    Aabb box;
    std::uint32_t node = kNone;
    std::uint32_t index = 0;  // in the node's objects
  };
  class Recorder;

  std::uint32_t allocate(const Node& node);
  void release(std::uint32_t node);
  // Where an object with this box belongs, searching down from `from`.
  std::uint32_t descend(std::uint32_t from, const Aabb& box) const;
  // Whether the object still belongs in `node`.
  bool belongs(std::uint32_t node, const Aabb& box) const;
  void insert(ObjectId id, std::uint32_t node);
  void remove(ObjectId id);
  void touch(std::uint32_t node);
  void split(std::uint32_t leaf, const DVec3& view);
  void merge(std::uint32_t inner);
  void splitMerge(const DVec3& view, UpdateStats& stats);
  int chooseAxis(const Aabb& cell, const DVec3& view) const;
  bool splitWorthwhile(std::uint32_t leaf, int axis, float plane) const;
  void buildRecursive(std::uint32_t leaf);
  void recomputeBoxes(UpdateStats& stats);
  void computeBox(std::uint32_t node);
  bool eligibleForTight(const Node& node) const;

  TernaryDesc desc_;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> free_;
  std::vector<ObjectSlot> objects_;
  std::uint32_t root_ = kNone;
  std::uint64_t revision_;
  std::int64_t frame_ = 0;
  std::int64_t last_measure_ = -1;  // the update whose frame measure() last saw
  // Nodes touched per update, for the last still_frames + 1 updates (ring).
  std::vector<std::vector<std::uint32_t>> touched_;
  std::vector<std::uint32_t> recompute_;  // scratch
  std::unique_ptr<Recorder> recorder_;
};

#if LOGRID_HAS_EXCEPTIONS
inline TernaryTree::TernaryTree(const std::vector<Aabb>& boxes, const TernaryDesc& desc)
    : TernaryTree(logrid::orThrow(create(boxes, desc))) {}
#endif

}  // namespace logrid::bvh
