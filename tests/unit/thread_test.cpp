// Everything in logrid that starts threads, driven hard enough that the threads really
// run (the builders split work only above their thresholds): the BVH builder's parallel
// subtrees (std::async above 100,000 objects), the DDO build's welding and edge linking
// (above 100,000 triangles) and its face workers, and the CPU occlusion buffer's worker
// threads with requests between draws (and the pool they run on). Each result is compared with the
// one-thread result, so a race that changes an answer fails here in any build; scripts/tsan.sh runs
// this program under ThreadSanitizer, which also reports races that change none.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <thread>

#include "ddo_scenes.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/ddo/build.hpp"
#include "occluder_scenes.hpp"
#include "worker_pool.hpp"

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

// What a buffer answers over one frame: the area asked about after each draw, and the
// whole buffer at the end.
struct BufferRun {
  std::vector<float> keys;
  std::vector<AreaDepth> areas;
};

// One frame of `b`: every object drawn (in the last frame, `frame` == 2, every other one
// moved by `turned`), a request after every fourth draw, the whole buffer read at the end.
BufferRun runFrame(cpu::OcclusionBuffer& b, const cpu::OccluderMeshes& meshes, const Camera& cam,
                   std::uint32_t frame, const cpu::ObjectTransform& turned) {
  BufferRun out;
  orThrow(b.beginFrame(cam));
  for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) {
    if (frame == 2 && i % 2) {
      b.drawObject(i, turned);
    } else {
      b.drawObject(i);
    }
    if (i % 4 != 3) continue;  // several objects between requests: their order matters
    const PixelRect corner{std::int32_t(i % 5) * 16, 8, std::int32_t(i % 5) * 16 + 24, 40};
    AreaDepth a;
    b.summarize(&corner, 1, &a);
    out.areas.push_back(a);
  }
  out.keys.resize(std::size_t(cam.width) * cam.height);
  b.readKeys({0, 0, std::int32_t(cam.width), std::int32_t(cam.height)}, out.keys.data());
  orThrow(b.endFrame());
  return out;
}

// Runs `buffers` (one descriptor each, all on the same scene) over three frames of three
// random scenes and expects every one to answer and hold what the first does, bit for
// bit. `min_covered`: keys in front of the clear key the first must hold in all.
void expectTheSameBuffers(const std::vector<cpu::OcclusionBufferDesc>& descs,
                          std::size_t min_covered) {
  // The last frame moves every other object (turned about the y axis and lifted),
  // handed over with its transform.
  cpu::ObjectTransform turned;
  const double c = std::cos(0.3), sn = std::sin(0.3);
  const double rotation[9] = {c, 0, -sn, 0, 1, 0, sn, 0, c};
  std::copy(rotation, rotation + 9, turned.rotation);
  turned.translation = {0.2, 0.5, -0.1};
  std::size_t covered = 0;
  for (int s = 0; s < 3; ++s) {
    const cpu::OccluderMeshes meshes = meshesOf(test::randomScene(std::uint32_t(s) + 70));
    std::vector<std::unique_ptr<cpu::OcclusionBuffer>> buffers;
    for (const cpu::OcclusionBufferDesc& d : descs) {
      buffers.push_back(std::make_unique<cpu::OcclusionBuffer>(meshes, d));
    }
    for (std::uint32_t frame = 0; frame < 3; ++frame) {
      const bool reversed = frame % 2 != 0;
      const Camera cam =
          test::randomCamera(std::uint32_t(s) * 5 + frame + 1, 96, 64,
                             reversed ? DepthConvention::Reversed : DepthConvention::Standard,
                             ClipDepthRange::ZeroToOne, DepthFormat::D32F);
      const BufferRun first = runFrame(*buffers[0], meshes, cam, frame, turned);
      for (float k : first.keys) covered += reversed ? k > 0.0f : k < 1.0f;
      for (std::size_t n = 1; n < buffers.size(); ++n) {
        const BufferRun other = runFrame(*buffers[n], meshes, cam, frame, turned);
        ASSERT_EQ(first.keys, other.keys) << "buffer " << n << " (" << descs[n].threads
                                          << " workers), scene " << s << " frame " << frame;
        for (std::size_t i = 0; i < first.areas.size(); ++i) {
          EXPECT_EQ(std::memcmp(&first.areas[i], &other.areas[i], sizeof(AreaDepth)), 0)
              << "buffer " << n << ", scene " << s << " frame " << frame << " request " << i;
        }
      }
    }
    for (std::size_t n = 0; n < buffers.size(); ++n) {
      if (descs[n].threads == 0) continue;
      // Which thread runs a task is up to the scheduler (the caller takes what is queued
      // when it waits): printed, not asserted; the pool's test below asserts that every
      // thread takes work.
      std::printf("%u threads: %.3f ms on the started ones\n", descs[n].threads,
                  buffers[n]->stats().worker_seconds * 1e3);
      EXPECT_GT(buffers[n]->stats().objects_moved, 0u);
      EXPECT_EQ(buffers[n]->stats().objects_set_up,
                buffers[n]->stats().objects_drawn - buffers[n]->stats().objects_skipped);
    }
  }
  EXPECT_GE(covered, min_covered) << "the buffers held too few keys to compare";
}

TEST(Threads, OcclusionBufferWorkersAnswerAsTheLazyCaller) {
  // One, two and three workers rasterise binned triangles while the caller asks for
  // areas between draws and reads the whole buffer at the end, over frames of one buffer
  // (the tiles of the frame before are cleared by the workers): per pixel, every key and
  // answer as the lazy caller's.
  std::vector<cpu::OcclusionBufferDesc> descs(4);
  for (std::uint32_t n = 0; n < 4; ++n) descs[n].threads = n;
  expectTheSameBuffers(descs, 1000);
}

TEST(Threads, MaskedOcclusionBufferIsTheSameForEveryWorkerCount) {
  // The masked blocks depend on the order triangles land in: the workers merge each
  // bin's triangles in draw order, so one to four workers write the same blocks.
  std::vector<cpu::OcclusionBufferDesc> descs(4);
  for (std::uint32_t n = 0; n < 4; ++n) {
    descs[n].threads = n + 1;
    descs[n].representation = cpu::Representation::Masked;
  }
  expectTheSameBuffers(descs, 1000);
}

TEST(Threads, WorkerPoolRunsEveryTaskOnceInPostedOrderPerWorker) {
  // Tasks posted one by one: each runs once, and the tasks one worker (the caller
  // included) runs are in the order posted (the buffer's draw order per bin rests on it).
  // Then forEach: each index once, and nothing left running when it returns. And a pool
  // of no thread: the caller runs everything in wait().
  struct Log {
    std::vector<std::vector<std::size_t>> by_worker;
    std::vector<std::uint32_t> runs;
  };
  cpu::detail::WorkerPool pool(3);
  ASSERT_EQ(pool.size(), 3u);
  Log log;
  log.by_worker.resize(pool.size() + 1);  // the caller runs tasks too, as worker 3
  constexpr std::size_t kTasks = 5000;
  log.runs.assign(kTasks, 0);
  auto record = [](void* context, std::uint32_t worker, std::size_t index) {
    Log& l = *static_cast<Log*>(context);
    l.by_worker[worker].push_back(index);
    ++l.runs[index];  // each index is one task: no two threads write one element
  };
  for (std::size_t i = 0; i < kTasks; ++i) pool.post(record, &log, i);
  pool.wait();
  std::size_t total = 0, busy_workers = 0;
  for (const std::vector<std::size_t>& w : log.by_worker) {
    EXPECT_TRUE(std::is_sorted(w.begin(), w.end()));
    total += w.size();
    busy_workers += !w.empty();
  }
  EXPECT_EQ(total, kTasks);
  EXPECT_EQ(std::count(log.runs.begin(), log.runs.end(), 1u), std::ptrdiff_t(kTasks));
  // forEach over four jobs that each wait until all four have started: it returns only
  // if the three threads and the caller each took one (a pool that left a thread idle
  // would hang here).
  struct Meeting {
    std::atomic<std::uint32_t> arrived{0};
    std::uint32_t worker_of[4] = {9, 9, 9, 9};
  } meeting;
  pool.forEach(
      4,
      [](void* c, std::uint32_t worker, std::size_t i) {
        Meeting& m = *static_cast<Meeting*>(c);
        m.worker_of[i] = worker;
        m.arrived.fetch_add(1);
        while (m.arrived.load() < 4) std::this_thread::yield();
      },
      &meeting);
  std::uint32_t sorted[4];
  std::copy(meeting.worker_of, meeting.worker_of + 4, sorted);
  std::sort(sorted, sorted + 4);
  for (std::uint32_t w = 0; w < 4; ++w) EXPECT_EQ(sorted[w], w) << "forEach's jobs by worker";
  EXPECT_GT(pool.busySeconds(), 0.0);
  std::vector<std::uint32_t> each(kTasks, 0);
  pool.forEach(
      kTasks,
      [](void* c, std::uint32_t, std::size_t i) {
        ++(*static_cast<std::vector<std::uint32_t>*>(c))[i];
      },
      &each);
  EXPECT_EQ(std::count(each.begin(), each.end(), 1u), std::ptrdiff_t(kTasks));
  std::printf("%zu of 3 workers and the caller took posted tasks\n", busy_workers);
  cpu::detail::WorkerPool none(0);
  std::vector<std::uint32_t> runs(100, 0);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    none.post(
        [](void* c, std::uint32_t worker, std::size_t index) {
          if (worker == 0) ++(*static_cast<std::vector<std::uint32_t>*>(c))[index];
        },
        &runs, i);
  }
  EXPECT_EQ(std::count(runs.begin(), runs.end(), 0u), 100)
      << "a pool of no thread ran a task before wait()";
  none.wait();
  EXPECT_EQ(std::count(runs.begin(), runs.end(), 1u), 100);
}

}  // namespace
}  // namespace logrid
