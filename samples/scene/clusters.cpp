#include "scene/clusters.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <exception>
#include <limits>
#include <thread>

#include "logrid/error.hpp"
#include "scene/scene.hpp"

namespace logrid::samples {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kMaxTriangles = 512;  // meshoptimizer's limits
constexpr std::uint32_t kMaxVertices = 255;

constexpr double kDelta = 0.01;      // radians: the least angle a skipped triangle is seen at
constexpr double kLeastSine = 0.01;  // of the angle between a triangle's edges

struct D3 {
  double x, y, z;
};
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
D3 at(const float* positions, std::uint32_t v) {
  const float* p = positions + std::size_t(v) * 3;
  return {p[0], p[1], p[2]};
}

// meshoptimizer's axis, the rest of the cone (clusters.hpp, ClusterCone) in double over
// the triangles (scene vertex numbers); a void cone where a triangle is too thin or not
// within 90 degrees less delta of the axis.
ClusterCone checkedCone(const float* meshopt_axis, const Aabb& box, const std::uint32_t* indices,
                        std::size_t triangles, const float* positions) {
  const ClusterCone none;
  D3 axis{meshopt_axis[0], meshopt_axis[1], meshopt_axis[2]};
  const double length = std::sqrt(dot(axis, axis));
  if (!(length > 0)) return none;
  axis = {axis.x / length, axis.y / length, axis.z / length};
  const D3 centre{0.5 * (box.min.x + box.max.x), 0.5 * (box.min.y + box.max.y),
                  0.5 * (box.min.z + box.max.z)};
  double least_cos = 1, apex_t = 0;
  for (std::size_t t = 0; t < triangles; ++t) {
    const D3 p0 = at(positions, indices[t * 3]);
    const D3 e1 = at(positions, indices[t * 3 + 1]) - p0,
             e2 = at(positions, indices[t * 3 + 2]) - p0;
    const D3 n = cross(e1, e2);
    const double area2 = std::sqrt(dot(n, n));
    // The sine at each corner: twice the area over the product of the edges that meet there.
    const D3 e3 = e2 - e1;
    const double l1 = dot(e1, e1), l2 = dot(e2, e2), l3 = dot(e3, e3);
    if (!(area2 > kLeastSine * std::sqrt(std::max({l1 * l2, l1 * l3, l2 * l3})))) return none;
    const D3 unit{n.x / area2, n.y / area2, n.z / area2};
    const double cos_axis = dot(unit, axis);
    if (!(cos_axis > 0)) return none;
    least_cos = std::min(least_cos, cos_axis);
    // The apex on the axis behind this triangle's plane: centre - t axis with
    // dot(centre - t axis - p0, n) <= 0.
    apex_t = std::max(apex_t, dot(centre - p0, unit) / cos_axis);
  }
  const double spread = std::acos(std::min(1.0, least_cos)) + kDelta;
  if (!(spread < M_PI / 2)) return none;
  ClusterCone cone;
  cone.axis[0] = axis.x, cone.axis[1] = axis.y, cone.axis[2] = axis.z;
  // A hair further back, so that rounding the products above leaves it behind every plane.
  const D3 diagonal{box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z};
  apex_t = apex_t * (1 + 1e-9) + 1e-9 * std::sqrt(dot(diagonal, diagonal));
  const D3 apex{centre.x - axis.x * apex_t, centre.y - axis.y * apex_t, centre.z - axis.z * apex_t};
  cone.apex[0] = apex.x, cone.apex[1] = apex.y, cone.apex[2] = apex.z;
  cone.cutoff = std::sin(spread);
  for (std::size_t k = 0; k < triangles * 3; ++k) {
    const D3 d = at(positions, indices[k]) - apex;
    cone.reach = std::max(cone.reach, std::sqrt(dot(d, d)));
  }
  return cone;
}

}  // namespace

bool facesAway(const ClusterCone& cone, const DVec3& eye) {
  const double d[3] = {cone.apex[0] - eye.x, cone.apex[1] - eye.y, cone.apex[2] - eye.z};
  const double distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(distance >= cone.reach) || !(distance > 0)) return false;
  return d[0] * cone.axis[0] + d[1] * cone.axis[1] + d[2] * cone.axis[2] >= cone.cutoff * distance;
}

std::uint32_t ClusterOptions::maxVertices() const {
  return vertices ? vertices : std::min(kMaxVertices, triangles + 2);
}

std::string validateClusterOptions(const ClusterOptions& o) {
  if (!o.enabled()) return {};
  if (o.triangles < 4 || o.triangles > kMaxTriangles || o.triangles % 4 != 0) {
    return "cluster size " + std::to_string(o.triangles) +
           " triangles is invalid; use a multiple of 4 from 4 to 512, or 0 for whole objects";
  }
  if (o.vertices != 0 && (o.vertices < 3 || o.vertices > kMaxVertices)) {
    return "cluster vertex limit " + std::to_string(o.vertices) +
           " is invalid; use 3 to 255, or 0 to let the triangle limit decide";
  }
  if (!(o.cone_weight >= 0 && o.cone_weight <= 1)) {
    return "cluster cone weight " + std::to_string(o.cone_weight) + " is invalid; use 0 to 1";
  }
  if (o.threads > 1024) {
    return "cluster threads " + std::to_string(o.threads) +
           " is out of range; use 0 (one per hardware thread) up to 1024";
  }
  return {};
}

ClusterBuilder::ClusterBuilder(const float* positions, std::size_t vertex_count,
                               const ClusterOptions& options)
    : positions_(positions), vertex_count_(vertex_count), options_(options) {}

ClusterBuilder::~ClusterBuilder() = default;

void ClusterBuilder::localize(const std::uint32_t* indices, std::size_t index_count) {
  // A hash table of at least twice the object's indices (so at most half full): the
  // object's size, where an array over the scene's vertices would be the scene's, for
  // every thread.
  std::size_t slots = 16;
  int bits = 4;
  while (slots < 2 * index_count) slots *= 2, ++bits;
  if (slot_vertex_.size() < slots) {
    slot_vertex_.assign(slots, kNone);
    slot_local_.resize(slots);
  }
  const std::size_t mask = slots - 1;
  const auto slotOf = [&](std::uint32_t v) {
    // Fibonacci hashing: the top bits of v times 2^64 / golden ratio.
    std::size_t s = std::size_t((std::uint64_t(v) * 0x9E3779B97F4A7C15ull) >> (64 - bits));
    while (slot_vertex_[s] != kNone && slot_vertex_[s] != v) s = (s + 1) & mask;
    return s;
  };
  global_of_.clear();
  local_positions_.clear();
  local_indices_.resize(index_count);
  for (std::size_t i = 0; i < index_count; ++i) {
    const std::uint32_t v = indices[i];
    assert(v < vertex_count_ && "ClusterBuilder::build: an index past the vertices");
    const std::size_t s = slotOf(v);
    if (slot_vertex_[s] == kNone) {
      slot_vertex_[s] = v;
      slot_local_[s] = static_cast<std::uint32_t>(global_of_.size());
      global_of_.push_back(v);
      local_positions_.insert(local_positions_.end(), positions_ + std::size_t(v) * 3,
                              positions_ + std::size_t(v) * 3 + 3);
    }
    local_indices_[i] = slot_local_[s];
  }
  // Emptied for the next object, the last in first: then each one's probe still passes
  // over the slots of those before it, as when it was put in.
  for (std::size_t i = global_of_.size(); i-- > 0;) slot_vertex_[slotOf(global_of_[i])] = kNone;
}

std::vector<Cluster> ClusterBuilder::build(const std::uint32_t* indices, std::size_t index_count,
                                           std::uint32_t* out) {
  // The object's own vertices, numbered from 0, so that meshoptimizer's work (and its
  // per-vertex arrays) is the object's size. Read before `out` is written: it may be
  // `indices`.
  localize(indices, index_count);

  const std::size_t max_vertices = options_.maxVertices();
  const std::size_t max_triangles = options_.triangles;
  meshlets_.resize(meshopt_buildMeshletsBound(index_count, max_vertices, max_triangles));
  meshlet_vertices_.resize(meshlets_.size() * max_vertices);
  meshlet_triangles_.resize(meshlets_.size() * max_triangles * 3);
  const std::size_t vertex_count = global_of_.size();
  std::size_t made = 0;
  if (options_.method == ClusterMethod::Scan) {
    // Both keep each triangle's vertices in their order.
    sorted_indices_.resize(index_count);
    meshopt_spatialSortTriangles(sorted_indices_.data(), local_indices_.data(), index_count,
                                 local_positions_.data(), vertex_count, 3 * sizeof(float));
    meshopt_optimizeVertexCache(local_indices_.data(), sorted_indices_.data(), index_count,
                                vertex_count);
    made = meshopt_buildMeshletsScan(meshlets_.data(), meshlet_vertices_.data(),
                                     meshlet_triangles_.data(), local_indices_.data(), index_count,
                                     vertex_count, max_vertices, max_triangles);
  } else {
    made = meshopt_buildMeshlets(meshlets_.data(), meshlet_vertices_.data(),
                                 meshlet_triangles_.data(), local_indices_.data(), index_count,
                                 local_positions_.data(), vertex_count, 3 * sizeof(float),
                                 max_vertices, max_triangles, options_.cone_weight);
  }

  // Checked before `out` is written (it may be `indices`).
  std::size_t returned = 0;
  for (std::size_t k = 0; k < made; ++k) returned += meshlets_[k].triangle_count;
  if (returned * 3 != index_count) {
    throw Error(ErrorCode::Runtime, "clusters: meshoptimizer returned " + std::to_string(returned) +
                                        " triangles for " + std::to_string(index_count / 3) +
                                        "; build with whole objects (--cluster 0)");
  }
  std::vector<Cluster> clusters;
  clusters.reserve(made);
  std::size_t written = 0;  // triangles
  for (std::size_t k = 0; k < made; ++k) {
    const meshopt_Meshlet& m = meshlets_[k];
    const std::uint32_t* verts = &meshlet_vertices_[m.vertex_offset];
    const unsigned char* tris = &meshlet_triangles_[m.triangle_offset];
    Cluster c;
    c.triangles = m.triangle_count;
    c.box = emptyBox();
    std::uint32_t* written_indices = out + written * 3;
    for (std::size_t i = 0; i < std::size_t(m.triangle_count) * 3; ++i) {
      const std::uint32_t local = verts[tris[i]];
      written_indices[i] = global_of_[local];
      growBox(c.box, &local_positions_[std::size_t(local) * 3]);
    }
    const meshopt_Bounds b = meshopt_computeMeshletBounds(
        verts, tris, m.triangle_count, local_positions_.data(), vertex_count, 3 * sizeof(float));
    if (b.cone_cutoff < 1) {
      c.cone = checkedCone(b.cone_axis, c.box, written_indices, m.triangle_count, positions_);
    }
    written += m.triangle_count;
    clusters.push_back(c);
  }
  return clusters;
}

std::vector<Cluster> ClusterBuilder::build(const std::uint32_t* indices, std::size_t index_count,
                                           std::vector<std::uint32_t>& out) {
  const std::size_t at = out.size();
  out.resize(at + index_count);
  return build(indices, index_count, out.data() + at);
}

std::vector<std::vector<Cluster>> buildClusters(const float* positions, std::size_t vertex_count,
                                                const std::uint32_t* indices,
                                                const std::uint32_t* order,
                                                const std::vector<TriangleSpan>& spans,
                                                std::uint32_t* out, const ClusterOptions& options) {
  std::vector<std::vector<Cluster>> clusters(spans.size());
  const unsigned wanted =
      options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const auto threads = static_cast<unsigned>(std::min<std::size_t>(wanted, spans.size()));
  // Objects taken a few at a time from a shared counter: the city's chunks cost alike,
  // a file's objects need not. Which thread builds an object changes nothing in it.
  constexpr std::size_t kObjectsATake = 8;
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> failed(threads);
  const auto work = [&](unsigned t) {
    try {
      ClusterBuilder builder(positions, vertex_count, options);
      std::vector<std::uint32_t> gathered;
      for (;;) {
        const std::size_t first = next.fetch_add(kObjectsATake);
        if (first >= spans.size()) return;
        for (std::size_t o = first; o < std::min(spans.size(), first + kObjectsATake); ++o) {
          const auto [begin, end] = spans[o];
          const std::uint32_t* object = indices + std::size_t(begin) * 3;
          if (order) {
            gathered.clear();
            for (std::size_t i = begin; i < end; ++i) {
              const std::uint32_t* triangle = indices + std::size_t(order[i]) * 3;
              gathered.insert(gathered.end(), triangle, triangle + 3);
            }
            object = gathered.data();
          }
          clusters[o] =
              builder.build(object, (std::size_t(end) - begin) * 3, out + std::size_t(begin) * 3);
        }
      }
    } catch (...) {
      failed[t] = std::current_exception();
      next = spans.size();  // the others stop at their next take
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  if (threads > 0) work(0);
  for (std::thread& thread : pool) thread.join();
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
  return clusters;
}

}  // namespace logrid::samples
