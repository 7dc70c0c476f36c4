// Optional: a logrid::Camera straight from GLM matrices, for applications that already
// hold their view and projection as glm::mat4 or glm::dmat4.
//
// Header-only. Including it needs GLM (0.9.9; Debian: libglm-dev, CMake:
// find_package(glm CONFIG) and link glm::glm); logrid's libraries themselves link no
// GLM into your program, and no other logrid header includes GLM.
//
// logrid defines no GLM_FORCE_* macro. GLM's own projection functions target the clip
// depth range of the including translation unit's GLM configuration: -1..1 by default,
// 0..1 with GLM_FORCE_DEPTH_ZERO_TO_ONE. glmClipDepthRange() says which, so that
//   camera.depth.clip_range = logrid::glmClipDepthRange();
// describes a projection from glm::perspective() or glm::ortho(). The explicit variants
// (glm::perspectiveRH_ZO, ..._NO) target the range their suffix names, whatever the
// configuration.
//
// Example (a renderer transforming world coordinates in float, 32F standard depth):
//   const glm::mat4 projection = glm::perspective(fovy, aspect, near, far);
//   const glm::mat4 view = glm::lookAt(eye, target, up);
//   logrid::Camera camera = logrid::cameraFromGlm(
//       projection, view, width, height,
//       {logrid::DepthConvention::Standard, logrid::glmClipDepthRange(),
//        logrid::DepthFormat::D32F});
#pragma once

#include <cstdint>

#include <glm/ext/matrix_double4x4.hpp>
#include <glm/ext/vector_double3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "logrid/camera.hpp"
#include "logrid/types.hpp"

namespace logrid {

// GLM and logrid lay matrices out alike (column-major, m[column][row] in GLM, element
// (row r, column c) at m[c * 4 + r] in logrid), so these copy element for element.
// Float elements widen to double exactly.
template <typename T, glm::qualifier Q>
Mat4d toMat4d(const glm::mat<4, 4, T, Q>& m) {
  Mat4d r;
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) r(row, c) = static_cast<double>(m[c][row]);
  }
  return r;
}

inline glm::dmat4 toGlm(const Mat4d& m) {
  glm::dmat4 r(1.0);
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) r[c][row] = m(row, c);
  }
  return r;
}

template <typename T, glm::qualifier Q>
DVec3 toDVec3(const glm::vec<3, T, Q>& v) {
  return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

inline glm::dvec3 toGlm(const DVec3& v) { return {v.x, v.y, v.z}; }

// The clip depth range that GLM's unsuffixed projection functions target in this
// translation unit (GLM_FORCE_DEPTH_ZERO_TO_ONE or not).
constexpr ClipDepthRange glmClipDepthRange() {
#if defined(GLM_CONFIG_CLIP_CONTROL)
  return (GLM_CONFIG_CLIP_CONTROL & GLM_CLIP_CONTROL_ZO_BIT) ? ClipDepthRange::ZeroToOne
                                                             : ClipDepthRange::NegativeOneToOne;
#elif defined(GLM_FORCE_DEPTH_ZERO_TO_ONE)
  return ClipDepthRange::ZeroToOne;
#else
  return ClipDepthRange::NegativeOneToOne;
#endif
}

// A camera for logrid from the application's projection and view (world to eye)
// matrices, float or double: view_projection = projection * view, multiplied in double
// after widening (so a float application's matrices lose nothing more). `depth` must
// describe the depth buffer and the clip range the projection targets (camera.hpp);
// `render_origin` is the point the renderer subtracts from world positions before its
// float transform ((0, 0, 0) when it transforms world coordinates, the eye when it
// renders camera-relative). The result is not validated: cullFrame() does that
// (validateCamera() in camera.hpp says what it checks).
template <typename T, glm::qualifier Q>
Camera cameraFromGlm(const glm::mat<4, 4, T, Q>& projection, const glm::mat<4, 4, T, Q>& view,
                     std::uint32_t width, std::uint32_t height, const DepthSetup& depth,
                     const glm::dvec3& render_origin = glm::dvec3(0.0)) {
  const glm::dmat4 p(projection);
  const glm::dmat4 v(view);
  Camera camera;
  camera.view_projection = toMat4d(p * v);
  camera.width = width;
  camera.height = height;
  camera.depth = depth;
  camera.render_origin = toDVec3(render_origin);
  return camera;
}

}  // namespace logrid
