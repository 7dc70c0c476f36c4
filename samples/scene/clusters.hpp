// Clusters (meshlets): an object's triangles split into small, spatially compact groups
// by meshoptimizer (meshopt_buildMeshlets), each culled on its own box, so that a box
// that shows a corner of a tree no longer draws the whole tree. The library knows
// nothing of them: to logrid a cluster is an object (an ObjectId with a box in the
// hierarchy); prepare.hpp keeps which object each cluster belongs to.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "logrid/types.hpp"

struct meshopt_Meshlet;

namespace logrid::samples {

// How meshoptimizer groups an object's triangles.
enum class ClusterMethod : std::uint8_t {
  // meshopt_buildMeshlets: grows each cluster from its neighbours by position (compact
  // clusters; the default).
  Grow,
  // The triangles sorted by place (meshopt_spatialSortTriangles) and for the vertex
  // cache (meshopt_optimizeVertexCache), then cut in that order (meshopt_
  // buildMeshletsScan): several times cheaper, clusters less compact where an object's
  // triangles are not already in a local order (docs/CLUSTERS.md).
  Scan,
};

struct ClusterOptions {
  // At most this many triangles a cluster: 4 to 512, a multiple of 4 (meshoptimizer's
  // limits); 0: no clusters, whole objects.
  std::uint32_t triangles = 0;
  // At most this many distinct vertices a cluster, 3 to 255; 0: as many as the
  // triangles allow (min(255, triangles + 2)).
  std::uint32_t vertices = 0;
  // meshoptimizer's cone_weight, 0 to 1: how much it trades a cluster's compactness for
  // a narrow normal cone (what back-face cluster culling needs); 0: compactness only.
  float cone_weight = 0;
  // Threads that split the objects among them (buildClustersInPlace), at most 1024; 0:
  // one per hardware thread. The clusters are the same for any number.
  unsigned threads = 0;
  ClusterMethod method = ClusterMethod::Grow;

  bool enabled() const { return triangles != 0; }
  std::uint32_t maxVertices() const;
};

// Empty when usable; else what is wrong and what to use.
std::string validateClusterOptions(const ClusterOptions& options);

// What tells that every triangle of a cluster faces away from an eye (facesAway()):
// meshoptimizer's normal cone (meshopt_computeMeshletBounds), taken again in double over
// the cluster's own triangles and widened, so that a cluster is said to face away only
// where every one of its triangles is seen from behind at a clear angle. With `axis` a
// unit vector, a = the largest angle between it and a triangle's normal, and `apex`
// behind every triangle's plane: an eye e with dot(normalize(apex - e), axis) >=
// sin(a + delta) sees each triangle from behind at delta or more from the apex, and at
// no less than half that from the triangle when |e - apex| >= `reach` (the farthest
// vertex from the apex). delta = 0.01 radians, and a triangle with an angle under 0.01
// (sine) at any corner makes the cone void. This bounds angles only: GL snaps window
// corners to its sub-pixel grid before it takes the area's sign, which can turn a thin
// triangle small on screen to face the eye, so the cone is a first, cheap test, and a
// cluster is skipped only where every triangle, where GL puts it, is a back face by more
// than that (clusterFacesAway, prepare.hpp). cutoff > 1: no eye (a void cone).
struct ClusterCone {
  double apex[3] = {0, 0, 0};
  double axis[3] = {0, 0, 0};
  double cutoff = 2;
  double reach = 0;
};

// Whether every triangle of the cluster faces away from `eye` (same coordinates as the
// positions): then a renderer that culls back faces draws none of it.
bool facesAway(const ClusterCone& cone, const DVec3& eye);

struct Cluster {
  std::uint32_t triangles = 0;  // consecutive in the output, after the previous cluster's
  Aabb box;                     // of its vertices
  ClusterCone cone;
};

// Splits triangles into clusters. Keeps the memory of the last call (meshoptimizer's
// input and output), so that an object's clusters cost its own size, not the scene's.
// One builder per thread: build() changes the builder.
class ClusterBuilder {
 public:
  // `positions`: xyz of every vertex the triangles may use (vertex_count of them).
  ClusterBuilder(const float* positions, std::size_t vertex_count, const ClusterOptions& options);
  ~ClusterBuilder();  // where meshoptimizer's types are known
  ClusterBuilder(const ClusterBuilder&) = delete;
  ClusterBuilder& operator=(const ClusterBuilder&) = delete;

  // The triangles `indices` (index_count, a multiple of 3) in clusters: the same
  // triangles, each with its vertices in their order, written to `out` (index_count of
  // them, which may be `indices` itself) cluster after cluster; returns the clusters in
  // that order. Throws logrid::Error(Runtime) if meshoptimizer loses or adds a triangle.
  std::vector<Cluster> build(const std::uint32_t* indices, std::size_t index_count,
                             std::uint32_t* out);
  // As above, the clustered triangles appended to `out`.
  std::vector<Cluster> build(const std::uint32_t* indices, std::size_t index_count,
                             std::vector<std::uint32_t>& out);

 private:
  // Numbers the object's vertices from 0 in the order they are first used.
  void localize(const std::uint32_t* indices, std::size_t index_count);

  const float* positions_;
  std::size_t vertex_count_;
  ClusterOptions options_;
  std::vector<std::uint32_t> slot_vertex_;  // scene vertex of each hash slot, or kNone
  std::vector<std::uint32_t> slot_local_;   // its local number
  std::vector<std::uint32_t> global_of_;    // local number -> scene vertex
  std::vector<float> local_positions_;
  std::vector<std::uint32_t> local_indices_;
  std::vector<std::uint32_t> sorted_indices_;  // ClusterMethod::Scan
  std::vector<meshopt_Meshlet> meshlets_;
  std::vector<std::uint32_t> meshlet_vertices_;
  std::vector<unsigned char> meshlet_triangles_;
};

// Triangles [first, second) of `indices` (three indices each), one range an object.
using TriangleSpan = std::pair<std::uint32_t, std::uint32_t>;

// Every object's triangles in clusters, on options.threads threads. Object o's
// triangles are order[spans[o].first, spans[o].second) of `indices` (three indices a
// triangle), or without an order (nullptr) that range itself; its clusters' triangles
// (ClusterBuilder::build) are written to out[3 * spans[o].first, 3 * spans[o].second),
// and answer[o] is its clusters. The spans must not overlap; `out` may be `indices`
// when there is no order (each object's clusters then take the place of its triangles).
// The answer and `out` are the same for any number of threads: each object's clusters
// depend on its own triangles only.
std::vector<std::vector<Cluster>> buildClusters(const float* positions, std::size_t vertex_count,
                                                const std::uint32_t* indices,
                                                const std::uint32_t* order,
                                                const std::vector<TriangleSpan>& spans,
                                                std::uint32_t* out, const ClusterOptions& options);

}  // namespace logrid::samples
