#include "logrid/camera.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "logrid/error.hpp"

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

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
  Mat4d r;
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a(row, k) * b(k, c);
      r(row, c) = s;
    }
  }
  return r;
}

Mat4d translation(const DVec3& t) {
  Mat4d r;
  r(0, 3) = t.x;
  r(1, 3) = t.y;
  r(2, 3) = t.z;
  return r;
}

Mat4d lookAt(const DVec3& eye, const DVec3& target, const DVec3& up) {
  auto sub = [](DVec3 a, DVec3 b) { return DVec3{a.x - b.x, a.y - b.y, a.z - b.z}; };
  auto cross = [](DVec3 a, DVec3 b) {
    return DVec3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  auto dot = [](DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto normalize = [&](DVec3 a) {
    const double len = std::sqrt(dot(a, a));
    if (!(len > 0) || !std::isfinite(len)) {
      throw Error(ErrorCode::InvalidArgument,
                  "lookAt: eye, target and up must be finite, eye != target, and up not "
                  "parallel to the view direction");
    }
    return DVec3{a.x / len, a.y / len, a.z / len};
  };
  const DVec3 f = normalize(sub(target, eye));
  const DVec3 s = normalize(cross(f, up));
  const DVec3 u = cross(s, f);
  Mat4d r;
  r(0, 0) = s.x, r(0, 1) = s.y, r(0, 2) = s.z, r(0, 3) = -dot(s, eye);
  r(1, 0) = u.x, r(1, 1) = u.y, r(1, 2) = u.z, r(1, 3) = -dot(u, eye);
  r(2, 0) = -f.x, r(2, 1) = -f.y, r(2, 2) = -f.z, r(2, 3) = dot(f, eye);
  return r;
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

void checkPlanes(const char* fn, double near, double far, bool perspective) {
  const bool near_ok = perspective ? (near > 0 && std::isfinite(near)) : std::isfinite(near);
  if (!near_ok || std::isnan(far) || !(far > near) || (!perspective && std::isinf(far))) {
    std::ostringstream out;
    out << fn << ": near " << near << " and far " << far << " are invalid; need "
        << (perspective ? "0 < near < far (far may be +inf)" : "near < far, both finite");
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
}

}  // namespace

Mat4d perspective(double fovy, double aspect, double near, double far, const DepthSetup& depth) {
  checkPlanes("perspective", near, far, true);
  if (!(fovy > 0 && fovy < M_PI) || !(aspect > 0) || !std::isfinite(aspect)) {
    std::ostringstream out;
    out << "perspective: fovy " << fovy << " rad and aspect " << aspect
        << " are invalid; need 0 < fovy < pi and aspect > 0";
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
  // z_ndc = (a z_eye + b) / -z_eye with z_ndc(-near) = zn and z_ndc(-far) = zf.
  const auto [zn, zf] = ndcDepthRange(depth);
  const double a = std::isinf(far) ? -zf : (zn * near - zf * far) / (far - near);
  const double b = zn * near + a * near;
  const double f = 1.0 / std::tan(fovy / 2.0);
  Mat4d r;
  r(0, 0) = f / aspect;
  r(1, 1) = f;
  r(2, 2) = a;
  r(2, 3) = b;
  r(3, 2) = -1.0;
  r(3, 3) = 0.0;
  return r;
}

Mat4d orthographic(double left, double right, double bottom, double top, double near, double far,
                   const DepthSetup& depth) {
  checkPlanes("orthographic", near, far, false);
  if (!(right > left) || !(top > bottom) || !std::isfinite(right - left) ||
      !std::isfinite(top - bottom)) {
    throw Error(ErrorCode::InvalidArgument,
                "orthographic: need left < right and bottom < top, all finite");
  }
  // z_ndc = a z_eye + b with z_ndc(-near) = zn and z_ndc(-far) = zf.
  const auto [zn, zf] = ndcDepthRange(depth);
  const double a = (zn - zf) / (far - near);
  const double b = zn + a * near;
  Mat4d r;
  r(0, 0) = 2.0 / (right - left);
  r(0, 3) = -(right + left) / (right - left);
  r(1, 1) = 2.0 / (top - bottom);
  r(1, 3) = -(top + bottom) / (top - bottom);
  r(2, 2) = a;
  r(2, 3) = b;
  return r;
}

float clearKey(const DepthSetup& depth) {
  return depth.convention == DepthConvention::Reversed ? -0.0f : 1.0f;
}

float nearPlaneKey(const DepthSetup& depth) {
  return depth.convention == DepthConvention::Reversed ? -1.0f : 0.0f;
}

}  // namespace logrid
