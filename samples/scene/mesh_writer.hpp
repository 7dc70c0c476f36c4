// Appends geometry to a Scene: vertices with a colour, triangles and quads, and the
// object bookkeeping (an object is a contiguous run of indices).
#pragma once

#include <cstdint>

#include "scene/scene.hpp"

namespace logrid::samples {

constexpr std::uint32_t rgba(int r, int g, int b) {
  return std::uint32_t(r) | std::uint32_t(g) << 8 | std::uint32_t(b) << 16 | 0xFF000000u;
}

class MeshWriter {
 public:
  explicit MeshWriter(Scene& scene) : scene_(scene) {}

  std::uint32_t vertex(float x, float y, float z, std::uint32_t color) {
    scene_.positions.insert(scene_.positions.end(), {x, y, z});
    scene_.vertex_colors.push_back(color);
    return std::uint32_t(scene_.vertex_colors.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    scene_.indices.insert(scene_.indices.end(), {a, b, c});
  }
  // a, b, c, d in order around the quad.
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  // A quad from four corner positions (x, y, z each), one colour.
  void quad(const float* a, const float* b, const float* c, const float* d, std::uint32_t color) {
    quad(vertex(a[0], a[1], a[2], color), vertex(b[0], b[1], b[2], color),
         vertex(c[0], c[1], c[2], color), vertex(d[0], d[1], d[2], color));
  }

  void beginObject() { object_first_ = std::uint32_t(scene_.indices.size()); }
  void endObject(std::uint32_t color = 0xFFFFFFFFu) {
    SceneObject o;
    o.first_index = object_first_;
    o.index_count = std::uint32_t(scene_.indices.size()) - object_first_;
    o.color = color;
    if (o.index_count) scene_.objects.push_back(o);
  }

 private:
  Scene& scene_;
  std::uint32_t object_first_ = 0;
};

}  // namespace logrid::samples
