// The scene as the directional discretized occluders (DDO, Bernardini, El-Sana and
// Klosowski) see it: triangles, and the renderer's objects as runs of triangles.
//
// Positions are xyz floats per vertex; indices three per triangle. Object o is the run
// of triangles [object_first[o], object_first[o + 1]); object_first starts at 0 and ends
// at the triangle count. Which objects an octree leaf holds is what the run time hands
// to the renderer (a leaf's triangles are drawn by drawing their objects).
//
// Triangles need not share vertices by index: two triangles are neighbours when an edge
// of one has exactly the same two end positions (bit for bit, after float conversion) as
// an edge of the other — which is what makes a rasteriser watertight along that edge.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace logrid::ddo {

struct SceneMesh {
  const std::vector<float>* positions = nullptr;
  const std::vector<std::uint32_t>* indices = nullptr;
  const std::vector<std::uint32_t>* object_first = nullptr;

  SceneMesh() = default;
  SceneMesh(const std::vector<float>& p, const std::vector<std::uint32_t>& i,
            const std::vector<std::uint32_t>& o)
      : positions(&p), indices(&i), object_first(&o) {}

  std::size_t vertexCount() const { return positions->size() / 3; }
  std::size_t triangleCount() const { return indices->size() / 3; }
  std::size_t objectCount() const { return object_first->empty() ? 0 : object_first->size() - 1; }
  const float* vertex(std::uint32_t v) const { return positions->data() + std::size_t(v) * 3; }
  std::uint32_t corner(std::size_t triangle, int k) const {
    return (*indices)[triangle * 3 + std::size_t(k)];
  }
};

// Returns an empty string if the mesh is usable, else a message naming the first
// problem: arrays not in threes, an index out of range, a non-finite coordinate, object
// runs that do not start at 0, go backwards or do not end at the triangle count, more
// than 2^32 - 2 triangles, or no triangle at all.
std::string validateSceneMesh(const SceneMesh& mesh);

// A 64-bit checksum of the positions, indices and object runs (what a DDO file was built
// from; ddo/file.hpp refuses a file whose checksum differs from the scene's).
std::uint64_t sceneChecksum(const SceneMesh& mesh);

}  // namespace logrid::ddo
