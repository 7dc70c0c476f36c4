// logrid — conservative image-space occlusion culling with a lazy occlusion grid.
//
// Conventions used by every public header of logrid:
//
// * World space is whatever the application uses; logrid only sees axis-aligned
//   boxes in it and a world-to-clip matrix.
// * Matrices are column-major 4x4 in double precision, laid out like OpenGL and GLM
//   (element (row r, column c) is m[c * 4 + r]); points are column vectors.
// * Pixels are in OpenGL window coordinates: origin at the bottom-left corner of the
//   viewport, x to the right, y up; pixel (i, j) has its centre at (i + 0.5, j + 0.5).
//   Rectangles are half-open: [x0, x1) x [y0, y1).
// * Depth is compared as a *depth key*: the window-space depth for the standard
//   convention and its negation for the reversed one, so that in both conventions a
//   smaller key is nearer to the eye, the cleared buffer holds the largest key, and
//   "occluded" always means "behind", i.e. a larger key.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

namespace logrid {

using NodeId = std::uint32_t;
using ObjectId = std::uint32_t;

struct Vec3 {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
};

// An axis-aligned box. Valid when min <= max on every axis and every value is finite;
// a box of zero extent on an axis is valid (a quad, a segment, a point).
struct Aabb {
  Vec3 min;
  Vec3 max;
};

// Column-major 4x4 matrix, double precision (see the conventions above).
struct Mat4d {
  double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  double& operator()(int row, int column) { return m[column * 4 + row]; }
  double operator()(int row, int column) const { return m[column * 4 + row]; }
};

struct DVec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

// Which way the z-buffer runs.
enum class DepthConvention : std::uint8_t {
  Standard,  // cleared to 1, GL_LESS: nearer is smaller
  Reversed,  // cleared to 0, GL_GREATER: nearer is larger (requires ClipDepthRange::ZeroToOne)
};

// The clip-space depth range the projection matrix targets (glClipControl's depth mode).
enum class ClipDepthRange : std::uint8_t {
  NegativeOneToOne,  // OpenGL's default: window depth = 0.5 * z_ndc + 0.5
  ZeroToOne,         // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE): window depth = z_ndc
};

// The depth buffer's storage format. Decides the quantisation part of the depth margin.
enum class DepthFormat : std::uint8_t {
  D16,   // 16-bit unsigned normalised
  D24,   // 24-bit unsigned normalised (with or without stencil)
  D32F,  // 32-bit float
};

// A half-open pixel rectangle [x0, x1) x [y0, y1) in window coordinates.
struct PixelRect {
  std::int32_t x0 = 0;
  std::int32_t y0 = 0;
  std::int32_t x1 = 0;
  std::int32_t y1 = 0;

  bool empty() const { return x1 <= x0 || y1 <= y0; }
  std::int64_t area() const { return empty() ? 0 : std::int64_t{x1 - x0} * std::int64_t{y1 - y0}; }
  // Do the two overlap? (Two non-empty ones: do they share a pixel.)
  bool meets(const PixelRect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// Does `area` meet (PixelRect::meets) any of `count` rectangles?
inline bool meetsAny(const PixelRect& area, const PixelRect* rects, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    if (area.meets(rects[i])) return true;
  }
  return false;
}

// Something drawn into the depth buffer besides the culler's own draws (Culler::noteDrawn,
// cullFrame's drawn_before, an occluder pre-pass).
struct DrawnArea {
  PixelRect rect;  // pixels it may cover (clipped to the viewport)
  // Its farthest depth key (with the margin of its rounding added); +infinity when
  // unknown: then every later occlusion-state test is done by depth.
  float far_key = std::numeric_limits<float>::infinity();
};

// The three answers of an occlusion test.
enum class Visibility : std::uint8_t {
  Visible,     // potentially visible: must be drawn (or its children tested)
  Occluded,    // hidden behind what is already in the depth buffer
  ViewCulled,  // outside the view frustum, or covers no pixel centre
};

const char* toString(DepthConvention);
const char* toString(ClipDepthRange);
const char* toString(DepthFormat);
const char* toString(Visibility);

}  // namespace logrid
