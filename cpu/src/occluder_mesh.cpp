#include "logrid/cpu/occluder_mesh.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>

#include "logrid/error.hpp"

namespace logrid::cpu {
namespace {

struct PositionKey {
  std::uint32_t bits[3];
  bool operator==(const PositionKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};

struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = k.bits[0] * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k.bits[1] * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k.bits[2] * 0x94D049BB133111EBull;
    return std::size_t(h ^ (h >> 32));
  }
};

Status fail(std::size_t object, const std::string& what) {
  std::ostringstream out;
  out << "OccluderMeshes::addObject: object " << object << ": " << what;
  return Status(ErrorCode::InvalidArgument, out.str());
}

}  // namespace

Result<std::uint32_t> OccluderMeshes::tryAddObject(const float* positions, std::size_t vertex_count,
                                                   const std::uint32_t* indices,
                                                   std::size_t index_count, const Aabb* box) {
  const std::size_t id = objects_.size();
  if (index_count % 3 != 0) {
    return fail(id, "index count " + std::to_string(index_count) + " is not a multiple of 3");
  }
  if (triangleCount() + index_count / 3 > std::numeric_limits<std::uint32_t>::max() / 3 ||
      vertexCount() + vertex_count > std::numeric_limits<std::uint32_t>::max()) {
    return fail(id, "the set would hold more than 2^32 / 3 triangles or 2^32 vertices; split it");
  }
  for (std::size_t i = 0; i < index_count; ++i) {
    if (indices[i] >= vertex_count) {
      return fail(id, "index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                          ", beyond the " + std::to_string(vertex_count) + " vertices");
    }
  }
  // A refused object leaves the set as it was: the vertices welded so far go again.
  const std::size_t vertices_before = vertexCount();
  const auto refuse = [&](const std::string& what) {
    positions_.resize(vertices_before * 3);
    return fail(id, what);
  };
  OccluderObject o;
  o.first_vertex = std::uint32_t(vertexCount());
  o.first_triangle = std::uint32_t(triangleCount());
  o.triangle_count = std::uint32_t(index_count / 3);
  Aabb bounds{{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
               std::numeric_limits<float>::infinity()},
              {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
               -std::numeric_limits<float>::infinity()}};

  // Weld the vertices the triangles use: bit-identical positions become one vertex.
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> welded;
  std::vector<std::uint32_t> remap(vertex_count, kNoNeighbour);
  for (std::size_t i = 0; i < index_count; ++i) {
    const std::uint32_t v = indices[i];
    if (remap[v] != kNoNeighbour) continue;
    const float* p = positions + std::size_t(v) * 3;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream out;
      out << "vertex " << v << " is (" << p[0] << ", " << p[1] << ", " << p[2]
          << "); positions must be finite";
      return refuse(out.str());
    }
    PositionKey key;
    std::memcpy(key.bits, p, sizeof key.bits);
    // +0 and -0 are the same position to a vertex shader.
    for (std::uint32_t& b : key.bits) b = b == 0x80000000u ? 0u : b;
    const auto [it, inserted] = welded.emplace(key, std::uint32_t(vertexCount() - o.first_vertex));
    if (inserted) {
      positions_.insert(positions_.end(), p, p + 3);
      bounds.min = {std::min(bounds.min.x, p[0]), std::min(bounds.min.y, p[1]),
                    std::min(bounds.min.z, p[2])};
      bounds.max = {std::max(bounds.max.x, p[0]), std::max(bounds.max.y, p[1]),
                    std::max(bounds.max.z, p[2])};
    }
    remap[v] = o.first_vertex + it->second;
  }
  o.vertex_count = std::uint32_t(vertexCount()) - o.first_vertex;
  o.box = box ? *box : bounds;
  if (box && o.vertex_count > 0 &&
      (bounds.min.x < box->min.x || bounds.min.y < box->min.y || bounds.min.z < box->min.z ||
       bounds.max.x > box->max.x || bounds.max.y > box->max.y || bounds.max.z > box->max.z)) {
    return refuse("a vertex lies outside the box given for the object");
  }

  // Edges shared by two or more triangles of this object form a ring through every use.
  const std::size_t first_index = indices_.size();
  for (std::size_t i = 0; i < index_count; ++i) indices_.push_back(remap[indices[i]]);
  adjacency_.resize(indices_.size(), kNoNeighbour);
  std::unordered_map<std::uint64_t, std::uint32_t> last_use;  // edge -> 3 t + k seen last
  last_use.reserve(index_count);
  const std::size_t t0 = first_index / 3, t1 = indices_.size() / 3;
  for (std::size_t t = t0; t < t1; ++t) {
    const std::uint32_t* v = &indices_[t * 3];
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // degenerate
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      const std::uint64_t key = a < b ? std::uint64_t(a) << 32 | b : std::uint64_t(b) << 32 | a;
      const std::uint32_t self = std::uint32_t(t * 3 + std::size_t(k));
      const auto [it, inserted] = last_use.emplace(key, self);
      if (inserted) continue;
      // Insert `self` into the ring after the previous use.
      const std::uint32_t previous = it->second;
      const std::uint32_t next = adjacency_[previous];
      adjacency_[previous] = self;
      adjacency_[self] = next == kNoNeighbour ? previous : next;
      it->second = self;
    }
  }
  markClosedSurfaces(t0, t1);
  objects_.push_back(o);
  return std::uint32_t(id);
}

void OccluderMeshes::markClosedSurfaces(std::size_t t0, std::size_t t1) {
  // Union-find over the triangles joined by well-behaved edges (exactly two uses, in
  // opposite directions); any other edge, or a degenerate triangle, opens its part.
  const std::size_t n = t1 - t0;
  std::vector<std::uint32_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = std::uint32_t(i);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::uint8_t> open(n, 0);
  for (std::size_t t = t0; t < t1; ++t) {
    const std::uint32_t* v = &indices_[t * 3];
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      open[t - t0] = 1;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t self = std::uint32_t(t * 3 + std::size_t(k));
      const std::uint32_t other = adjacency_[self];
      const bool pair = other != kNoNeighbour && adjacency_[other] == self;
      const std::uint32_t* w = pair ? &indices_[std::size_t(other / 3) * 3] : nullptr;
      const int ko = int(other % 3);
      if (!pair || w[(ko + 1) % 3] != v[(k + 2) % 3] || w[(ko + 2) % 3] != v[(k + 1) % 3]) {
        open[t - t0] = 1;
        continue;
      }
      const std::uint32_t a = find(std::uint32_t(t - t0)), b = find(other / 3 - std::uint32_t(t0));
      if (a != b) parent[a] = b;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (open[i]) open[find(std::uint32_t(i))] = 1;
  }
  // Which way each closed part is wound: the sign of its volume (sum of the tetrahedra
  // of its triangles with one of its points), positive when counter-clockwise seen from
  // outside.
  std::vector<double> volume(n, 0.0);
  std::vector<std::uint32_t> apex(n, kNoNeighbour);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t root = find(std::uint32_t(i));
    if (open[root]) continue;
    const std::uint32_t* v = &indices_[(t0 + i) * 3];
    if (apex[root] == kNoNeighbour) apex[root] = v[0];
    const float* o = &positions_[std::size_t(apex[root]) * 3];
    double p[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c)
        p[k][c] = double(positions_[std::size_t(v[k]) * 3 + std::size_t(c)]) - o[c];
    }
    volume[root] += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                    p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                    p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
  }
  closed_.resize(t1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t root = find(std::uint32_t(i));
    closed_[t0 + i] = open[root] || volume[root] == 0 ? 0 : volume[root] > 0 ? 1 : 2;
  }
}

Status OccluderMeshes::trySetInsideSolid(std::uint32_t id, std::uint32_t fallback) {
  if (id >= objects_.size() || (fallback != kNoOccluder && fallback >= objects_.size()) ||
      fallback == id) {
    std::ostringstream out;
    out << "OccluderMeshes::setInsideSolid: object " << id << " with fallback " << fallback
        << " is invalid; the set has " << objects_.size()
        << " objects and an object cannot be its own fallback";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  objects_[id].inside_solid = true;
  objects_[id].fallback = fallback;
  return {};
}

std::size_t OccluderMeshes::memoryBytes() const {
  return positions_.capacity() * sizeof(float) +
         (indices_.capacity() + adjacency_.capacity()) * sizeof(std::uint32_t) +
         closed_.capacity() + objects_.capacity() * sizeof(OccluderObject);
}

}  // namespace logrid::cpu
