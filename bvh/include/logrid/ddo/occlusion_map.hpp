// The DDO run time's occlusion map (DDO §4.2): the occluders selected so far, in image
// space, tested against a node's bounding rectangle.
//
// The paper projects occluders onto a coordinate plane and keeps the union of their
// rectangles (quadtree, uniform quadtree or hierarchy of grids), with no depth: its
// front-to-back order is meant to guarantee that every occluder lies in front of every
// node tested after it. That does not hold for the tight boxes of triangles that reach
// out of their cells, so this map keeps depth: per pixel, the key (types.hpp) of the
// nearest occluder covering the pixel's centre (a z-buffer of occluders, the union of
// their hidden regions), and per 16 x 16 tile the largest of those keys, so that most
// tests are decided tile by tile. A node is occluded when every pixel of its rectangle
// holds a key below the node's nearest key minus its margin: whatever the node holds lies
// behind an occluder at every pixel, hence behind the geometry that makes the occluder
// valid. Order no longer matters for correctness, only for how much is culled.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/types.hpp"

namespace logrid::ddo {

class OcclusionMap {
 public:
  static constexpr std::uint32_t kTile = 16;

  // Empty (every pixel at `clear_key`) for a width x height viewport.
  void reset(std::uint32_t width, std::uint32_t height, float clear_key);

  // Covers the pixel centres inside or on the convex quad `window` (window coordinates,
  // corners in order around it) with key = a + b x + c y (x, y the pixel centre), where
  // it is nearer than what the pixel holds. Returns the pixels written.
  std::uint64_t insertQuad(const double window[4][2], double a, double b, double c);

  // Does every pixel of `rect` (clipped to the viewport) hold a key < threshold?
  bool occludes(const PixelRect& rect, float threshold) const;

  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  float key(std::uint32_t x, std::uint32_t y) const { return keys_[std::size_t(y) * width_ + x]; }

 private:
  void refreshTile(std::uint32_t tx, std::uint32_t ty);

  std::uint32_t width_ = 0, height_ = 0, tiles_x_ = 0, tiles_y_ = 0;
  float clear_ = 1;
  std::vector<float> keys_;
  std::vector<float> tile_max_;
  std::vector<std::uint8_t> tile_dirty_;
  std::vector<std::uint32_t> dirty_list_;
};

}  // namespace logrid::ddo
