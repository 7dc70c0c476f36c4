// Hierarchy invariants: every primitive in exactly one leaf, boxes contain their
// children and primitives, the leaf bound holds, children follow parents; refit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "expect_status.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

bool contains(const Aabb& outer, const Aabb& inner) {
  return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
         outer.max.x >= inner.max.x && outer.max.y >= inner.max.y && outer.max.z >= inner.max.z;
}

std::vector<Aabb> randomBoxes(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-100, 100), size(0, 5);
  std::vector<Aabb> boxes(n);
  for (Aabb& b : boxes) {
    b.min = {pos(rng), pos(rng), pos(rng)};
    b.max = {b.min.x + size(rng), b.min.y + size(rng), b.min.z + size(rng)};
  }
  return boxes;
}

void checkStructure(const bvh::FlatHierarchy& h, std::size_t objects, std::uint32_t leaf,
                    std::uint32_t max_children) {
  const auto& nodes = h.nodes();
  ASSERT_FALSE(nodes.empty());
  std::vector<int> seen(objects, 0);
  std::vector<int> parents(nodes.size(), 0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const auto& node = nodes[n];
    EXPECT_LE(node.child_count, max_children);
    EXPECT_NE(node.child_count == 0, node.object_count == 0) << "node " << n;
    EXPECT_LE(node.object_count, leaf);
    for (std::uint32_t c = 0; c < node.child_count; ++c) {
      const std::uint32_t child = node.first_child + c;
      ASSERT_LT(child, nodes.size());
      EXPECT_GT(child, n);
      ++parents[child];
      EXPECT_TRUE(contains(node.box, nodes[child].box)) << "node " << n << " child " << child;
    }
    for (std::uint32_t i = 0; i < node.object_count; ++i) ++seen[h.object(NodeId(n), i)];
  }
  for (std::size_t n = 1; n < nodes.size(); ++n) EXPECT_EQ(parents[n], 1) << "node " << n;
  for (std::size_t i = 0; i < objects; ++i) EXPECT_EQ(seen[i], 1) << "object " << i;
}

TEST(BvhTest, OverBoxesEveryObjectInOneLeafAndBoxesNest) {
  for (std::uint32_t leaf : {1u, 3u, 16u}) {
    for (std::uint32_t children : {2u, 4u, 8u}) {
      const auto boxes = randomBoxes(1000, leaf * 10 + children);
      const bvh::FlatHierarchy h = bvh::buildOverBoxes(boxes, {leaf, children, 2});
      checkStructure(h, boxes.size(), leaf, children);
      for (const auto& node : h.nodes()) {
        for (std::uint32_t i = 0; i < node.object_count; ++i) {
          EXPECT_TRUE(contains(node.box, boxes[h.objects()[node.first_object + i]]));
        }
      }
    }
  }
}

TEST(BvhTest, BuildIsDeterministicWhateverTheThreadCount) {
  const auto boxes = randomBoxes(300000, 3);
  const bvh::FlatHierarchy a = bvh::buildOverBoxes(boxes, {4, 2, 1});
  const bvh::FlatHierarchy b = bvh::buildOverBoxes(boxes, {4, 2, 4});
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  EXPECT_EQ(a.objects(), b.objects());
}

TEST(BvhTest, EmptyAndSingleObject) {
  EXPECT_EQ(bvh::buildOverBoxes({}).root(), kNoNode);
  const bvh::FlatHierarchy one = bvh::buildOverBoxes({{{0, 0, 0}, {1, 1, 1}}});
  ASSERT_EQ(one.nodes().size(), 1u);
  EXPECT_EQ(one.objectCount(0), 1u);
}

TEST(BvhTest, OverTrianglesLeavesRespectTheBoundAndChunksAreContiguous) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> pos(-50, 50);
  std::vector<float> positions(3 * 20000);
  for (float& p : positions) p = pos(rng);
  std::vector<std::uint32_t> indices(3 * 30000);
  for (std::uint32_t& i : indices) i = std::uint32_t(rng() % 20000);
  const bvh::TriangleHierarchy th = bvh::buildOverTriangles(positions, indices, {1500, 2, 0});
  const auto& h = th.hierarchy;
  checkStructure(h, h.objects().size(), 1, 2);
  ASSERT_EQ(th.chunk_first.size(), h.objects().size() + 1);
  EXPECT_EQ(th.chunk_first.front(), 0u);
  EXPECT_EQ(th.chunk_first.back(), 30000u);
  std::vector<int> seen(30000, 0);
  for (std::uint32_t t : th.triangle_order) ++seen[t];
  for (int s : seen) EXPECT_EQ(s, 1);
  for (std::size_t n = 0; n < h.nodes().size(); ++n) {
    const auto& node = h.nodes()[n];
    if (node.child_count) continue;
    const ObjectId chunk = h.object(NodeId(n), 0);
    const std::uint32_t first = th.chunk_first[chunk], last = th.chunk_first[chunk + 1];
    EXPECT_LE(last - first, 1500u);
    EXPECT_GT(last, first);
    for (std::uint32_t i = first; i < last; ++i) {
      const std::uint32_t t = th.triangle_order[i];
      for (int k = 0; k < 3; ++k) {
        const float* p = &positions[indices[t * 3 + std::uint32_t(k)] * 3];
        EXPECT_TRUE(contains(node.box, {{p[0], p[1], p[2]}, {p[0], p[1], p[2]}}));
      }
    }
  }
}

TEST(BvhTest, RefitFollowsMovedObjects) {
  auto boxes = randomBoxes(500, 4);
  bvh::FlatHierarchy h = bvh::buildOverBoxes(boxes, {2, 2, 1});
  for (Aabb& b : boxes) {  // move everything by (+300, 0, -7)
    b.min.x += 300, b.max.x += 300, b.min.z -= 7, b.max.z -= 7;
  }
  boxes[17].max.y += 1000;  // and one grows
  h.refit(boxes);
  checkStructure(h, boxes.size(), 2, 2);
  for (const auto& node : h.nodes()) {
    for (std::uint32_t i = 0; i < node.object_count; ++i) {
      EXPECT_TRUE(contains(node.box, boxes[h.objects()[node.first_object + i]]));
    }
  }
  EXPECT_GE(h.bounds(h.root()).max.y, boxes[17].max.y);
  EXPECT_THROW(h.refit(std::vector<Aabb>(3)), Error);
}

TEST(BvhTest, BadInputIsAClearError) {
  try {
    bvh::buildOverBoxes({{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {0, 1, 1}}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("object 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bvh::buildOverBoxes({{{NAN, 0, 0}, {1, 1, 1}}}), Error);
  try {
    bvh::buildOverTriangles({0, 0, 0, 1, 0, 0}, {0, 1, 2});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bvh::buildOverTriangles({0, 0, INFINITY, 1, 0, 0, 0, 1, 0}, {0, 1, 2}), Error);
  EXPECT_THROW(bvh::buildOverBoxes({}, {0, 2, 0}), Error);
  EXPECT_THROW(bvh::buildOverBoxes({}, {1, 3, 0}), Error);
}

// The result forms (logrid/error.hpp) return the error the throwing forms throw, with
// the same code and message.
TEST(BvhTest, TryBuildReturnsWhatBuildThrows) {
  const std::vector<Aabb> bad_box{{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {0, 1, 1}}};
  test::expectBothForms([&] { return bvh::tryBuildOverBoxes(bad_box); },
                        [&] { bvh::buildOverBoxes(bad_box); }, ErrorCode::BadInput,
                        {"bvh: object 1 has an invalid box (min 1 0 0, max 0 1 1)"});
  test::expectBothForms(
      [&] {
        return bvh::tryBuildOverBoxes({}, {1, 3, 0});
      },
      [&] {
        bvh::buildOverBoxes({}, {1, 3, 0});
      },
      ErrorCode::InvalidArgument, {"bvh: max_children 3 is invalid; use 2, 4 or 8"});
  const std::vector<float> positions{0, 0, 0, 1, 0, 0};
  const std::vector<std::uint32_t> indices{0, 1, 2};
  test::expectBothForms([&] { return bvh::tryBuildOverTriangles(positions, indices); },
                        [&] { bvh::buildOverTriangles(positions, indices); }, ErrorCode::BadInput,
                        {"bvh: triangle 0 uses vertex 2 but there are only 2 vertices"});
  const std::vector<float> infinite{0, 0, INFINITY, 1, 0, 0, 0, 1, 0};
  test::expectBothForms([&] { return bvh::tryBuildOverTriangles(infinite, indices); },
                        [&] { bvh::buildOverTriangles(infinite, indices); }, ErrorCode::BadInput,
                        {"bvh: vertex 0 has a non-finite coordinate (z = inf)"});
  const std::vector<float> two{0, 0, 0, 1, 0};
  test::expectBothForms([&] { return bvh::tryBuildOverTriangles(two, indices); },
                        [&] { bvh::buildOverTriangles(two, indices); }, ErrorCode::BadInput,
                        {"positions and indices must come in threes"});
  const Result<bvh::FlatHierarchy> built = bvh::tryBuildOverBoxes(randomBoxes(50, 3), {2, 4, 1});
  ASSERT_TRUE(built.ok()) << built.status().message();
  checkStructure(built.value(), 50, 2, 4);
}

TEST(BvhTest, TryRefitReturnsWhatRefitThrowsAndChangesNothing) {
  std::vector<Aabb> boxes = randomBoxes(30, 4);
  bvh::FlatHierarchy h = bvh::buildOverBoxes(boxes);
  const std::vector<bvh::FlatHierarchy::Node> before = h.nodes();
  const std::vector<Aabb> short_list(boxes.begin(), boxes.begin() + 10);
  test::expectBothForms([&] { return h.tryRefit(short_list); }, [&] { h.refit(short_list); },
                        ErrorCode::InvalidArgument, {"FlatHierarchy::refit: object", "10 boxes"});
  boxes[12].max.y = NAN;
  const std::vector<ObjectId> moved{12};
  test::expectBothForms([&] { return h.tryRefit(boxes, moved); }, [&] { h.refit(boxes, moved); },
                        ErrorCode::BadInput,
                        {"FlatHierarchy::refit: object 12 has an invalid box"});
  test::expectBothForms([&] { return h.tryRefit(boxes); }, [&] { h.refit(boxes); },
                        ErrorCode::BadInput, {"FlatHierarchy::refit: object 12"});
  const std::vector<ObjectId> unknown{30};
  test::expectBothForms([&] { return h.tryRefit(boxes, unknown); },
                        [&] { h.refit(boxes, unknown); }, ErrorCode::InvalidArgument,
                        {"moved object 30 is not in the hierarchy"});
  ASSERT_EQ(h.nodes().size(), before.size());
  for (std::size_t n = 0; n < before.size(); ++n) {
    EXPECT_EQ(std::memcmp(&h.nodes()[n].box, &before[n].box, sizeof(Aabb)), 0) << "node " << n;
  }
}

}  // namespace
}  // namespace logrid
