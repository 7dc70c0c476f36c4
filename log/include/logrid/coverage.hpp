// Coverage the CPU knows: the pixels a convex quad drawn by the renderer is certain to
// cover, so that the lazy occlusion grid can record the cells (parts of tiles) it covers
// entirely as hidden behind the quad's farthest key, without reading them
// (OcclusionGrid::recordCovered). The occluder pre-pass of ddo+log uses it for its
// occluder quads, which it does not draw: the scene geometry that makes them valid covers
// every pixel GL would give them, at or in front of their keys (occluder_source.hpp).
//
// Why a recorded cell (the `rect` below) is conservative. The quad reaches the renderer as two
// triangles (0, 1, 2) and (0, 2, 3) of its corners in normalized device coordinates (float, w = 1),
// drawn with a depth test that keeps the nearer fragment. A cell is recorded when every
// sample point of every pixel of the cell (the pixel centre; with Camera::multisample any
// point of the pixel) lies inside the quad at a distance greater than `edge` from each of
// its edge lines, where edge bounds how far the renderer may move a point of an edge:
//   * a vertex's window position differs from the exact one computed here in double by
//     the float rounding of its NDC coordinates and of the viewport transform (and, for a
//     quad the renderer clips, of the clipped vertices, which lie on the edges up to the
//     same rounding): kRenderErrorUlps * u * (1 + |ndc|) * half the viewport side, per
//     axis, with the projection's render_error_ulps (projection.hpp, (2) and (4));
//   * then it is snapped to the sub-pixel grid: up to half a sub-pixel step per axis
//     (ProjectionSettings::subpixel_bits; GL requires at least 4 bits);
// so each vertex moves by at most d = hypot(widen_x, widen_y), and every point of a drawn
// edge lies within d of the exact edge (a point of a segment moves by at most what its
// ends move). Let p be a sample point farther than d from every exact edge line, inside
// the exact quad. Moving the vertices continuously from their exact to their drawn
// positions never moves the outline across p, so p's winding number about the drawn
// outline stays 1; that number is the sum of its winding numbers about the two drawn
// triangles (their shared diagonal cancels), so p lies inside one of them, or on the
// diagonal between two triangles lying on either side of it, which GL's rule for shared
// edges gives to exactly one of them. The sample gets a fragment of the quad.
//
// Its depth: the fragment's key lies between the keys of the triangle's corners, moved by
// the rounding of drawing (the quad's near_key and far_key carry that margin: the
// projection's quantisation step and render error, as DrawnArea::far_key does), and the
// depth test only makes the stored key smaller, so after the draw every sample of the
// cell holds a key <= far_key for the rest of the frame (until a clear). No fragment is
// clipped away: the rule asks near_key > the near plane's key and far_key < the clear key
// (a quad that might reach either plane records nothing), and the renderer's x/y clipping
// keeps every point inside the viewport.
//
// The quad must be convex (checked: a non-convex or degenerate outline, such as a quad
// seen edge-on, covers nothing). A convex region holds the convex hull of any points it
// holds, so it suffices to test the four corner samples of the cell against the region
// {p : every edge's inward distance > edge}, itself convex.
//
// tests/unit/coverage_test.cpp tests the rule at tile borders, at the near plane and edge
// on; tests/gl/coverage_gl_test.cpp draws quads with GL, finds no recorded sample beyond
// the recorded key with the defaults, and shrinks the margins: without the edge widening
// a snapped edge leaves a recorded pixel free, without the quantisation step a D16 key is
// stored beyond the recorded one (the render error term is not shown apart on llvmpipe;
// see that test), and two quads with a gap along a column of pixel centres leave that
// column's cells unrecorded (each cell is judged against one quad at a time; cells of
// different quads hide a tile together in the grid).
#pragma once

#include "logrid/camera.hpp"
#include "logrid/projection.hpp"
#include "logrid/types.hpp"

namespace logrid {

// A convex quad the renderer draws with the depth test that keeps the nearer fragment.
struct DrawnQuad {
  // Corners in window coordinates (pixels, origin at the lower left), in order around the
  // quad (either orientation), exactly as the NDC corners handed to the renderer map to
  // the viewport before any rounding.
  double window[4][2] = {};
  float near_key = 0;  // smallest and largest key the renderer may store for it, with
  float far_key = 0;   // the margin of drawing it (DrawnArea::far_key)
};

// What the renderer may do to a quad: see the derivation above.
struct CoverageRule {
  double snap = 0;          // pixels a vertex may be snapped by, per axis
  double render_error = 0;  // relative float error of a window coordinate (ulps * u)
  double half_width = 0;    // half the viewport, pixels
  double half_height = 0;
  bool whole_pixels = false;  // samples anywhere in a pixel (Camera::multisample)
  float near_limit = 0;       // the near plane's key: near_key must lie beyond it
  float far_limit = 1;        // the clear key: far_key must lie in front of it
};

// The rule for `camera` drawn with the projection's settings (the same margins
// Projector uses).
CoverageRule coverageRule(const Camera& camera, const ProjectionSettings& settings = {});

// Does the renderer certainly store a key <= quad.far_key at every sample of every pixel
// of `rect` (non-empty, inside the viewport) once it has drawn the quad?
bool coversRect(const DrawnQuad& quad, const PixelRect& rect, const CoverageRule& rule);

// coversRect() for one quad and many rectangles: the quad's checks and edges are worked
// out once (OcclusionGrid::recordCovered asks it for every cell under the quad).
class QuadCoverage {
 public:
  QuadCoverage(const DrawnQuad& quad, const CoverageRule& rule);
  bool covers(const PixelRect& rect) const;

 private:
  bool usable_ = false;  // within the planes, finite, convex
  double nx_[4] = {}, ny_[4] = {}, offset_[4] = {};
  double inset_ = 0.5;
};

}  // namespace logrid
