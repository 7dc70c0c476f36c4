// Everything in logrid that starts threads, driven hard enough that the threads really
// run (the builders split work only above their thresholds): the BVH builder's parallel
// subtrees (std::async above 100,000 objects), the DDO build's welding and edge linking
// (above 100,000 triangles) and its face workers, and the CPU occlusion buffer's worker
// threads with requests between draws. Each result is compared with the one-thread
// result, so a race that changes an answer fails here in any build; scripts/tsan.sh
// runs this program under ThreadSanitizer, which also reports races that change none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "ddo_scenes.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/ddo/build.hpp"
#include "occluder_scenes.hpp"

namespace logrid {
namespace {

TEST(Threads, BvhBuildOnWorkersEqualsTheOneThreadBuild) {
  // 2^18 objects: above the builder's threshold at the root and its two children, so
  // with four threads three subtrees are built by std::async.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-1000, 1000), size(0.1f, 4);
  std::vector<Aabb> boxes(1u << 18);
  for (Aabb& b : boxes) {
    b.min = {pos(rng), pos(rng), pos(rng)};
    b.max = {b.min.x + size(rng), b.min.y + size(rng), b.min.z + size(rng)};
  }
  bvh::BuildArgs one;
  one.max_leaf_size = 4;
  one.threads = 1;
  bvh::BuildArgs four = one;
  four.threads = 4;
  const bvh::FlatHierarchy a = bvh::buildOverBoxes(boxes, one);
  const bvh::FlatHierarchy b = bvh::buildOverBoxes(boxes, four);
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  ASSERT_EQ(a.objects(), b.objects());
  for (std::size_t n = 0; n < a.nodes().size(); ++n) {
    const bvh::FlatHierarchy::Node &x = a.nodes()[n], &y = b.nodes()[n];
    ASSERT_TRUE(x.first_child == y.first_child && x.child_count == y.child_count &&
                x.first_object == y.first_object && x.object_count == y.object_count &&
                std::memcmp(&x.box, &y.box, sizeof x.box) == 0)
        << "node " << n << " differs between one and four threads";
  }
}

TEST(Threads, DdoBuildOnWorkersEqualsTheOneThreadBuild) {
  // 2 x 2 x 160^2 = 102,400 wall triangles and some clutter: welding and edge linking
  // run on threads; the faces are tested by a pool of workers either way.
  test::TriangleScene s;
  test::TriangleScene::WallOptions wall;
  wall.n = 160;
  s.wall(2, 0.25, -8, 8, -8, 8, wall);
  s.wall(0, 3.5, -8, 8, -8, 8, wall);
  std::mt19937 rng(7);
  s.clutter(rng, 400, -10, 10, 0.3);
  ddo::BuildArgs args;
  args.leaf_triangles = 8192;
  args.regions = 32;
  args.threads = 1;
  const ddo::Octree one = ddo::buildOctree(s.mesh(), args);
  args.threads = 3;
  ddo::BuildReport report;
  const ddo::Octree three = ddo::buildOctree(s.mesh(), args, {}, &report);
  EXPECT_EQ(report.threads, 3u);
  ASSERT_EQ(one.nodes().size(), three.nodes().size());
  EXPECT_GT(one.nodes().size(), 1u);
  EXPECT_EQ(one.masks(), three.masks()) << "face masks differ between one and three threads";
  for (std::size_t n = 0; n < one.nodes().size(); ++n) {
    EXPECT_EQ(one.nodes()[n].triangle_count, three.nodes()[n].triangle_count) << "node " << n;
    EXPECT_EQ(one.nodes()[n].child_mask, three.nodes()[n].child_mask) << "node " << n;
  }
  EXPECT_GT(report.faces_valid, 0u) << "no face was valid; the walls test nothing";
}

cpu::OccluderMeshes meshesOf(const std::vector<test::TestMesh>& scene) {
  cpu::OccluderMeshes m;
  for (const test::TestMesh& t : scene) {
    m.addObject(t.positions.data(), t.positions.size() / 3, t.indices.data(), t.indices.size());
  }
  return m;
}

TEST(Threads, OcclusionBufferWorkersAnswerAsTheLazyCaller) {
  // Three workers draw while the caller asks for areas between draws and reads the
  // whole buffer at the end, over frames of one buffer (the tiles of the frame before
  // are cleared by the workers). In the last frame every other object moves (turned
  // about the y axis and lifted), handed over with its transform.
  cpu::ObjectTransform turned;
  const double c = std::cos(0.3), sn = std::sin(0.3);
  const double rotation[9] = {c, 0, -sn, 0, 1, 0, sn, 0, c};
  std::copy(rotation, rotation + 9, turned.rotation);
  turned.translation = {0.2, 0.5, -0.1};
  for (int s = 0; s < 3; ++s) {
    const cpu::OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s) + 70));
    cpu::OcclusionBufferDesc lazy;
    lazy.threads = 0;
    cpu::OcclusionBufferDesc workers = lazy;
    workers.threads = 3;
    cpu::OcclusionBuffer reference(meshes, lazy), threaded(meshes, workers);
    for (std::uint32_t frame = 0; frame < 3; ++frame) {
      const Camera cam =
          test::randomCamera(std::uint32_t(s) * 5 + frame + 1, 96, 64,
                             frame % 2 ? DepthConvention::Reversed : DepthConvention::Standard,
                             ClipDepthRange::ZeroToOne, DepthFormat::D32F);
      std::vector<std::vector<float>> keys;
      std::vector<AreaDepth> areas;
      for (cpu::OcclusionBuffer* b : {&reference, &threaded}) {
        orThrow(b->beginFrame(cam));
        for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) {
          if (frame == 2 && i % 2) {
            b->drawObject(i, turned);
          } else {
            b->drawObject(i);
          }
          const PixelRect corner{std::int32_t(i % 5) * 16, 8, std::int32_t(i % 5) * 16 + 24, 40};
          AreaDepth a;
          b->summarize(&corner, 1, &a);
          areas.push_back(a);
        }
        std::vector<float> k(std::size_t(cam.width) * cam.height);
        b->readKeys({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, k.data());
        orThrow(b->endFrame());
        keys.push_back(std::move(k));
      }
      ASSERT_EQ(keys[0], keys[1]) << "scene " << s << " frame " << frame;
      const std::size_t half = areas.size() / 2;
      for (std::size_t i = 0; i < half; ++i) {
        EXPECT_EQ(std::memcmp(&areas[i], &areas[half + i], sizeof(AreaDepth)), 0)
            << "scene " << s << " frame " << frame << " area after object " << i;
      }
    }
    EXPECT_GT(threaded.stats().worker_seconds, 0.0);
    EXPECT_GT(threaded.stats().objects_moved, 0u);
  }
}

}  // namespace
}  // namespace logrid
