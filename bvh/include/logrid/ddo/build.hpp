// Building the DDO octree and its occluder bitmasks (DDO §3.1, §3.2).
//
// The validity test of a face f for a region r (§3.2) asks whether "a connected
// collection of polygons, in the geometry within and nearby the node, intersects every
// possible ray" from the region to the face, i.e. cuts the viewspace frustum P(f, r)
// (regions.hpp) into a part holding the face and a part holding the viewpoints. The
// paper grows such a collection breadth first from a seed polygon across shared edges,
// gives up on a polygon that touches the face or the clipping plane or an edge inside the
// frustum without a neighbour, and finally decides whether the boundary edges, projected
// along the frustum's axis, contain the face's centre. That last step is a heuristic
// (a projected boundary may wind around the centre without the surface cutting every
// ray); here it is replaced by an exact criterion with the same ingredients:
//
//   * Seeds: the triangles crossed by one segment from the top cap of P to the face (the
//     frustum's axis, moved slightly when it grazes an edge or vertex).
//   * A piece: the triangles reached from a seed across shared edges that meet P. Only
//     triangles strictly between the face plane and the clipping plane take part (the
//     paper's "does not intersect the face or the clipping plane", made stricter).
//   * Closed: every edge of the piece that meets P is shared by an even number of the
//     piece's triangles (no free edge inside P).
//   * Cuts: the segment crosses the piece an odd number of times, each crossing through a
//     triangle's interior.
// A closed piece is a surface whose boundary lies outside P, so any two paths through P
// from the top cap to the face cross it the same number of times modulo 2; one path
// crossing it an odd number of times means every path crosses it: the face is hidden
// from every viewpoint of the region. Shared edges are exact (same end positions), which
// is also what keeps a rasteriser from leaving cracks along them. A closed wall of two
// sheets splits into two pieces inside P, each of which cuts on its own.
//
// Work is bounded: a piece larger than max_piece_triangles is abandoned (the region is
// then not marked valid, which keeps culling conservative).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "logrid/ddo/mesh.hpp"
#include "logrid/ddo/octree.hpp"
#include "logrid/error.hpp"

namespace logrid::ddo {

struct BuildArgs {
  std::uint32_t leaf_triangles = 2048;           // a node with more triangles is subdivided
  std::uint32_t regions = 64;                    // 32 or 64 view-direction regions per face
  std::uint32_t max_depth = 16;                  // levels below the root at most
  std::uint32_t threads = 0;                     // worker threads (0: one per hardware thread)
  std::uint32_t max_piece_triangles = 1u << 16;  // work bound per region (see above)
};

// Returns an empty string if the arguments are usable, else a message naming the field.
std::string validateBuildArgs(const BuildArgs& args);

struct BuildProgress {
  const char* stage = "";  // "octree", "topology", "index", "faces"
  std::uint64_t done = 0;
  std::uint64_t total = 0;
};
// Called from the thread that called buildOctree(), a few times a second at most.
using ProgressCallback = std::function<void(const BuildProgress&)>;

// What a build did and how long each stage took (wall time).
struct BuildReport {
  double octree_ms = 0;    // subdivision, bounds and leaf object lists
  double topology_ms = 0;  // welding vertices and linking shared edges
  double index_ms = 0;     // the segment index over all triangles
  double faces_ms = 0;     // the validity tests
  double total_ms = 0;
  std::uint64_t nodes = 0;
  std::uint64_t leaves = 0;
  std::uint64_t faces = 0;                 // nodes * 6
  std::uint64_t faces_nothing_behind = 0;  // skipped: no geometry beyond the face's plane
  std::uint64_t faces_valid = 0;           // faces with at least one valid region
  std::uint64_t regions_tested = 0;
  std::uint64_t regions_valid = 0;
  std::uint64_t regions_degenerate = 0;  // every test segment grazed an edge: not valid
  std::uint64_t pieces_followed = 0;
  std::uint64_t pieces_abandoned = 0;    // larger than max_piece_triangles
  std::uint64_t corner_misses = 0;       // ruled out: an edge of the frustum crosses nothing
  std::uint64_t pieces_open = 0;         // with a free edge inside the frustum
  std::uint64_t pieces_closed_even = 0;  // closed, but crossed an even number of times
  std::uint64_t piece_triangles = 0;     // triangles the searches of pieces visited
  std::uint64_t temporary_bytes = 0;     // largest memory the build held besides the result
  std::uint32_t threads = 0;
};

// Builds the octree and every face's bitmask. In both forms (logrid/error.hpp):
// tryBuildOctree() returns the octree or the error, buildOctree() throws the error as
// logrid::Error. Fails with ErrorCode::InvalidArgument for arguments validateBuildArgs()
// refuses and ErrorCode::BadInput for a mesh validateSceneMesh() refuses. `progress` must
// not throw.
Result<Octree> tryBuildOctree(const SceneMesh& mesh, const BuildArgs& args = {},
                              const ProgressCallback& progress = {}, BuildReport* report = nullptr);
Octree buildOctree(const SceneMesh& mesh, const BuildArgs& args = {},
                   const ProgressCallback& progress = {}, BuildReport* report = nullptr);

#if LOGRID_HAS_EXCEPTIONS
inline Octree buildOctree(const SceneMesh& mesh, const BuildArgs& args,
                          const ProgressCallback& progress, BuildReport* report) {
  return logrid::orThrow(tryBuildOctree(mesh, args, progress, report));
}
#endif

}  // namespace logrid::ddo
