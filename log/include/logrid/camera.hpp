// The camera logrid culls for: a world-to-clip matrix, a viewport and the depth
// buffer's set-up. See types.hpp for the matrix, pixel and depth-key conventions.
#pragma once

#include <cstdint>
#include <string>

#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid {

// How the application's depth buffer is set up. Decides how window depth becomes a
// depth key and how large the depth margin must be (see projection.hpp).
struct DepthSetup {
  DepthConvention convention = DepthConvention::Standard;
  ClipDepthRange clip_range = ClipDepthRange::NegativeOneToOne;
  DepthFormat format = DepthFormat::D32F;
};

struct Camera {
  // World to clip space (projection * view), column-major, double precision.
  Mat4d view_projection;
  // Viewport size in pixels; the viewport's origin is (0, 0). Both must be >= 1.
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  DepthSetup depth;
  // The point the renderer subtracts from world positions before its single-precision
  // vertex transform. (0, 0, 0) for a renderer that transforms world coordinates in
  // float; the eye position for one that renders camera-relative. logrid uses it only
  // to bound the renderer's rounding error (projection.hpp), which grows with the
  // distance of the geometry from this point.
  DVec3 render_origin;
  // Set when the renderer samples anywhere but at pixel centres (multisampling,
  // conservative rasterisation): a box then counts every pixel it touches, not only
  // those whose centres it covers.
  bool multisample = false;
};

// The largest viewport side logrid accepts (GL drivers allow at most 32768).
inline constexpr std::uint32_t kMaxViewportSide = 32768;

// Returns an empty string if the camera can be culled for, otherwise a message that
// names the bad field and its value: a NaN or infinite matrix element, a matrix whose
// bottom row is zero (every clip w is 0), a zero or too large viewport, a non-finite
// render origin, an unknown depth enum value, reversed depth without the zero-to-one
// clip range. Not caught, because the camera alone does not show them: a singular
// matrix (accepted: logrid then projects as degenerately as the renderer draws), and a
// projection built for another depth set-up than `depth` (wrong answers: build both
// from the same DepthSetup, as perspective() and orthographic() take it).
std::string validateCamera(const Camera& camera);

// ---------------------------------------------------------------------------
// Matrix helpers (double precision, column-major). Applications may build their
// matrices any way they like; these exist so that samples and tests agree.
// ---------------------------------------------------------------------------

Mat4d multiply(const Mat4d& a, const Mat4d& b);
Mat4d translation(const DVec3& offset);
// The three that can fail come in both forms (error.hpp): tryX() returns the matrix or
// the error (ErrorCode::InvalidArgument naming the values), X() throws it.
//
// Right-handed view matrix looking from eye towards target (the camera looks down -z).
Result<Mat4d> tryLookAt(const DVec3& eye, const DVec3& target, const DVec3& up);
Mat4d lookAt(const DVec3& eye, const DVec3& target, const DVec3& up);
// Right-handed perspective projection. fovy in radians, near > 0. far may be +infinity
// (only meaningful for the reversed convention, where it is the usual choice). The
// matrix maps near to the convention's near depth and far to its far depth.
Result<Mat4d> tryPerspective(double fovy, double aspect, double near, double far,
                             const DepthSetup& depth);
Mat4d perspective(double fovy, double aspect, double near, double far, const DepthSetup& depth);
// Right-handed orthographic projection; near and far are distances along -z.
Result<Mat4d> tryOrthographic(double left, double right, double bottom, double top, double near,
                              double far, const DepthSetup& depth);
Mat4d orthographic(double left, double right, double bottom, double top, double near, double far,
                   const DepthSetup& depth);
#if LOGRID_HAS_EXCEPTIONS
inline Mat4d lookAt(const DVec3& eye, const DVec3& target, const DVec3& up) {
  return orThrow(tryLookAt(eye, target, up));
}
inline Mat4d perspective(double fovy, double aspect, double near, double far,
                         const DepthSetup& depth) {
  return orThrow(tryPerspective(fovy, aspect, near, far, depth));
}
inline Mat4d orthographic(double left, double right, double bottom, double top, double near,
                          double far, const DepthSetup& depth) {
  return orThrow(tryOrthographic(left, right, bottom, top, near, far, depth));
}
#endif

// The key of the cleared buffer (the farthest key) and of the near plane.
float clearKey(const DepthSetup& depth);
float nearPlaneKey(const DepthSetup& depth);
// Window depth (as stored in the buffer, in [0, 1]) to depth key and back.
inline float depthKey(DepthConvention convention, float window_depth) {
  return convention == DepthConvention::Reversed ? -window_depth : window_depth;
}
inline float windowDepth(DepthConvention convention, float key) {
  return convention == DepthConvention::Reversed ? -key : key;
}

}  // namespace logrid
