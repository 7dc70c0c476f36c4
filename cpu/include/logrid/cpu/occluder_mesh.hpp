// The triangles a CPU occlusion buffer (occlusion_buffer.hpp) rasterises for each object
// the application draws: the object's own mesh, or a simpler occluder mesh the
// application supplies. Built once, at load time; read-only afterwards, so one set can
// serve several buffers and threads.
//
// Positions are in the coordinates the Camera's view_projection takes (the renderer's
// "local" coordinates, camera.hpp), three indices per triangle, one contiguous run of
// triangles per object. Building welds, per object, the vertices whose positions are
// bit-identical (a GL vertex shader maps them to the same clip position, so GL rasterises
// the edges between them without cracks) and records which triangles share an edge:
// the coverage rule of the buffer relies on it (occlusion_buffer.hpp, "Coverage").
//
// Two kinds of object:
//   * its own mesh: the triangles the application draws for it, as they are;
//   * a model inside it (`inside_solid`): triangles that lie inside closed, convex
//     solids formed by the object's drawn triangles (a crown inside the crown mesh),
//     plus, optionally, drawn triangles as they are (a trunk). Such a model hides what
//     the real object hides only while the eye is outside the object and its box lies
//     wholly beyond the near plane; otherwise the buffer uses the object's `fallback`
//     (usually its own mesh) or nothing. The solid may also be bounded by the
//     triangles of several objects (a building cut into chunks), each of which is drawn
//     unless culled; then `box` must contain them all (the argument that this holds:
//     samples/scene/scene.hpp, OccluderSolid).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid::cpu {

inline constexpr std::uint32_t kNoOccluder = 0xFFFFFFFFu;
inline constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu;

struct OccluderObject {
  std::uint32_t first_vertex = 0;  // welded vertices of the object: [first, first + count)
  std::uint32_t vertex_count = 0;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  // The box of the geometry the application draws for this object (for a model, the
  // box of the real geometry it stands for, not the model's); every vertex of the
  // object lies inside it.
  Aabb box;
  bool inside_solid = false;
  std::uint32_t fallback = kNoOccluder;  // index of another object in the set, or none
};

class OccluderMeshes {
 public:
  // Both forms of each (logrid/error.hpp).
  // Appends an object: `vertex_count` positions (xyz) and `index_count` indices into
  // them (three per triangle). Returns its index, or an error (InvalidArgument) naming
  // the object and the value for an index count that is not a multiple of 3, an index out
  // of range, a non-finite position, a vertex outside `box`, or more than 2^32 - 1
  // triangles in all; a refused object leaves the set as it was.
  // `box`: as OccluderObject::box; pass nullptr to use the bounds of the positions.
  Result<std::uint32_t> tryAddObject(const float* positions, std::size_t vertex_count,
                                     const std::uint32_t* indices, std::size_t index_count,
                                     const Aabb* box = nullptr);
  std::uint32_t addObject(const float* positions, std::size_t vertex_count,
                          const std::uint32_t* indices, std::size_t index_count,
                          const Aabb* box = nullptr);
  // Marks object `id` as a model inside its real geometry, with an optional fallback; an
  // error (InvalidArgument) for an unknown id or fallback.
  Status trySetInsideSolid(std::uint32_t id, std::uint32_t fallback);
  void setInsideSolid(std::uint32_t id, std::uint32_t fallback);

  std::size_t objectCount() const { return objects_.size(); }
  const OccluderObject& object(std::uint32_t id) const { return objects_[id]; }
  std::size_t triangleCount() const { return indices_.size() / 3; }
  std::size_t vertexCount() const { return positions_.size() / 3; }
  std::size_t memoryBytes() const;

  // Welded positions (xyz), indices into them (three per triangle), and per triangle
  // edge the next edge between the same two welded vertices: adjacency()[3 t + k]
  // describes edge k of triangle t, the edge opposite its corner k, and holds 3 t' + k'
  // for the next triangle t' of the same object with such an edge k' (following it
  // visits every such edge and returns), or kNoNeighbour (an edge of one triangle, or a
  // degenerate triangle). Two triangles on an edge point at each other.
  const std::vector<float>& positions() const { return positions_; }
  const std::vector<std::uint32_t>& indices() const { return indices_; }
  const std::vector<std::uint32_t>& adjacency() const { return adjacency_; }
  // Per triangle: 0 unless it belongs to a closed, consistently wound surface (every edge
  // of its connected part shared by exactly two of its triangles in opposite directions
  // and a nonzero volume); then 1 if the surface is wound counter-clockwise seen from
  // outside, 2 if clockwise. The triangles of such a surface that face the eye cover all
  // that it covers, so the buffer may leave the others out (occlusion_buffer.hpp).
  const std::vector<std::uint8_t>& closed() const { return closed_; }

 private:
  void markClosedSurfaces(std::size_t first_triangle, std::size_t end_triangle);

  std::vector<float> positions_;
  std::vector<std::uint32_t> indices_;
  std::vector<std::uint32_t> adjacency_;
  std::vector<std::uint8_t> closed_;
  std::vector<OccluderObject> objects_;
};

#if LOGRID_HAS_EXCEPTIONS
inline std::uint32_t OccluderMeshes::addObject(const float* positions, std::size_t vertex_count,
                                               const std::uint32_t* indices,
                                               std::size_t index_count, const Aabb* box) {
  return orThrow(tryAddObject(positions, vertex_count, indices, index_count, box));
}
inline void OccluderMeshes::setInsideSolid(std::uint32_t id, std::uint32_t fallback) {
  orThrow(trySetInsideSolid(id, fallback));
}
#endif

}  // namespace logrid::cpu
