// The hierarchies for moving objects (bvh/motion.hpp) and the ternary tree's rules
// (bvh/ternary_tree.hpp; Kovalčík and Sochor, Eurographics 2005), without GL:
//   * §3.1: objects straddling a split plane go to the third child (or stay in the inner
//     node of the binary tree);
//   * §3.2: still nodes get tight boxes, which a move undoes;
//   * §3.4: the split and merge thresholds (R_split 0.25, O_split 12, R_merge 0.75,
//     O_merge 5), our guard against the split/merge cycle, the view-dependent plane;
//   * every hierarchy keeps the Hierarchy contract under random motion (objects that
//     leave the bounds, pass through each other, stop and start), and revision() changes
//     exactly when node ids are reassigned;
//   * culled with the software rasteriser, moving boxes are never missed, with every
//     hierarchy, with the pixel statistics of §3.3 and with colliding-query detection
//     (§3.5), which hides a box behind a nearer one of the same batch.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <set>
#include <tuple>

#include "box_world.hpp"
#include "expect_status.hpp"
#include "logrid/bvh/motion.hpp"
#include "logrid/bvh/ternary_tree.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

using bvh::MotionKind;
using bvh::TernaryDesc;
using bvh::TernaryTree;
using Kind = TernaryTree::Kind;

Aabb box(float x0, float y0, float z0, float x1, float y1, float z1) {
  return {{x0, y0, z0}, {x1, y1, z1}};
}

bool contains(const Aabb& outer, const Aabb& inner) {
  return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
         inner.max.x <= outer.max.x && inner.max.y <= outer.max.y && inner.max.z <= outer.max.z;
}

bool sameBox(const Aabb& a, const Aabb& b) { return contains(a, b) && contains(b, a); }

Aabb unionOf(const std::vector<Aabb>& boxes, const std::vector<ObjectId>& ids) {
  Aabb u = boxes[ids.front()];
  for (ObjectId id : ids) {
    const Aabb& b = boxes[id];
    u.min = {std::min(u.min.x, b.min.x), std::min(u.min.y, b.min.y), std::min(u.min.z, b.min.z)};
    u.max = {std::max(u.max.x, b.max.x), std::max(u.max.y, b.max.y), std::max(u.max.z, b.max.z)};
  }
  return u;
}

// Small boxes along x in [0, 100] (the longest axis), away from x = 50.
std::vector<Aabb> rowOfBoxes(int count) {
  std::vector<Aabb> out;
  for (int i = 0; i < count; ++i) {
    const float x = i < count / 2 ? 2.0f + 3.0f * float(i) : 98.0f - 3.0f * float(i - count / 2);
    out.push_back(box(x - 0.5f, 0, float(i % 3), x + 0.5f, 1, float(i % 3) + 1));
  }
  return out;
}

std::vector<ObjectId> objectsOf(const Hierarchy& h, NodeId n) {
  std::vector<ObjectId> out;
  for (std::uint32_t i = 0; i < h.objectCount(n); ++i) out.push_back(h.object(n, i));
  return out;
}

// The Hierarchy contract: boxes hold children and objects, every object appears once.
void expectContract(const bvh::MotionHierarchy& h, const std::vector<Aabb>& boxes,
                    const std::string& where) {
  std::vector<int> seen(boxes.size(), 0);
  std::vector<NodeId> stack;
  if (h.root() != kNoNode) stack.push_back(h.root());
  std::size_t nodes = 0;
  while (!stack.empty()) {
    const NodeId n = stack.back();
    stack.pop_back();
    ++nodes;
    ASSERT_LT(nodes, 10u * boxes.size() + 10) << where << ": the hierarchy has a cycle";
    const Aabb b = h.bounds(n);
    for (ObjectId id : objectsOf(h, n)) {
      ASSERT_LT(id, boxes.size());
      ++seen[id];
      EXPECT_TRUE(contains(b, boxes[id]))
          << where << ": node " << n << " does not hold object " << id;
    }
    for (std::uint32_t c = 0; c < h.childCount(n); ++c) {
      const NodeId child = h.child(n, c);
      EXPECT_TRUE(contains(b, h.bounds(child)))
          << where << ": node " << n << " does not hold its child " << child;
      stack.push_back(child);
    }
  }
  for (std::size_t id = 0; id < boxes.size(); ++id) {
    EXPECT_EQ(seen[id], 1) << where << ": object " << id << " appears " << seen[id] << " times";
  }
}

TernaryDesc noAdaptation() {
  TernaryDesc d;
  d.split_merge = false;
  return d;
}

// ---------------------------------------------------------------------------
// §3.1 the third child.
// ---------------------------------------------------------------------------

TEST(TernaryTree, StraddlingObjectsGoToTheThirdChild) {
  std::vector<Aabb> boxes = rowOfBoxes(20);
  boxes.push_back(box(49, 0, 0, 51, 1, 1));  // across x = 50
  boxes.push_back(box(45, 0, 2, 55, 1, 3));
  const ObjectId a = 20, b = 21;
  TernaryTree tree(boxes, noAdaptation());
  const NodeId root = tree.root();
  ASSERT_EQ(tree.kind(root), Kind::Inner);
  EXPECT_EQ(tree.splitAxis(root), 0);
  EXPECT_EQ(tree.splitPlane(root), 50.0f);
  const NodeId third = tree.rawChild(root, 2);
  ASSERT_NE(third, kNoNode);
  EXPECT_EQ(tree.kind(third), Kind::Straddle);
  EXPECT_EQ(tree.nodeOf(a), third);
  EXPECT_EQ(tree.nodeOf(b), third);
  EXPECT_EQ(tree.objectCount(root), 0u) << "nothing stays in the ternary tree's inner node";
  // The third child's box is the box of its objects, not its cell.
  EXPECT_TRUE(sameBox(tree.bounds(third), unionOf(boxes, {a, b})));
  for (ObjectId id = 0; id < 20; ++id) {
    NodeId n = tree.nodeOf(id);
    while (tree.parent(n) != root) n = tree.parent(n);
    EXPECT_EQ(n, tree.rawChild(root, boxes[id].max.x <= 50 ? 0 : 1)) << "object " << id;
  }
  expectContract(tree, boxes, "ternary");

  // The binary tree (the paper's old algorithm) keeps them in the inner node.
  TernaryTree binary(boxes, bvh::binaryTreeDesc());
  const NodeId broot = binary.root();
  ASSERT_EQ(binary.kind(broot), Kind::Inner);
  EXPECT_EQ(binary.rawChild(broot, 2), kNoNode);
  EXPECT_EQ(binary.nodeOf(a), broot);
  EXPECT_EQ(binary.nodeOf(b), broot);
  EXPECT_EQ(binary.objectCount(broot), 2u);
  EXPECT_TRUE(sameBox(binary.bounds(broot), binary.cell(broot))) << "old: boxes are cells";
  expectContract(binary, boxes, "binary");
}

TEST(TernaryTree, MovingAcrossThePlaneMovesTheObjectToTheThirdChildAndBack) {
  std::vector<Aabb> boxes = rowOfBoxes(24);
  TernaryTree tree(boxes, noAdaptation());
  const NodeId root = tree.root();
  ASSERT_EQ(tree.kind(root), Kind::Inner);
  const ObjectId id = 0;
  const std::vector<ObjectId> moved{id};
  boxes[id] = box(49.5f, 0, 0, 50.5f, 1, 1);
  bvh::UpdateStats s = tree.update({&boxes, &moved, {}});
  EXPECT_EQ(s.relocated, 1u);
  EXPECT_EQ(tree.nodeOf(id), tree.rawChild(root, 2));
  expectContract(tree, boxes, "across");
  boxes[id] = box(70, 0, 0, 71, 1, 1);
  s = tree.update({&boxes, &moved, {}});
  EXPECT_EQ(s.relocated, 1u);
  NodeId n = tree.nodeOf(id);
  while (tree.parent(n) != root) n = tree.parent(n);
  EXPECT_EQ(n, tree.rawChild(root, 1));
  expectContract(tree, boxes, "above");
}

TEST(TernaryTree, AnObjectLeavingTheRootCellIsHeldByTheRoot) {
  std::vector<Aabb> boxes = rowOfBoxes(24);
  TernaryTree tree(boxes, noAdaptation());
  const NodeId root = tree.root();
  const Aabb cell = tree.cell(root);
  const std::vector<ObjectId> moved{3};
  boxes[3] = box(500, 0, 0, 501, 1, 1);
  tree.update({&boxes, &moved, {}});
  EXPECT_EQ(tree.nodeOf(3), root);
  EXPECT_TRUE(contains(tree.bounds(root), boxes[3]));
  EXPECT_TRUE(sameBox(tree.cell(root), cell)) << "the cells stay";
  expectContract(tree, boxes, "outside");
  boxes[3] = box(10, 0, 0, 11, 1, 1);  // back inside
  tree.update({&boxes, &moved, {}});
  EXPECT_NE(tree.nodeOf(3), root);
  expectContract(tree, boxes, "back");
}

// ---------------------------------------------------------------------------
// §3.4 split and merge.
// ---------------------------------------------------------------------------

// One leaf (the root) with `objects` objects, never split at build.
TernaryTree singleLeaf(std::vector<Aabb>& boxes, int objects) {
  boxes = rowOfBoxes(objects);
  TernaryDesc d;
  d.build_leaf = 1000;
  d.view_dependent_split = false;
  return TernaryTree(boxes, d);
}

bool splitsWith(int objects, double ratio) {
  std::vector<Aabb> boxes;
  TernaryTree tree = singleLeaf(boxes, objects);
  const NodeId root = tree.root();
  EXPECT_EQ(tree.kind(root), Kind::Leaf);
  tree.setMeasuredRatio(root, ratio);
  const std::vector<ObjectId> none;
  const std::uint64_t revision = tree.revision();
  const bvh::UpdateStats s = tree.update({&boxes, &none, {}});
  const bool split = tree.kind(root) == Kind::Inner;
  EXPECT_EQ(s.splits, split ? 1u : 0u);
  EXPECT_EQ(tree.revision() != revision, split) << "a split reassigns node ids";
  expectContract(tree, boxes, "split");
  return split;
}

TEST(TernaryTree, SplitNeedsRatioAtLeastRsplitAndAtLeastOsplitObjects) {
  EXPECT_TRUE(splitsWith(12, 0.25));  // both at the threshold
  EXPECT_TRUE(splitsWith(30, 1.0));
  EXPECT_FALSE(splitsWith(12, 0.24));  // ratio just below R_split
  EXPECT_FALSE(splitsWith(11, 1.0));   // one object below O_split
  EXPECT_FALSE(splitsWith(12, 0.0));
}

TEST(TernaryTree, NoSplitWithoutStatisticsOfTheLastFrame) {
  std::vector<Aabb> boxes;
  TernaryTree tree = singleLeaf(boxes, 20);
  const std::vector<ObjectId> none;
  tree.update({&boxes, &none, {}});  // never measured
  EXPECT_EQ(tree.kind(tree.root()), Kind::Leaf);
  tree.setMeasuredRatio(tree.root(), 1.0);
  tree.update({&boxes, &none, {}});  // measured after the last update: splits
  EXPECT_EQ(tree.kind(tree.root()), Kind::Inner);
}

// A root split at build into two leaves of `below` and `above` objects (and a third
// child of `across`).
TernaryTree splitRoot(std::vector<Aabb>& boxes, int below, int above, int across) {
  boxes.clear();
  for (int i = 0; i < below; ++i)
    boxes.push_back(box(2.0f * float(i), 0, 0, 2.0f * float(i) + 1, 1, 1));
  for (int i = 0; i < above; ++i) {
    boxes.push_back(box(99.0f - 2.0f * float(i), 0, 0, 100.0f - 2.0f * float(i), 1, 1));
  }
  for (int i = 0; i < across; ++i) boxes.push_back(box(48, 0, float(i), 52, 1, float(i) + 1));
  TernaryDesc d;
  d.build_leaf = 2;
  d.max_depth = 1;  // only the root is split at build
  d.view_dependent_split = false;
  return TernaryTree(boxes, d);
}

bool mergesWith(int below, int above, int across, double r0, double r1, double r2) {
  std::vector<Aabb> boxes;
  TernaryTree tree = splitRoot(boxes, below, above, across);
  const NodeId root = tree.root();
  EXPECT_EQ(tree.kind(root), Kind::Inner);
  tree.setMeasuredRatio(tree.rawChild(root, 0), r0);
  tree.setMeasuredRatio(tree.rawChild(root, 1), r1);
  tree.setMeasuredRatio(tree.rawChild(root, 2), r2);
  const std::vector<ObjectId> none;
  const std::uint64_t revision = tree.revision();
  const bvh::UpdateStats s = tree.update({&boxes, &none, {}});
  const bool merged = tree.kind(root) == Kind::Leaf;
  EXPECT_EQ(s.merges, merged ? 1u : 0u);
  EXPECT_EQ(tree.revision() != revision, merged);
  if (merged) {
    EXPECT_EQ(tree.objectCount(root), std::uint32_t(below + above + across));
  }
  expectContract(tree, boxes, "merge");
  return merged;
}

TEST(TernaryTree, MergeNeedsEverySiblingAtMostRmergeAndOmerge) {
  EXPECT_TRUE(mergesWith(5, 5, 0, 0.75, 0.75, 0.0));  // at the thresholds
  EXPECT_TRUE(mergesWith(3, 4, 2, 0.1, 0.5, 0.75));
  EXPECT_FALSE(mergesWith(5, 5, 0, 0.76, 0.1, 0.0));   // one sibling too visible
  EXPECT_FALSE(mergesWith(5, 5, 1, 0.1, 0.1, 0.751));  // the third child counts too
  EXPECT_FALSE(mergesWith(6, 3, 0, 0.0, 0.0, 0.0));    // one sibling over O_merge
}

TEST(TernaryTree, MergeIsSkippedWhenTheMergedLeafWouldSplitAgain) {
  // 5 + 5 + 2 = 12 objects: each sibling passes the paper's merge test, but the merged
  // leaf would meet O_split and be split again (our guard, ternary_tree.hpp).
  EXPECT_FALSE(mergesWith(5, 5, 2, 0.3, 0.3, 0.3));
  EXPECT_TRUE(mergesWith(5, 5, 1, 0.3, 0.3, 0.3));
}

TEST(TernaryTree, SplitPlaneFacesTheViewer) {
  auto axisFor = [](const Aabb& cell_extent, DVec3 view) {
    std::vector<Aabb> boxes;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0, 1);
    for (int i = 0; i < 40; ++i) {
      const float x = u(rng) * (cell_extent.max.x - 1), y = u(rng) * (cell_extent.max.y - 1),
                  z = u(rng) * (cell_extent.max.z - 1);
      boxes.push_back(box(x, y, z, x + 0.5f, y + 0.5f, z + 0.5f));
    }
    boxes.push_back(box(0, 0, 0, 0.1f, 0.1f, 0.1f));
    boxes.push_back(cell_extent.max.x > 0 ? box(cell_extent.max.x - 0.1f, cell_extent.max.y - 0.1f,
                                                cell_extent.max.z - 0.1f, cell_extent.max.x,
                                                cell_extent.max.y, cell_extent.max.z)
                                          : box(0, 0, 0, 1, 1, 1));
    TernaryDesc d;
    d.build_leaf = 1000;
    TernaryTree tree(boxes, d);
    tree.setMeasuredRatio(tree.root(), 1.0);
    const std::vector<ObjectId> none;
    tree.update({&boxes, &none, view});
    EXPECT_EQ(tree.kind(tree.root()), Kind::Inner);
    return tree.splitAxis(tree.root());
  };
  const Aabb cube = box(0, 0, 0, 100, 100, 100);
  EXPECT_EQ(axisFor(cube, {0, 0, -1}), 2);
  EXPECT_EQ(axisFor(cube, {0.9, 0.1, 0.3}), 0);
  EXPECT_EQ(axisFor(cube, {0.2, -0.9, 0.3}), 1);
  // A long, low cell seen from the side: the view's axis (z) although x is longest.
  EXPECT_EQ(axisFor(box(0, 0, 0, 200, 10, 100), {0.1, 0, 1}), 2);
  // Looking down on a flat cell: y is under 1/8 of the longest side, so x is halved.
  EXPECT_EQ(axisFor(box(0, 0, 0, 200, 10, 100), {0, -1, 0}), 0);
}

// ---------------------------------------------------------------------------
// §3.2 tight boxes.
// ---------------------------------------------------------------------------

TEST(TernaryTree, StillNodesGetTightBoxesAndAMoveUndoesThem) {
  std::vector<Aabb> boxes = rowOfBoxes(40);
  TernaryDesc d = noAdaptation();
  d.still_frames = 3;
  TernaryTree tree(boxes, d);
  const NodeId root = tree.root();
  // Nothing has moved yet: tight from the start, the root's box is the objects' union.
  std::vector<ObjectId> all(boxes.size());
  for (ObjectId i = 0; i < all.size(); ++i) all[i] = i;
  EXPECT_TRUE(tree.tight(root));
  EXPECT_TRUE(sameBox(tree.bounds(root), unionOf(boxes, all)));

  const ObjectId id = 1;
  const NodeId leaf = tree.nodeOf(id);
  ASSERT_NE(leaf, root);
  const std::vector<ObjectId> moved{id}, none;
  boxes[id].min.x += 0.25f;  // a small move within its cell
  boxes[id].max.x += 0.25f;
  const bvh::UpdateStats s = tree.update({&boxes, &moved, {}});
  EXPECT_EQ(s.relocated, 0u);
  EXPECT_EQ(tree.nodeOf(id), leaf);
  // The moved object's leaf and its ancestors fall back to their cells.
  for (NodeId n = leaf; n != kNoNode; n = tree.parent(n)) {
    EXPECT_FALSE(tree.tight(n)) << "node " << n;
    EXPECT_TRUE(sameBox(tree.bounds(n), tree.cell(n))) << "node " << n;
  }
  // A node elsewhere keeps its tight box.
  const NodeId other = tree.nodeOf(39);
  ASSERT_NE(other, leaf);
  EXPECT_TRUE(tree.tight(other));
  expectContract(tree, boxes, "moved");
  // Still for still_frames updates: tight again.
  tree.update({&boxes, &none, {}});
  tree.update({&boxes, &none, {}});
  EXPECT_FALSE(tree.tight(leaf)) << "two still updates are not enough";
  const bvh::UpdateStats t = tree.update({&boxes, &none, {}});
  EXPECT_GT(t.tight_boxes, 0u);
  EXPECT_TRUE(tree.tight(leaf));
  EXPECT_TRUE(tree.tight(root));
  EXPECT_TRUE(sameBox(tree.bounds(root), unionOf(boxes, all)));
  expectContract(tree, boxes, "still again");

  // Without tight boxes, nodes keep their cells.
  TernaryDesc loose = noAdaptation();
  loose.tight_boxes = false;
  TernaryTree cells(boxes, loose);
  EXPECT_FALSE(cells.tight(cells.root()));
  EXPECT_TRUE(sameBox(cells.bounds(cells.root()), cells.cell(cells.root())));
}

// ---------------------------------------------------------------------------
// §3.3 the pixel statistics.
// ---------------------------------------------------------------------------

// Records what the culler tested, and passes it on to the tree's recorder.
struct Tap final : CullObserver {
  CullObserver* next = nullptr;
  std::vector<std::tuple<NodeId, BoxProjection, Visibility>> tested;
  void onTested(NodeId n, const BoxProjection& p, Visibility v) override {
    tested.emplace_back(n, p, v);
    if (next) next->onTested(n, p, v);
  }
};

TEST(TernaryTree, MeasureCountsTheVisiblePixelsOfEachLeaf) {
  for (bool count_only : {false, true}) {
    const test::BoxWorld world = test::makeBoxWorld(41);
    TernaryDesc d;
    d.o_split = 4;  // many small leaves
    TernaryTree tree(world.boxes, d);
    Culler culler;
    Tap tap;
    tap.next = tree.observer();
    culler.setObserver(&tap);
    const Camera cam = test::boxCamera(160, 96, DepthConvention::Standard, 0.1);
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
    test::CountOnlySource queries(depth);
    DepthSource& source = count_only ? static_cast<DepthSource&>(queries) : depth;
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    culler.cullFrame(cam, tree, source,
                     [&](ObjectId id) { test::drawBox(raster, world.boxes[id], id); });
    const bvh::MeasureStats m = tree.measure(cam, source);
    EXPECT_GT(m.counted, 0u);
    EXPECT_EQ(m.queries > 0, count_only) << "a count-only source answers with queries";
    std::size_t occluded = 0, tall = 0;
    for (const auto& [node, p, v] : tap.tested) {
      if (!tree.alive(node) || tree.kind(node) == Kind::Inner) continue;
      const double ratio = tree.measuredRatio(node);
      ASSERT_GE(ratio, 0.0) << "leaf " << node << " tested but not measured";
      if (v == Visibility::Occluded) {
        EXPECT_EQ(ratio, 0.0) << "an occluded leaf shows nothing";
        ++occluded;
        continue;
      }
      if (p.cls != ProjectionClass::Inside) {
        EXPECT_EQ(ratio, 1.0);
        continue;
      }
      std::uint32_t exact = 0;
      depth.countAtOrBeyond(&p.rect, 1, p.occlusionThreshold(), &exact);
      const double want = double(exact) / double(p.rect.area());
      if (count_only || p.rect.y1 - p.rect.y0 <= 8) {
        EXPECT_NEAR(ratio, want, 1e-6) << "leaf " << node << ": the whole rectangle is counted";
      } else {
        ++tall;  // counted on 8 rows: an estimate
        EXPECT_LE(ratio, 1.0);
      }
    }
    EXPECT_GT(occluded, 0u);
    if (!count_only) {
      EXPECT_GT(tall, 0u) << "some leaves are taller than 8 rows";
    }
  }
}

// ---------------------------------------------------------------------------
// Every hierarchy under random motion.
// ---------------------------------------------------------------------------

struct Mover {
  Aabb start;
  float vx, vz;
  int stop_every;
};

class RandomMotion {
 public:
  explicit RandomMotion(std::uint32_t seed, int count = 300) : rng_(seed) {
    std::uniform_real_distribution<float> pos(0, 100), size(0.2f, 4), v(-6, 6);
    for (int i = 0; i < count; ++i) {
      const float x = pos(rng_), z = pos(rng_), s = size(rng_);
      boxes.push_back(box(x, 0, z, x + s, s, z + s));
      movers.push_back({boxes.back(), v(rng_), v(rng_), 2 + int(rng_() % 4)});
    }
    // Two that pass through each other, and a large still one.
    movers[0] = {box(10, 0, 50, 12, 2, 52), 5, 0, 0};
    movers[1] = {box(90, 0, 50, 92, 2, 52), -5, 0, 0};
    boxes[0] = movers[0].start, boxes[1] = movers[1].start;
  }
  // Moves the first `moving` objects to their positions at `frame`: every stop_every-th
  // frame they stand; some leave [0, 100] far behind.
  void step(int frame, std::size_t moving) {
    moved.clear();
    for (std::size_t i = 0; i < std::min(moving, boxes.size()); ++i) {
      const Mover& m = movers[i];
      if (m.stop_every && frame % m.stop_every == 0) continue;
      const float t = float(frame);
      Aabb b = m.start;
      b.min.x += m.vx * t, b.max.x += m.vx * t, b.min.z += m.vz * t, b.max.z += m.vz * t;
      boxes[i] = b;
      moved.push_back(static_cast<ObjectId>(i));
    }
  }
  std::vector<Aabb> boxes;
  std::vector<ObjectId> moved;

 private:
  std::mt19937 rng_;
  std::vector<Mover> movers;
};

class EveryHierarchy : public testing::TestWithParam<MotionKind> {};

TEST_P(EveryHierarchy, KeepsTheContractUnderRandomMotion) {
  RandomMotion motion(7);
  bvh::MotionDesc desc;
  desc.ternary.o_split = 4;  // small leaves: many splits and merges
  desc.ternary.o_merge = 3;
  desc.ternary.still_frames = 2;
  auto h = bvh::makeMotionHierarchy(GetParam(), motion.boxes, desc);
  auto* tree = dynamic_cast<TernaryTree*>(h.get());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ratio(0, 1);
  std::uint32_t splits = 0, merges = 0, relocated = 0, rebuilds = 0;
  for (int frame = 1; frame <= 40; ++frame) {
    motion.step(frame, frame < 30 ? 150 : 0);  // then everything stands still
    const std::uint64_t revision = h->revision();
    const bvh::UpdateStats s = h->update(
        {&motion.boxes, &motion.moved, {std::cos(frame * 0.3), 0.2, std::sin(frame * 0.3)}});
    splits += s.splits, merges += s.merges, relocated += s.relocated, rebuilds += s.rebuilds;
    const bool reassigned = s.splits + s.merges + s.rebuilds > 0;
    EXPECT_EQ(h->revision() != revision, reassigned) << "frame " << frame;
    expectContract(*h, motion.boxes, "frame " + std::to_string(frame));
    if (tree) {  // random statistics for every leaf, as measure() would set them
      for (NodeId n = 0; n < tree->nodeCapacity(); ++n) {
        if (tree->alive(n) && tree->kind(n) != Kind::Inner) tree->setMeasuredRatio(n, ratio(rng));
      }
    }
  }
  std::printf("[ motion ] %s: %u splits, %u merges, %u relocated, %u rebuilds\n",
              bvh::motionInfo(GetParam()).name, splits, merges, relocated, rebuilds);
  if (GetParam() == MotionKind::Ternary || GetParam() == MotionKind::TernaryObjects) {
    EXPECT_GT(splits, 0u);
    EXPECT_GT(merges, 0u);
    EXPECT_GT(relocated, 0u);
    // Everything stood still for the last frames: the whole tree is tight.
    EXPECT_TRUE(tree->tight(tree->root()));
  }
  if (GetParam() == MotionKind::Binary) {
    EXPECT_EQ(splits + merges, 0u);
  }
  if (GetParam() == MotionKind::Rebuild) {
    EXPECT_EQ(rebuilds, 40u);
  }
  if (GetParam() == MotionKind::Refit) {
    EXPECT_GT(rebuilds, 0u) << "objects fly far apart: the quality criterion must trigger";
    EXPECT_LT(rebuilds, 30u);
  }
}

TEST_P(EveryHierarchy, RefusesABadBoxAndStaysUsable) {
  RandomMotion motion(9, 40);
  auto h = bvh::makeMotionHierarchy(GetParam(), motion.boxes);
  std::vector<Aabb> bad = motion.boxes;
  bad[5].min.x = std::numeric_limits<float>::quiet_NaN();
  const std::vector<ObjectId> moved{5};
  EXPECT_THROW(h->update({&bad, &moved, {}}), Error);
  const std::vector<ObjectId> out_of_range{1000};
  EXPECT_THROW(h->update({&motion.boxes, &out_of_range, {}}), Error);
  motion.step(1, 40);
  h->update({&motion.boxes, &motion.moved, {}});
  expectContract(*h, motion.boxes, "after errors");
}

// The result forms (logrid/error.hpp): tryUpdate() returns the error update() throws,
// with the same code and message, and leaves the hierarchy as it was.
TEST_P(EveryHierarchy, TryUpdateReturnsWhatUpdateThrows) {
  RandomMotion motion(9, 40);
  Result<std::unique_ptr<bvh::MotionHierarchy>> made =
      bvh::tryMakeMotionHierarchy(GetParam(), motion.boxes);
  ASSERT_TRUE(made.ok()) << made.status().message();
  bvh::MotionHierarchy& h = *made.value();
  const std::uint64_t revision = h.revision();
  std::vector<Aabb> bad = motion.boxes;
  bad[5].min.x = std::numeric_limits<float>::quiet_NaN();
  const std::vector<ObjectId> moved{5};
  test::expectBothForms(
      [&] {
        return h.tryUpdate({&bad, &moved, {}});
      },
      [&] {
        h.update({&bad, &moved, {}});
      },
      ErrorCode::BadInput, {"object 5 has an invalid box", "finite with min <= max"});
  const std::vector<ObjectId> out_of_range{1000};
  test::expectBothForms(
      [&] {
        return h.tryUpdate({&motion.boxes, &out_of_range, {}});
      },
      [&] {
        h.update({&motion.boxes, &out_of_range, {}});
      },
      ErrorCode::InvalidArgument, {"moved object 1000 is out of range"});
  test::expectBothForms([&] { return h.tryUpdate({}); }, [&] { h.update({}); },
                        ErrorCode::InvalidArgument, {"boxes and moved must be given"});
  EXPECT_EQ(h.revision(), revision);
  expectContract(h, motion.boxes, "after the refused updates");
  motion.step(1, 40);
  const Result<bvh::UpdateStats> updated = h.tryUpdate({&motion.boxes, &motion.moved, {}});
  ASSERT_TRUE(updated.ok()) << updated.status().message();
  expectContract(h, motion.boxes, "after an update");
}

TEST_P(EveryHierarchy, TryMakeReturnsWhatMakeThrows) {
  std::vector<Aabb> boxes = RandomMotion(9, 40).boxes;
  boxes[7].min.y = boxes[7].max.y + 1;  // min > max
  test::expectBothForms([&] { return bvh::tryMakeMotionHierarchy(GetParam(), boxes); },
                        [&] { bvh::makeMotionHierarchy(GetParam(), boxes); }, ErrorCode::BadInput,
                        {"object 7 has an invalid box"});
  bvh::MotionDesc desc;
  desc.ternary.o_split = 1;
  test::expectBothForms([&] { return bvh::tryMakeMotionHierarchy(GetParam(), {}, desc); },
                        [&] { bvh::makeMotionHierarchy(GetParam(), {}, desc); },
                        ErrorCode::InvalidArgument, {"o_split 1 is invalid"});
}

INSTANTIATE_TEST_SUITE_P(Kinds, EveryHierarchy,
                         testing::Values(MotionKind::Refit, MotionKind::Rebuild,
                                         MotionKind::Ternary, MotionKind::TernaryObjects,
                                         MotionKind::Binary),
                         [](const testing::TestParamInfo<MotionKind>& p) {
                           std::string s = bvh::motionInfo(p.param).name;
                           for (char& ch : s) ch = ch == '-' ? '_' : ch;
                           return s;
                         });

TEST(FlatHierarchyRefit, PartialRefitEqualsFullRefit) {
  RandomMotion motion(11, 200);
  bvh::FlatHierarchy partial = bvh::buildOverBoxes(motion.boxes);
  bvh::FlatHierarchy full = partial;
  const std::uint64_t revision = partial.revision();
  for (int frame = 1; frame < 6; ++frame) {
    motion.step(frame, 60);
    partial.refit(motion.boxes, motion.moved);
    full.refit(motion.boxes);
    ASSERT_EQ(partial.nodes().size(), full.nodes().size());
    for (std::size_t n = 0; n < full.nodes().size(); ++n) {
      EXPECT_TRUE(sameBox(partial.nodes()[n].box, full.nodes()[n].box)) << "node " << n;
    }
  }
  EXPECT_EQ(partial.revision(), revision) << "refitting keeps node ids";
  EXPECT_GT(partial.surfaceAreaSum(), 0.0);
}

TEST(TernaryTree, CreateReturnsWhatTheConstructorThrows) {
  std::vector<Aabb> boxes = RandomMotion(3, 20).boxes;
  boxes[4].max.z = std::numeric_limits<float>::infinity();
  test::expectBothForms([&] { return TernaryTree::create(boxes); },
                        [&] { TernaryTree tree(boxes); }, ErrorCode::BadInput,
                        {"TernaryTree: object 4 has an invalid box"});
  bvh::TernaryDesc desc;
  desc.max_depth = 0;
  test::expectBothForms([&] { return TernaryTree::create({}, desc); },
                        [&] { TernaryTree tree({}, desc); }, ErrorCode::InvalidArgument,
                        {"ternary tree: max_depth 0 is out of range"});
  boxes[4].max.z = boxes[4].min.z;
  Result<TernaryTree> tree = TernaryTree::create(boxes);
  ASSERT_TRUE(tree.ok()) << tree.status().message();
  EXPECT_EQ(tree->objectTotal(), boxes.size());
}

TEST(MotionKind, AnUnknownKindIsRefused) {
  test::expectStatus(bvh::tryMakeMotionHierarchy(MotionKind(99), {}).status(),
                     ErrorCode::InvalidArgument, {"motion: unknown hierarchy kind"});
}

TEST(MotionDesc, BadSettingsAreRefusedWithTheField) {
  bvh::MotionDesc d;
  d.ternary.r_split = 1.5;
  EXPECT_NE(bvh::validateMotionDesc(d).find("r_split"), std::string::npos);
  d = {};
  d.rebuild_growth = -1;
  EXPECT_NE(bvh::validateMotionDesc(d).find("rebuild_growth"), std::string::npos);
  d = {};
  d.ternary.o_split = 1;
  EXPECT_NE(bvh::validateMotionDesc(d).find("o_split"), std::string::npos);
  EXPECT_THROW(bvh::makeMotionHierarchy(MotionKind::Ternary, {}, d), Error);
  EXPECT_EQ(bvh::parseMotionKind("ternary"), MotionKind::Ternary);
  EXPECT_FALSE(bvh::parseMotionKind("octree"));
}

// ---------------------------------------------------------------------------
// Culling moving boxes: nothing visible is missed.
// ---------------------------------------------------------------------------

struct CullCase {
  MotionKind kind;
  Method method;
  std::uint32_t lookahead;
  bool colliding;
  DepthConvention convention;
};

class MovingBoxes : public testing::TestWithParam<CullCase> {};

TEST_P(MovingBoxes, NoVisibleBoxIsMissed) {
  const CullCase c = GetParam();
  test::BoxWorld world = test::makeBoxWorld(31);
  bvh::MotionDesc desc;
  desc.ternary.o_split = 6;
  desc.ternary.o_merge = 2;
  auto h = bvh::makeMotionHierarchy(c.kind, world.boxes, desc);
  CullerDesc cd;
  cd.method = c.method;
  cd.tile_size = 16;
  cd.lookahead = c.lookahead;
  cd.detect_colliding = c.colliding;
  Culler culler(cd);
  culler.setObserver(h->observer());
  std::vector<Aabb> start = world.boxes;
  std::vector<ObjectId> moved;
  std::uint64_t drawn = 0, occluded = 0, measured = 0, splits = 0, waits = 0;
  for (int frame = 0; frame < 10; ++frame) {
    // Half of the random boxes drift sideways and back, some through the walls; every
    // third frame they stand.
    moved.clear();
    if (frame % 3 != 2) {
      for (ObjectId id = 0; id < 300; ++id) {
        const float dx = 12.0f * std::sin(0.7f * float(frame) + float(id));
        Aabb& b = world.boxes[id];
        b = start[id];
        b.min.x += dx, b.max.x += dx;
        b.min.z += 0.5f * dx, b.max.z += 0.5f * dx;
        moved.push_back(id);
      }
    }
    const Camera cam = test::boxCamera(160, 96, c.convention, -0.2 + 0.05 * frame);
    const bvh::UpdateStats u = h->update({&world.boxes, &moved, {0.1, 0, -1}});
    splits += u.splits + u.merges;
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    std::set<ObjectId> seen;
    const FrameStats stats = culler.cullFrame(cam, *h, depth, [&](ObjectId id) {
      test::drawBox(raster, world.boxes[id], id);
      EXPECT_TRUE(seen.insert(id).second) << "drawn twice: " << id;
    });
    measured += h->measure(cam, depth).counted;
    for (ObjectId id : test::visibleBoxes(world.boxes, cam)) {
      EXPECT_TRUE(seen.count(id)) << "frame " << frame << ": visible box " << id << " culled";
    }
    drawn += seen.size();
    occluded += stats.boxes_occluded;
    waits += stats.colliding_waits;
  }
  EXPECT_GT(occluded, 0u);
  if (c.kind == MotionKind::Ternary || c.kind == MotionKind::TernaryObjects) {
    EXPECT_GT(measured, 0u) << "§3.3: visible leaves are counted after each frame";
    EXPECT_GT(splits, 0u) << "the statistics drive splits or merges";
  }
  if (c.colliding && c.lookahead > 1) {
    EXPECT_GT(waits, 0u);
  }
  if (!c.colliding) {
    EXPECT_EQ(waits, 0u);
  }
  std::printf("[ moving ] %s %s K=%u colliding=%d: drawn %llu, occluded %llu, waits %llu\n",
              bvh::motionInfo(c.kind).name, toString(c.method), c.lookahead, int(c.colliding),
              (unsigned long long)drawn, (unsigned long long)occluded, (unsigned long long)waits);
}

std::vector<CullCase> cullCases() {
  std::vector<CullCase> out;
  for (const bvh::MotionInfo& info : bvh::motionTable()) {
    const MotionKind k = info.kind;
    for (Method m : {Method::LogState, Method::LogZfar}) {
      out.push_back({k, m, 1, false, DepthConvention::Standard});
      out.push_back({k, m, kUnlimitedLookahead, true, DepthConvention::Reversed});
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Hierarchies, MovingBoxes, testing::ValuesIn(cullCases()),
                         [](const testing::TestParamInfo<CullCase>& p) {
                           const CullCase& c = p.param;
                           std::string s = std::string(bvh::motionInfo(c.kind).name) + "_" +
                                           toString(c.method) +
                                           (c.colliding ? "_colliding_" : "_") +
                                           toString(c.convention);
                           for (char& ch : s) ch = ch == '-' ? '_' : ch;
                           return s;
                         });

// ---------------------------------------------------------------------------
// §3.5 colliding queries.
// ---------------------------------------------------------------------------

// Two leaves under one root: a wall near the camera and a box right behind it. Before
// the frame a far backdrop is drawn (so every tile must be read). In one batch both are
// read before the wall is drawn and the box counts as visible; with colliding-query
// detection the box waits, the wall is drawn, and the box is found hidden.
class TwoBoxes final : public Hierarchy {
 public:
  std::vector<Aabb> boxes{box(-3, -2, -6, 3, 2, -5.5f), box(-1, -1, -20, 1, 1, -18)};
  NodeId root() const override { return 0; }
  Aabb bounds(NodeId n) const override {
    // The root holds the eye, so it is visible without a test and both leaves are read
    // from the tiles the backdrop left outdated.
    return n == 0 ? box(-3, -2, -20, 3, 2, 1) : boxes[n - 1];
  }
  std::uint32_t childCount(NodeId n) const override { return n == 0 ? 2 : 0; }
  NodeId child(NodeId, std::uint32_t i) const override { return i + 1; }
  std::uint32_t objectCount(NodeId n) const override { return n == 0 ? 0 : 1; }
  ObjectId object(NodeId n, std::uint32_t) const override { return n - 1; }
};

std::set<ObjectId> cullTwoBoxes(Method method, bool colliding, FrameStats& stats) {
  TwoBoxes h;
  CullerDesc cd;
  cd.method = method;
  cd.tile_size = 8;
  cd.lookahead = kUnlimitedLookahead;
  cd.detect_colliding = colliding;
  Culler culler(cd);
  Camera cam;
  cam.width = 64;
  cam.height = 64;
  cam.view_projection = perspective(1.2, 1.0, 0.5, 100, cam.depth);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  cpu::SoftwareRasterizer raster(cam, depth, nullptr);
  test::drawBox(raster, box(-50, -50, -90, 50, 50, -89), 99);  // the backdrop
  const Projector projector(cam);
  const BoxProjection backdrop = projector.project(box(-50, -50, -90, 50, 50, -89));
  std::set<ObjectId> drawn;
  stats = culler.cullFrame(cam, h, depth,
                           [&](ObjectId id) {
                             test::drawBox(raster, h.boxes[id], id);
                             drawn.insert(id);
                           },
                           {{backdrop.rect, backdrop.far_key + backdrop.margin}});
  return drawn;
}

TEST(CollidingQueries, TheFartherBoxWaitsForTheNearerOneAndIsHidden) {
  for (Method m : {Method::LogState, Method::LogZfar}) {
    FrameStats batched, waited;
    const std::set<ObjectId> without = cullTwoBoxes(m, false, batched);
    const std::set<ObjectId> with = cullTwoBoxes(m, true, waited);
    EXPECT_EQ(without, (std::set<ObjectId>{0, 1})) << toString(m) << ": read in one batch";
    EXPECT_EQ(batched.colliding_waits, 0u);
    EXPECT_EQ(with, (std::set<ObjectId>{0})) << toString(m) << ": the box waits and is hidden";
    EXPECT_EQ(waited.colliding_waits, 1u);
    EXPECT_GT(waited.batches, batched.batches) << "waiting costs a batch";
  }
}

}  // namespace
}  // namespace logrid
