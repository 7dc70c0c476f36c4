#include "logrid/projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "rounding.hpp"

#include "logrid/error.hpp"

namespace logrid {
namespace {

using detail::roundDown;
using detail::roundUp;

// Clamps an integral-valued double into [lo, hi] before converting it.
std::int32_t clampToInt(double v, std::int32_t lo, std::int32_t hi) {
  if (!(v > lo)) return lo;
  if (v >= hi) return hi;
  return static_cast<std::int32_t>(v);
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A point of the (near-clipped) box in clip space, with S: the sums of the magnitudes
// of the terms of its clip x, y, z and w (see "Why the margins have their values").
struct ClipPoint {
  double c[4];
  double s[4];
};

// The 12 edges of a box whose corners are numbered by bits (x: 1, y: 2, z: 4).
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

double dot4(const double* plane, const double* c) {
  return plane[0] * c[0] + plane[1] * c[1] + plane[2] * c[2] + plane[3] * c[3];
}

}  // namespace

std::string validateProjectionSettings(const ProjectionSettings& settings) {
  std::ostringstream out;
  if (settings.subpixel_bits < 0 || settings.subpixel_bits > 16) {
    out << "Projector: subpixel_bits " << settings.subpixel_bits
        << " is out of range; use 0 to 16 (the default 4 is GL's minimum and safe everywhere)";
  } else if (!(settings.render_error_ulps >= 0) || !std::isfinite(settings.render_error_ulps)) {
    out << "Projector: render_error_ulps " << settings.render_error_ulps
        << " is invalid; use a finite value >= 0 (the default " << kRenderErrorUlps << " is safe)";
  } else if (!(settings.quantisation_scale >= 0) || !std::isfinite(settings.quantisation_scale)) {
    out << "Projector: quantisation_scale " << settings.quantisation_scale
        << " is invalid; use a finite value >= 0 (the default 1 is safe)";
  }
  return out.str();
}

Projector::Projector(const Camera& camera, const ProjectionSettings& settings)
    : camera_(camera), settings_(settings) {
  const std::string problem = validateCamera(camera);
  if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, problem);
  const std::string bad_settings = validateProjectionSettings(settings);
  if (!bad_settings.empty()) throw Error(ErrorCode::InvalidArgument, bad_settings);

  origin_ = camera.render_origin;
  const Mat4d render = multiply(camera.view_projection, translation(origin_));
  for (int i = 0; i < 16; ++i) {
    render_[i] = render.m[i];
    render_abs_[i] = std::fabs(render.m[i]);
  }

  const bool reversed = camera.depth.convention == DepthConvention::Reversed;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  const double low = zero_to_one ? 0.0 : -1.0;
  // "z_ndc >= c" is z - c w >= 0 and "z_ndc <= c" is c w - z >= 0 (for w > 0).
  const double ge_low[4] = {0, 0, 1, -low};
  const double le_one[4] = {0, 0, -1, 1};
  std::copy(reversed ? le_one : ge_low, (reversed ? le_one : ge_low) + 4, near_plane_);
  std::copy(reversed ? ge_low : le_one, (reversed ? ge_low : le_one) + 4, far_plane_);

  depth_scale_ = zero_to_one ? 1.0 : 0.5;
  depth_offset_ = zero_to_one ? 0.0 : 0.5;
  key_sign_ = reversed ? -1.0 : 1.0;
  quantisation_ = quantisationStep(camera.depth.format) * settings.quantisation_scale;
  snap_px_ = settings.subpixel_bits >= 16 ? 0.0 : std::ldexp(0.5, -settings.subpixel_bits);
  clear_key_ = logrid::clearKey(camera.depth);
  near_key_ = logrid::nearPlaneKey(camera.depth);
}

BoxProjection Projector::project(const Aabb& box) const { return projectWith(box, nullptr); }

BoxProjection Projector::projectWith(const Aabb& box, Extent* extent) const {
  BoxProjection out;
  const PixelRect viewport = viewportRect();
  // Anything we cannot reason about is visible everywhere and drawn last.
  auto visibleEverywhere = [&](ProjectionClass cls) {
    out.cls = cls;
    out.rect = viewport;
    out.near_key = near_key_;
    out.far_key = clear_key_;
    out.margin = 0;
    return out;
  };
  if (!finite(box.min) || !finite(box.max) || box.min.x > box.max.x || box.min.y > box.max.y ||
      box.min.z > box.max.z) {
    return visibleEverywhere(ProjectionClass::Invalid);
  }

  // Corners relative to the render origin, in clip space, with their term magnitudes.
  ClipPoint corners[8];
  int outside[6] = {0, 0, 0, 0, 0, 0};
  bool crosses_near = false;
  for (int i = 0; i < 8; ++i) {
    const double q[3] = {double((i & 1) ? box.max.x : box.min.x) - origin_.x,
                         double((i & 2) ? box.max.y : box.min.y) - origin_.y,
                         double((i & 4) ? box.max.z : box.min.z) - origin_.z};
    ClipPoint& p = corners[i];
    for (int r = 0; r < 4; ++r) {
      p.c[r] = render_[r] * q[0] + render_[4 + r] * q[1] + render_[8 + r] * q[2] + render_[12 + r];
      p.s[r] = render_abs_[r] * std::fabs(q[0]) + render_abs_[4 + r] * std::fabs(q[1]) +
               render_abs_[8 + r] * std::fabs(q[2]) + render_abs_[12 + r];
    }
    const double w = p.c[3];
    outside[0] += (w + p.c[0] < 0);
    outside[1] += (w - p.c[0] < 0);
    outside[2] += (w + p.c[1] < 0);
    outside[3] += (w - p.c[1] < 0);
    const bool beyond_near = dot4(near_plane_, p.c) < 0;
    outside[4] += beyond_near;
    outside[5] += (dot4(far_plane_, p.c) < 0);
    crosses_near |= beyond_near;
  }
  for (int count : outside) {
    if (count == 8) {
      out.cls = ProjectionClass::Outside;
      return out;
    }
  }

  // The part of the box on the visible side of the near plane: corners inside, plus
  // the points where edges cross the plane (LOG §5 clips the boxes in software too).
  ClipPoint points[8 + 12];
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    if (dot4(near_plane_, corners[i].c) >= 0) points[count++] = corners[i];
  }
  if (crosses_near) {
    for (const auto& edge : kEdges) {
      const ClipPoint& a = corners[edge[0]];
      const ClipPoint& b = corners[edge[1]];
      const double da = dot4(near_plane_, a.c);
      const double db = dot4(near_plane_, b.c);
      if ((da < 0) == (db < 0)) continue;
      const double t = da / (da - db);
      ClipPoint& p = points[count++];
      for (int r = 0; r < 4; ++r) {
        p.c[r] = a.c[r] + t * (b.c[r] - a.c[r]);
        // |.| of a convex combination is at most the combination of the |.|s.
        p.s[r] = a.s[r] + t * (b.s[r] - a.s[r]);
      }
    }
  }

  const double half_w = 0.5 * camera_.width;
  const double half_h = 0.5 * camera_.height;
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = -x_min, key_min = x_min, key_max = -x_min;
  double err_x = 0, err_y = 0, err_z = 0;
  double w_min = std::numeric_limits<double>::infinity(), w_max = 0;
  for (int i = 0; i < count; ++i) {
    const ClipPoint& p = points[i];
    const double w = p.c[3];
    // Points of the clipped box lie in front of the eye for any sane projection; if
    // not (w <= 0, a projection that puts the near plane behind the eye), give up.
    if (!(w > 0)) return visibleEverywhere(ProjectionClass::CrossesNear);
    w_min = std::min(w_min, w), w_max = std::max(w_max, w);
    const double inv_w = 1.0 / w;
    const double xn = p.c[0] * inv_w, yn = p.c[1] * inv_w, zn = p.c[2] * inv_w;
    const double wx = (xn + 1.0) * half_w, wy = (yn + 1.0) * half_h;
    const double key = key_sign_ * (depth_scale_ * zn + depth_offset_);
    x_min = std::min(x_min, wx), x_max = std::max(x_max, wx);
    y_min = std::min(y_min, wy), y_max = std::max(y_max, wy);
    key_min = std::min(key_min, key), key_max = std::max(key_max, key);
    err_x = std::max(err_x, (p.s[0] + std::fabs(xn) * p.s[3]) * inv_w * half_w);
    err_y = std::max(err_y, (p.s[1] + std::fabs(yn) * p.s[3]) * inv_w * half_h);
    err_z = std::max(err_z, (p.s[2] + std::fabs(zn) * p.s[3]) * inv_w * depth_scale_);
  }
  if (!(x_min <= x_max) || !(y_min <= y_max) || !(key_min <= key_max) || !std::isfinite(err_z)) {
    return visibleEverywhere(ProjectionClass::Invalid);
  }

  const double k = settings_.render_error_ulps * kUnitRoundoff;
  const double widen_x = k * err_x + snap_px_;
  const double widen_y = k * err_y + snap_px_;
  if (extent) *extent = {widen_x, widen_y, w_min, w_max};
  const std::int32_t w_px = static_cast<std::int32_t>(camera_.width);
  const std::int32_t h_px = static_cast<std::int32_t>(camera_.height);
  if (camera_.multisample) {
    // Every pixel the widened footprint touches.
    out.rect.x0 = clampToInt(std::floor(x_min - widen_x), 0, w_px);
    out.rect.x1 = clampToInt(std::ceil(x_max + widen_x), 0, w_px);
    out.rect.y0 = clampToInt(std::floor(y_min - widen_y), 0, h_px);
    out.rect.y1 = clampToInt(std::ceil(y_max + widen_y), 0, h_px);
  } else {
    // Pixels whose centre i + 0.5 lies in the widened footprint.
    out.rect.x0 = clampToInt(std::ceil(x_min - widen_x - 0.5), 0, w_px);
    out.rect.x1 = clampToInt(std::floor(x_max + widen_x - 0.5) + 1.0, 0, w_px);
    out.rect.y0 = clampToInt(std::ceil(y_min - widen_y - 0.5), 0, h_px);
    out.rect.y1 = clampToInt(std::floor(y_max + widen_y - 0.5) + 1.0, 0, h_px);
  }

  const double far_plane_key = clear_key_;
  key_min = std::clamp(key_min, double(near_key_), far_plane_key);
  key_max = std::clamp(key_max, double(near_key_), far_plane_key);
  const double largest_key = std::max(std::fabs(key_min), std::fabs(key_max));
  out.near_key = roundDown(key_min);
  out.far_key = roundUp(key_max);
  out.margin = roundUp(quantisation_ + k * (err_z + largest_key));
  out.widen_x = roundUp(widen_x);
  out.widen_y = roundUp(widen_y);

  if (crosses_near) {
    out.cls = ProjectionClass::CrossesNear;
    out.near_key = near_key_;
  } else if (out.rect.empty()) {
    out.cls = ProjectionClass::Outside;  // covers no pixel centre: draws nothing
  } else {
    out.cls = ProjectionClass::Inside;
  }
  return out;
}

std::optional<QueryBox> Projector::queryBox(const Aabb& box) const {
  Extent e;
  if (projectWith(box, &e).cls != ProjectionClass::Inside) return std::nullopt;
  // Rows of the clip transform (xyz parts): a, b in pixels per clip unit, c the z row,
  // d the w row; a, b and c projected onto the plane normal to d ("Query boxes").
  double a[3], b[3], c[3], d[3];
  for (int j = 0; j < 3; ++j) {
    a[j] = render_[4 * j] * 0.5 * camera_.width;
    b[j] = render_[4 * j + 1] * 0.5 * camera_.height;
    c[j] = render_[4 * j + 2];
    d[j] = render_[4 * j + 3];
  }
  auto dot3 = [](const double* u, const double* v) {
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
  };
  const double dd = dot3(d, d);
  if (dd > 0) {
    const double ka = dot3(a, d) / dd, kb = dot3(b, d) / dd, kc = dot3(c, d) / dd;
    for (int j = 0; j < 3; ++j) {
      a[j] -= ka * d[j];
      b[j] -= kb * d[j];
      c[j] -= kc * d[j];
    }
  }
  const double aa = dot3(a, a), ab = dot3(a, b), bb = dot3(b, b);
  const double half_trace = 0.5 * (aa + bb);
  const double lambda =
      half_trace - std::sqrt(std::max(0.0, half_trace * half_trace - (aa * bb - ab * ab)));
  if (!(lambda > 0) || !(e.w_min > 0)) return std::nullopt;  // a degenerate projection
  const double r = 2.0 * std::hypot(e.widen_x, e.widen_y) + kQueryWidenPixels;
  // The eigenvalue carries the rounding of its formula: a relative slack of 1e-6.
  const double delta = r * e.w_max / std::sqrt(lambda) * (1.0 + 1e-6);
  if (!std::isfinite(delta)) return std::nullopt;

  QueryBox out;
  out.box.min = {roundDown(double(box.min.x) - delta), roundDown(double(box.min.y) - delta),
                 roundDown(double(box.min.z) - delta)};
  out.box.max = {roundUp(double(box.max.x) + delta), roundUp(double(box.max.y) + delta),
                 roundUp(double(box.max.z) + delta)};
  const BoxProjection q = project(out.box);
  if (q.cls != ProjectionClass::Inside) return std::nullopt;
  const double depth_shift = depth_scale_ * std::sqrt(dot3(c, c)) * delta / e.w_min;
  out.depth_bias = roundUp(2.0 * double(q.margin) + depth_shift);
  // Faces moved nearer than the near plane would be clipped away: no query then.
  if (!(double(q.near_key) - double(out.depth_bias) - double(q.margin) > double(near_key_))) {
    return std::nullopt;
  }
  return out;
}

}  // namespace logrid
