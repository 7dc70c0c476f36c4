// The object-ID oracle: the check that a culled frame missed no visible object
// (docs/DESIGN.md, "The oracle"). It renders an ID pass of the whole scene into a
// framebuffer with an object-ID attachment and reads back which objects the full render
// shows; a conservative culler must have drawn every one of them. `logrid walk --verify`
// and the oracle tests use it, and an application verifies its own integration with it:
//
//   gl::Framebuffer ids_fb({width, height, camera.depth, /*object_ids=*/true});
//   ... cull and draw the frame as usual, remembering the ids the callback drew ...
//   const gl::OracleFrame oracle = gl::objectIdOracle(ids_fb, camera, object_boxes, [&] {
//     for (ObjectId id = 0; id < object_count; ++id) drawWithIdShader(id);
//   });
//   assert(oracle.missedBy(drawn_ids).empty());
//
// Depth-extrapolation artifacts. A fragment whose depth lies far nearer than its own
// object's box allows (key < near_key - 16 default margins, projection.hpp) cannot come
// from interpolating the object's triangles: Mesa llvmpipe produces such fragments on
// edge-on sliver triangles (areas around 1e-4 pixel), whose depth plane it extrapolates
// to pixel centres that fixed-point snapping let in (docs/ANALYSIS.md,
// "Depth-extrapolation artifacts"). No method that compares box depths can see them, so
// objects shown only through such fragments are reported apart, never silently dropped.
#pragma once

#include <functional>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/projection.hpp"
#include "logrid/types.hpp"

namespace logrid::gl {

// What the ID pass of a frame found, each list in ascending id order.
struct OracleFrame {
  std::vector<ObjectId> visible;    // some fragment within the depth range of the object's box
  std::vector<ObjectId> artifacts;  // only fragments nearer than the object's box allows

  // The visible objects that are not in `drawn` (any order, repeats allowed), in
  // ascending order: what a conservative culler must never leave out.
  std::vector<ObjectId> missedBy(const std::vector<ObjectId>& drawn) const;
};

// Renders the ID pass of the frame `camera` sees and classifies the objects it shows.
//
//   framebuffer   created with object_ids (an R32UI attachment), as large as the
//                 camera's viewport, for the camera's depth set-up. Its depth and IDs are
//                 cleared here (IDs to Framebuffer::kNoObject); its colour is left alone.
//   camera        the frame's camera, as the culler got it.
//   object_boxes  per ObjectId, the box enclosing that object's geometry, in the
//                 coordinates camera.view_projection maps (as the hierarchy's leaves
//                 give them). IDs in the buffer beyond its size are ignored.
//   draw_ids      called once with the framebuffer bound, its depth state applied and
//                 only the ID attachment enabled: draws every object of the scene (at
//                 least every one in the view frustum) with the frame's depth test,
//                 writing its id to colour attachment 1 (layout(location = 1) out uint in
//                 GLSL; gl::MeshRenderer does it in Pass::ObjectIds).
// Needs the current context. In both forms (logrid/error.hpp): tryObjectIdOracle()
// returns the frame or the error, objectIdOracle() throws it as logrid::Error. Fails with
// ErrorCode::InvalidArgument for a framebuffer without an ID attachment or of another
// size or depth set-up (convention, clip range, format) than the camera, or an invalid
// camera, and with ErrorCode::Runtime for a GL error during the pass.
Result<OracleFrame> tryObjectIdOracle(const Framebuffer& framebuffer, const Camera& camera,
                                      const std::vector<Aabb>& object_boxes,
                                      const std::function<void()>& draw_ids);
OracleFrame objectIdOracle(const Framebuffer& framebuffer, const Camera& camera,
                           const std::vector<Aabb>& object_boxes,
                           const std::function<void()>& draw_ids);

// The same for a frame whose Projector the application already holds (the frame's
// camera is projector.camera()), so that the pass builds none of its own: `projector`
// must have the default ProjectionSettings (Projector::create(camera)), because the
// artifacts are judged with the default margins whatever settings the culler projects
// with (a culler whose margins are too small then shows misses, not artifacts). The
// Camera form above is this with Projector::create(camera).
Result<OracleFrame> tryObjectIdOracle(const Framebuffer& framebuffer, const Projector& projector,
                                      const std::vector<Aabb>& object_boxes,
                                      const std::function<void()>& draw_ids);
OracleFrame objectIdOracle(const Framebuffer& framebuffer, const Projector& projector,
                           const std::vector<Aabb>& object_boxes,
                           const std::function<void()>& draw_ids);

#if LOGRID_HAS_EXCEPTIONS
inline OracleFrame objectIdOracle(const Framebuffer& framebuffer, const Camera& camera,
                                  const std::vector<Aabb>& object_boxes,
                                  const std::function<void()>& draw_ids) {
  return logrid::orThrow(tryObjectIdOracle(framebuffer, camera, object_boxes, draw_ids));
}
inline OracleFrame objectIdOracle(const Framebuffer& framebuffer, const Projector& projector,
                                  const std::vector<Aabb>& object_boxes,
                                  const std::function<void()>& draw_ids) {
  return logrid::orThrow(tryObjectIdOracle(framebuffer, projector, object_boxes, draw_ids));
}
#endif

}  // namespace logrid::gl
