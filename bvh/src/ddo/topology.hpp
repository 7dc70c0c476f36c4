// Which triangles share an edge, by exact position (DDO §3.2's "neighbor polygon along
// edge e"). Internal to the preprocessing.
//
// Vertices are welded by their float position (bit for bit, -0 and +0 alike); a
// triangle whose welded corners repeat is degenerate and takes no part. Each half-edge
// h = 3 * t + k (from corner k to corner k + 1 of triangle t) is linked into a cycle of
// every half-edge with the same two welded end vertices, in either direction: next(h)
// walks the cycle, which is h alone for an edge no other triangle shares.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/ddo/mesh.hpp"

namespace logrid::ddo::detail {

class MeshTopology {
 public:
  // Uses up to `threads` threads (>= 1).
  MeshTopology(const SceneMesh& mesh, unsigned threads);

  std::uint32_t next(std::uint32_t half_edge) const { return next_[half_edge]; }
  bool degenerate(std::uint32_t triangle) const {
    return (degenerate_[triangle >> 6] >> (triangle & 63)) & 1u;
  }
  std::size_t memoryBytes() const { return next_.capacity() * 4 + degenerate_.capacity() * 8; }
  // The largest memory held at once while building (the welding table and the
  // vertex-to-triangle lists, freed before the constructor returns).
  std::size_t buildBytes() const { return build_bytes_; }

 private:
  std::vector<std::uint32_t> next_;
  std::vector<std::uint64_t> degenerate_;
  std::size_t build_bytes_ = 0;
};

}  // namespace logrid::ddo::detail
