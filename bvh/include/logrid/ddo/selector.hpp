// The DDO run time (DDO §4): a top-down, front-to-back walk of the octree for one camera
// that selects the faces valid for the viewpoint, tests every node against the occlusion
// map of the faces selected so far, and hands the objects of visible leaves to the
// renderer. Two uses (samples/cli, methods `ddo` and `ddo+log`):
//   * the paper's culler: draw what select() hands over; nothing is read back;
//   * occluders for another culler: draw occluders() into the depth buffer first (depth
//     only, integration/occluder_renderer.hpp), then run that culler.
//
// Order (§4.1). Children are visited front to back with the paper's look-up table: for
// the octant o of the eye relative to the cell's centre, the order o ^ k for k = 0, 1, 2,
// 4, 3, 5, 6, 7 (the eye's octant, its three face neighbours, its three edge neighbours,
// the opposite one). A node's valid faces enter the map before its children are visited
// (the paper enters them after): the map holds depth (occlusion_map.hpp), so the order
// only decides how early they help.
//
// A face is selected for a viewpoint e when (regions.hpp):
//   * e lies at height >= H above it (beyond the clipping plane), or, for an orthographic
//     camera, the view direction comes from the face's side;
//   * some anchor point of the enlarged face sees e with slopes in a region whose bit is
//     set (all regions whose cells meet the range of slopes over the anchors are tried);
//   * the part of the region's frustum the eye looks through, i.e. the convex hull of
//     the enlarged face and the points where the rays from the eye to its corners cross
//     the clipping plane, lies wholly in front of the near plane: the geometry that hides
//     the face is then neither clipped nor behind the eye, and the rasteriser draws it
//     over every pixel of the face (its depth margin is that hull's box's);
//   * the face, pushed back by its depth margin, lies in front of the far plane.
//
// Pixels and depth of an occluder. The face is drawn where the scene's geometry hides it,
// and must never hide that geometry: its depth keys are pushed back by twice the sum of
// the projection margins (projection.hpp) of the face and of the region's frustum, which
// bounds the stored depth of both. Its outline: the validity test covered the face
// enlarged by face_margin times its side, so a rasteriser may move the face's edges by up
// to the projected width of that band. Where the band is narrower on screen than twice
// `snap_pixels` (a vertex of the scene or of the quad moves by up to 1/16 pixel on each
// axis with GL's minimum of 4 sub-pixel bits, 0.09 pixel along an edge's normal, plus
// float rounding), the quad is shrunk by 2 * snap_pixels instead.
//
// Occluders drawn for another culler are merged: adjacent selected faces of one plane
// with a common edge become one quad (rows first, then columns), when both had a wide
// enough band.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/ddo/occlusion_map.hpp"
#include "logrid/ddo/octree.hpp"
#include "logrid/error.hpp"
#include "logrid/projection.hpp"

namespace logrid::ddo {

struct SelectorSettings {
  bool occlusion_map = true;   // test nodes against the map (off: view-frustum culling only)
  double snap_pixels = 0.125;  // how far a rasteriser may move an edge (see above)
  bool merge = true;           // merge adjacent faces into larger occluders
  // Nodes whose rectangle on screen is narrower and lower than this many pixels are
  // skipped with their subtrees (0: none): their faces, and their children's, lie inside
  // it and fill no tile of that side alone. ddo+log sets the grid's tile size: on the
  // city at 0.1 (640x480) that halves the walk (1.4 to 0.7 ms a frame) for 2 % fewer
  // tiles recorded (docs/DDO.md). Only merged neighbours could have filled one.
  std::uint32_t min_node_pixels = 0;
};

// A selected occluder: a convex quad in normalized device coordinates (w = 1), its depth
// already pushed back, ready to draw with the depth test and depth writes on.
struct Occluder {
  double ndc[4][3] = {};     // x, y, z of the corners, in order around the quad
  double window[4][2] = {};  // the same corners in window coordinates (exact, before the
                             // float rounding of ndc): its outline for coverage.hpp
  PixelRect rect;            // every pixel it may cover (window coordinates)
  float near_key = 0;        // smallest and largest depth key GL may store for it (its
  float far_key = 0;         // corners' keys with the rounding of drawing them: the
                             // projection settings' quantisation and render error)
  std::uint32_t faces = 1;   // octree faces it stands for
};

// The occluder GL draws for a convex outline in window coordinates (pixels, lower-left
// origin) whose depth keys are key = plane[0] + plane[1] x + plane[2] y, standing for
// `faces` octree faces: its NDC corners, the pixels it may cover and the keys GL may
// store for it, with the rounding of drawing it (the projection's quantisation step and
// render error, projection.hpp). Nothing when it covers no pixel of the viewport.
std::optional<Occluder> makeOccluder(const double window[4][2], const double plane[3],
                                     std::uint32_t faces, const Camera& camera,
                                     const ProjectionSettings& projection = {});

struct SelectionStats {
  std::uint64_t nodes_visited = 0;
  std::uint64_t nodes_view_culled = 0;
  std::uint64_t nodes_occluded = 0;  // found hidden by the map (subtree culled)
  std::uint64_t nodes_near = 0;      // crossing the near plane: visible without a test
  std::uint64_t nodes_small = 0;     // smaller than SelectorSettings::min_node_pixels: skipped
  // Without a face valid from any region in their subtree: skipped unprojected where the
  // walk serves faces alone (no occlusion map, no draw callback: ddo+log).
  std::uint64_t nodes_faceless = 0;
  std::uint64_t map_tests = 0;
  std::uint64_t leaves_visible = 0;
  std::uint64_t objects = 0;         // handed to the draw callback
  std::uint64_t faces_valid = 0;     // faces of visited nodes valid for this viewpoint
  std::uint64_t faces_selected = 0;  // of those, usable (near and far planes, outline)
  std::uint64_t occluders = 0;       // occluders() after merging
  std::uint64_t map_pixels = 0;      // map pixels written
  double seconds = 0;
};

class Selector {
 public:
  // `octree` must outlive the selector and keep its masks (the selector notes which
  // subtrees hold a valid face).
  explicit Selector(const Octree& octree, const SelectorSettings& settings = {});

  // One frame. `draw` (may be empty) gets each object of each visible leaf once. In both
  // forms (logrid/error.hpp): fails with ErrorCode::InvalidArgument for an invalid camera
  // (validateCamera) or projection settings (validateProjectionSettings).
  Status trySelect(const Camera& camera, const std::function<void(ObjectId)>& draw,
                   SelectionStats& stats, const ProjectionSettings& projection = {});
  void select(const Camera& camera, const std::function<void(ObjectId)>& draw,
              SelectionStats& stats, const ProjectionSettings& projection = {});

  const std::vector<Occluder>& occluders() const { return occluders_; }
  const OcclusionMap& map() const { return map_; }
  const SelectorSettings& settings() const { return settings_; }

 private:
  struct Face;
  struct Frame;
  struct FaceOutline;
  // `p`: the node's projection (its parent projects its children together).
  void visit(std::uint32_t node, const BoxProjection& p, Frame& frame);
  // The node's faces that hide what lies behind them from this viewpoint, each through
  // the steps below (false: the face is not used this frame).
  void selectFaces(std::uint32_t node, Frame& frame);
  // The viewpoint lies in one of the face's valid regions (the bits of `mask`).
  bool seesValidRegion(std::uint64_t mask, const FaceFrame& face, const Frame& frame) const;
  // The projection of the cone between the face and its clipping plane, whose margin
  // bounds the depth of the geometry that hides the face.
  static bool coneProjection(const FaceFrame& face, const Frame& frame, BoxProjection& cone);
  // The face's outline on screen, its depth push-back and whether it may be merged.
  static bool faceOnScreen(const FaceFrame& frame_face, const Frame& frame,
                           const BoxProjection& cone, Face& face, FaceOutline& outline);
  // The depth plane over the outline, pushed back; false if it reaches the far plane.
  static bool depthPlane(const FaceOutline& outline, float clear_key, Face& face);
  void finishOccluders(Frame& frame);

  const Octree& octree_;
  SelectorSettings settings_;
  OcclusionMap map_;
  std::vector<Occluder> occluders_;
  std::vector<std::uint32_t> object_stamp_;
  std::uint32_t stamp_ = 0;
  // Per node: some face of it or of a node below has a valid region.
  std::vector<std::uint8_t> with_faces_;
};

#if LOGRID_HAS_EXCEPTIONS
inline void Selector::select(const Camera& camera, const std::function<void(ObjectId)>& draw,
                             SelectionStats& stats, const ProjectionSettings& projection) {
  logrid::orThrow(trySelect(camera, draw, stats, projection));
}
#endif

}  // namespace logrid::ddo
