#include "logrid/ddo/build.hpp"

#include <atomic>
#include <chrono>
#include <memory>
#include <sstream>
#include <thread>
#include <utility>

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
  auto tell = [&](const char* stage, std::uint64_t done, std::uint64_t total) {
    if (progress) progress({stage, done, total});
  };

  tell("octree", 0, 1);
  auto t0 = Clock::now();
  Octree octree = detail::subdivide(mesh, args);
  r.octree_ms = msSince(t0);
  tell("octree", 1, 1);

  tell("topology", 0, 1);
  t0 = Clock::now();
  const detail::MeshTopology topology(mesh, threads);
  r.topology_ms = msSince(t0);
  tell("topology", 1, 1);

  tell("index", 0, 1);
  t0 = Clock::now();
  Result<detail::SegmentIndex> built_index = detail::SegmentIndex::create(mesh, threads);
  if (!built_index) return built_index.status();
  const detail::SegmentIndex& index = *built_index;
  r.index_ms = msSince(t0);
  tell("index", 1, 1);

  // The faces, node by node, shared among the threads in small batches.
  t0 = Clock::now();
  const detail::FaceTester tester(mesh, topology, index, octree.layout(), args.max_piece_triangles);
  const std::size_t node_count = octree.nodes().size();
  const Aabb scene_bounds = octree.nodes().front().bounds;
  std::atomic<std::size_t> next_node{0}, done_nodes{0};
  std::vector<detail::FaceCounters> counters(threads);
  std::vector<std::uint64_t> nothing_behind(threads, 0), faces_valid(threads, 0);
  // The face tests report no errors (bad input was refused above): a worker always runs
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
            ++nothing_behind[id];
            continue;
          }
          const std::uint64_t bits = tester.validRegions(frame, scratch, counters[id]);
          octree.setMask(std::uint32_t(n), f, bits);
          faces_valid[id] += bits != 0;
        }
      }
      done_nodes.fetch_add(last - first);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < threads; ++i) pool.emplace_back(worker, i);
  tell("faces", 0, node_count);
  while (done_nodes.load() < node_count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    tell("faces", std::min(done_nodes.load(), node_count), node_count);
  }
  for (std::thread& t : pool) t.join();
  tell("faces", node_count, node_count);
  r.faces_ms = msSince(t0);

  r.nodes = node_count;
  for (const OctreeNode& n : octree.nodes()) r.leaves += n.leaf();
  r.faces = node_count * kFaces;
  for (unsigned i = 0; i < threads; ++i) {
    r.faces_nothing_behind += nothing_behind[i];
    r.faces_valid += faces_valid[i];
    r.regions_tested += counters[i].regions_tested;
    r.regions_valid += counters[i].regions_valid;
    r.regions_degenerate += counters[i].regions_degenerate;
    r.pieces_followed += counters[i].pieces_followed;
    r.pieces_abandoned += counters[i].pieces_abandoned;
    r.pieces_open += counters[i].open_pieces;
    r.corner_misses += counters[i].corner_misses;
    r.pieces_closed_even += counters[i].closed_even;
    r.piece_triangles += counters[i].piece_triangles;
  }
  r.temporary_bytes = std::max<std::uint64_t>(
      topology.buildBytes(), topology.memoryBytes() + index.memoryBytes() +
                                 std::uint64_t(threads) * mesh.triangleCount() * 4);
  r.total_ms = msSince(start);
  if (report) *report = r;
  return octree;
}

}  // namespace logrid::ddo
