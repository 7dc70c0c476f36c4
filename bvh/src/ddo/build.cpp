#include "logrid/ddo/build.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include "logrid/elapsed.hpp"
#include "octree_build.hpp"
#include "segment_index.hpp"
#include "topology.hpp"
#include "validity.hpp"

namespace logrid::ddo {

std::string validateBuildArgs(const BuildArgs& args) {
  std::ostringstream out;
  if (args.leaf_triangles < 1) {
    out << "ddo: leaf_triangles " << args.leaf_triangles << " is invalid; use 1 or more";
  } else if (!RegionLayout::forCount(args.regions)) {
    out << "ddo: regions " << args.regions << " is invalid; use 32 or 64";
  } else if (args.max_depth < 1 || args.max_depth > 24) {
    out << "ddo: max_depth " << args.max_depth << " is out of range; use 1 to 24";
  } else if (args.threads > 1024) {
    out << "ddo: threads " << args.threads << " is out of range; use 0 (one per hardware thread) "
        << "up to 1024";
  } else if (args.max_piece_triangles < 1) {
    out << "ddo: max_piece_triangles " << args.max_piece_triangles << " is invalid; use 1 or more";
  }
  return out.str();
}

namespace {

using Clock = std::chrono::steady_clock;

// True when the scene has nothing beyond the face's plane (on the side away from its
// node): such a face hides nothing, so it is never worth testing or drawing.
bool nothingBehind(const FaceFrame& face, const Aabb& scene) {
  const double lo[3] = {scene.min.x, scene.min.y, scene.min.z};
  const double hi[3] = {scene.max.x, scene.max.y, scene.max.z};
  return face.dir > 0 ? lo[face.axis] >= face.plane : hi[face.axis] <= face.plane;
}

void tell(const ProgressCallback& progress, const char* stage, std::uint64_t done,
          std::uint64_t total) {
  if (progress) progress({stage, done, total});
}

// One thread's counts of the face tests.
struct FaceCounts {
  detail::FaceCounters tests;
  std::uint64_t nothing_behind = 0, valid = 0;
};

// Every face's mask of valid regions, the nodes shared among `threads` in small batches;
// progress told every 200 ms. Answers each thread's counts.
std::vector<FaceCounts> testFaces(Octree& octree, const detail::FaceTester& tester,
                                  unsigned threads, const ProgressCallback& progress) {
  const std::size_t node_count = octree.nodes().size();
  const Aabb scene_bounds = octree.nodes().front().bounds;
  std::atomic<std::size_t> next_node{0}, done_nodes{0};
  std::vector<FaceCounts> counts(threads);
  // The face tests report no errors (bad input was refused before): a worker always runs
  // to the end of the nodes.
  auto worker = [&](unsigned id) {
    detail::FaceScratch scratch;
    tester.prepare(scratch);
    constexpr std::size_t kBatch = 16;
    for (;;) {
      const std::size_t first = next_node.fetch_add(kBatch);
      if (first >= node_count) break;
      const std::size_t last = std::min(node_count, first + kBatch);
      for (std::size_t n = first; n < last; ++n) {
        for (int f = 0; f < kFaces; ++f) {
          const FaceFrame frame = octree.face(std::uint32_t(n), f);
          if (nothingBehind(frame, scene_bounds)) {
            ++counts[id].nothing_behind;
            continue;
          }
          const std::uint64_t bits = tester.validRegions(frame, scratch, counts[id].tests);
          octree.setMask(std::uint32_t(n), f, bits);
          counts[id].valid += bits != 0;
        }
      }
      done_nodes.fetch_add(last - first);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < threads; ++i) pool.emplace_back(worker, i);
  tell(progress, "faces", 0, node_count);
  while (done_nodes.load() < node_count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    tell(progress, "faces", std::min(done_nodes.load(), node_count), node_count);
  }
  for (std::thread& t : pool) t.join();
  tell(progress, "faces", node_count, node_count);
  return counts;
}

void addCounts(BuildReport& r, const FaceCounts& c) {
  r.faces_nothing_behind += c.nothing_behind;
  r.faces_valid += c.valid;
  r.regions_tested += c.tests.regions_tested;
  r.regions_valid += c.tests.regions_valid;
  r.regions_degenerate += c.tests.regions_degenerate;
  r.pieces_followed += c.tests.pieces_followed;
  r.pieces_abandoned += c.tests.pieces_abandoned;
  r.pieces_open += c.tests.open_pieces;
  r.corner_misses += c.tests.corner_misses;
  r.pieces_closed_even += c.tests.closed_even;
  r.piece_triangles += c.tests.piece_triangles;
}

}  // namespace

Result<Octree> tryBuildOctree(const SceneMesh& mesh, const BuildArgs& args,
                              const ProgressCallback& progress, BuildReport* report) {
  std::string bad_args = validateBuildArgs(args);
  if (!bad_args.empty()) return Status(ErrorCode::InvalidArgument, std::move(bad_args));
  std::string bad_mesh = validateSceneMesh(mesh);
  if (!bad_mesh.empty()) return Status(ErrorCode::BadInput, std::move(bad_mesh));
  const unsigned threads =
      args.threads ? args.threads : std::max(1u, std::thread::hardware_concurrency());
  BuildReport r;
  r.threads = threads;
  const auto start = Clock::now();

  tell(progress, "octree", 0, 1);
  auto t0 = Clock::now();
  Octree octree = detail::subdivide(mesh, args);
  r.octree_ms = msSince(t0);
  tell(progress, "octree", 1, 1);

  tell(progress, "topology", 0, 1);
  t0 = Clock::now();
  const detail::MeshTopology topology(mesh, threads);
  r.topology_ms = msSince(t0);
  tell(progress, "topology", 1, 1);

  tell(progress, "index", 0, 1);
  t0 = Clock::now();
  Result<detail::SegmentIndex> built_index = detail::SegmentIndex::create(mesh, threads);
  if (!built_index) return built_index.status();
  const detail::SegmentIndex& index = *built_index;
  r.index_ms = msSince(t0);
  tell(progress, "index", 1, 1);

  t0 = Clock::now();
  const detail::FaceTester tester(mesh, topology, index, octree.layout(), args.max_piece_triangles);
  for (const FaceCounts& c : testFaces(octree, tester, threads, progress)) addCounts(r, c);
  r.faces_ms = msSince(t0);

  r.nodes = octree.nodes().size();
  for (const OctreeNode& n : octree.nodes()) r.leaves += n.leaf();
  r.faces = r.nodes * kFaces;
  r.temporary_bytes = std::max<std::uint64_t>(
      topology.buildBytes(), topology.memoryBytes() + index.memoryBytes() +
                                 std::uint64_t(threads) * mesh.triangleCount() * 4);
  r.total_ms = msSince(start);
  if (report) *report = r;
  return octree;
}

}  // namespace logrid::ddo
