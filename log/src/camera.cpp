#include "logrid/camera.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include "logrid/error.hpp"
#include "logrid/glm_camera.hpp"

namespace logrid {

const char* toString(DepthConvention c) {
  return c == DepthConvention::Reversed ? "reversed" : "standard";
}
const char* toString(ClipDepthRange r) {
  return r == ClipDepthRange::ZeroToOne ? "zero-to-one" : "negative-one-to-one";
}
const char* toString(DepthFormat f) {
  switch (f) {
    case DepthFormat::D16: return "16";
    case DepthFormat::D24: return "24";
    case DepthFormat::D32F: return "32f";
  }
  return "?";
}
const char* toString(Visibility v) {
  switch (v) {
    case Visibility::Visible: return "visible";
    case Visibility::Occluded: return "occluded";
    case Visibility::ViewCulled: return "view-culled";
  }
  return "?";
}
const char* toString(ErrorCode c) {
  switch (c) {
    case ErrorCode::InvalidArgument: return "invalid argument";
    case ErrorCode::Unsupported: return "unsupported";
    case ErrorCode::Environment: return "environment";
    case ErrorCode::BadInput: return "bad input";
    case ErrorCode::Runtime: return "runtime";
  }
  return "?";
}

std::string validateCamera(const Camera& camera) {
  std::ostringstream out;
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(camera.view_projection.m[i])) {
      out << "camera: view_projection element " << i << " (row " << i % 4 << ", column " << i / 4
          << ") is " << camera.view_projection.m[i] << "; every matrix element must be finite";
      return out.str();
    }
  }
  const Mat4d& m = camera.view_projection;
  if (m(3, 0) == 0 && m(3, 1) == 0 && m(3, 2) == 0 && m(3, 3) == 0) {
    return "camera: view_projection has an all-zero bottom row, so every clip w is 0; pass "
           "projection * view";
  }
  if (camera.width < 1 || camera.height < 1 || camera.width > kMaxViewportSide ||
      camera.height > kMaxViewportSide) {
    out << "camera: viewport " << camera.width << "x" << camera.height
        << " is out of range; each side must be between 1 and " << kMaxViewportSide;
    return out.str();
  }
  const DVec3& o = camera.render_origin;
  if (!std::isfinite(o.x) || !std::isfinite(o.y) || !std::isfinite(o.z)) {
    out << "camera: render_origin (" << o.x << ", " << o.y << ", " << o.z << ") must be finite";
    return out.str();
  }
  const DepthSetup& d = camera.depth;
  if (d.convention != DepthConvention::Standard && d.convention != DepthConvention::Reversed) {
    out << "camera: depth.convention has the unknown value " << int(d.convention)
        << "; use DepthConvention::Standard or Reversed";
  } else if (d.clip_range != ClipDepthRange::NegativeOneToOne &&
             d.clip_range != ClipDepthRange::ZeroToOne) {
    out << "camera: depth.clip_range has the unknown value " << int(d.clip_range)
        << "; use ClipDepthRange::NegativeOneToOne or ZeroToOne";
  } else if (d.format != DepthFormat::D16 && d.format != DepthFormat::D24 &&
             d.format != DepthFormat::D32F) {
    out << "camera: depth.format has the unknown value " << int(d.format)
        << "; use DepthFormat::D16, D24 or D32F, as the depth buffer is";
  } else if (d.convention == DepthConvention::Reversed &&
             d.clip_range != ClipDepthRange::ZeroToOne) {
    out << "camera: reversed depth needs the zero-to-one clip range; set depth.clip_range to "
           "ClipDepthRange::ZeroToOne (glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)) and build "
           "the projection for it";
  }
  return out.str();
}

// multiply() and translation() work on Mat4d itself: a frame's matrices stay in one form
// from the application's camera to the projector. The projections and the view matrix
// are GLM's, in double precision, with logrid's checks and messages around them, each
// converted once when it is made. GLM's clip-range choice is made per call (the _NO and
// _ZO variants), from the DepthSetup, so no GLM_FORCE_DEPTH_ZERO_TO_ONE is defined
// anywhere in logrid.

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
  // Each element summed over k = 0..3 in order, as GLM's product sums a's columns, so
  // that the matrices of every caller are exactly what they were when this was GLM's.
  Mat4d r;
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) {
      r(row, c) =
          a(row, 0) * b(0, c) + a(row, 1) * b(1, c) + a(row, 2) * b(2, c) + a(row, 3) * b(3, c);
    }
  }
  return r;
}

Mat4d translation(const DVec3& t) {
  Mat4d r;  // the identity
  r(0, 3) = t.x;
  r(1, 3) = t.y;
  r(2, 3) = t.z;
  return r;
}

Result<Mat4d> tryLookAt(const DVec3& eye, const DVec3& target, const DVec3& up) {
  // glm::lookAtRH normalises target - eye and cross(direction, up); it returns NaNs where
  // either has no length, so that is checked first.
  const glm::dvec3 e = toGlm(eye), t = toGlm(target), u = toGlm(up);
  const auto usable = [](const glm::dvec3& v) {
    const double length = glm::length(v);
    return length > 0 && std::isfinite(length);
  };
  if (!usable(t - e) || !usable(glm::cross(glm::normalize(t - e), u)) || !usable(u)) {
    return Status(ErrorCode::InvalidArgument,
                  "lookAt: eye, target and up must be finite, eye != target, and up not "
                  "parallel to the view direction");
  }
  return toMat4d(glm::lookAtRH(e, t, u));
}

namespace {

// The NDC depths of the near and far planes for a depth set-up.
struct NdcDepthRange {
  double near_ndc;
  double far_ndc;
};

NdcDepthRange ndcDepthRange(const DepthSetup& depth) {
  const double low = depth.clip_range == ClipDepthRange::ZeroToOne ? 0.0 : -1.0;
  return depth.convention == DepthConvention::Reversed ? NdcDepthRange{1.0, low}
                                                       : NdcDepthRange{low, 1.0};
}

Status checkPlanes(const char* fn, double near, double far, bool perspective) {
  const bool near_ok = perspective ? (near > 0 && std::isfinite(near)) : std::isfinite(near);
  if (!near_ok || std::isnan(far) || !(far > near) || (!perspective && std::isinf(far))) {
    std::ostringstream out;
    out << fn << ": near " << near << " and far " << far << " are invalid; need "
        << (perspective ? "0 < near < far (far may be +inf)" : "near < far, both finite");
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

}  // namespace

Result<Mat4d> tryPerspective(double fovy, double aspect, double near, double far,
                             const DepthSetup& depth) {
  if (Status planes = checkPlanes("perspective", near, far, true); !planes) return planes;
  if (!(fovy > 0 && fovy < M_PI) || !(aspect > 0) || !std::isfinite(aspect)) {
    std::ostringstream out;
    out << "perspective: fovy " << fovy << " rad and aspect " << aspect
        << " are invalid; need 0 < fovy < pi and aspect > 0";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  const bool zero_to_one = depth.clip_range == ClipDepthRange::ZeroToOne;
  if (std::isinf(far)) {
    // GLM 0.9.9 has an infinite projection only for -1..1 standard depth, so the depth
    // row is set here: z_ndc = (a z_eye + b) / -z_eye with z_ndc(-near) = zn and
    // z_ndc -> zf as z_eye -> -inf gives a = -zf and b = (zn - zf) near. The other rows
    // do not depend on far.
    const auto [zn, zf] = ndcDepthRange(depth);
    glm::dmat4 r = glm::perspectiveRH_NO(fovy, aspect, near, 2 * near);
    r[2][2] = -zf;
    r[3][2] = (zn - zf) * near;
    return toMat4d(r);
  }
  // Reversed depth is the same projection with the planes swapped: near then maps to the
  // far end of the clip range and far to the near end.
  const bool reversed = depth.convention == DepthConvention::Reversed;
  const double n = reversed ? far : near, f = reversed ? near : far;
  return toMat4d(zero_to_one ? glm::perspectiveRH_ZO(fovy, aspect, n, f)
                             : glm::perspectiveRH_NO(fovy, aspect, n, f));
}

Result<Mat4d> tryOrthographic(double left, double right, double bottom, double top, double near,
                              double far, const DepthSetup& depth) {
  if (Status planes = checkPlanes("orthographic", near, far, false); !planes) return planes;
  if (!(right > left) || !(top > bottom) || !std::isfinite(right - left) ||
      !std::isfinite(top - bottom)) {
    return Status(ErrorCode::InvalidArgument,
                  "orthographic: need left < right and bottom < top, all finite");
  }
  // As in perspective(): reversed depth swaps the planes.
  const bool reversed = depth.convention == DepthConvention::Reversed;
  const double n = reversed ? far : near, f = reversed ? near : far;
  return toMat4d(depth.clip_range == ClipDepthRange::ZeroToOne
                     ? glm::orthoRH_ZO(left, right, bottom, top, n, f)
                     : glm::orthoRH_NO(left, right, bottom, top, n, f));
}

float clearKey(const DepthSetup& depth) {
  return depth.convention == DepthConvention::Reversed ? -0.0f : 1.0f;
}

float nearPlaneKey(const DepthSetup& depth) {
  return depth.convention == DepthConvention::Reversed ? -1.0f : 0.0f;
}

}  // namespace logrid
