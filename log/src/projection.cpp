#include "logrid/projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

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

// The 12 edges of a box whose corners are numbered by bits (x: 1, y: 2, z: 4).
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

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

Result<Projector> Projector::create(const Camera& camera, const ProjectionSettings& settings) {
  std::string problem = validateCamera(camera);
  if (problem.empty()) problem = validateProjectionSettings(settings);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  return Projector(Checked{}, camera, settings);
}

Projector::Projector(Checked, const Camera& camera, const ProjectionSettings& settings)
    : camera_(camera), settings_(settings) {
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

void Projector::project(const Aabb* boxes, std::size_t count, BoxProjection* out) const {
  for (std::size_t i = 0; i < count; ++i) out[i] = projectWith(boxes[i], nullptr);
}

bool Projector::outsideFrustum(const Aabb& box) const {
  if (!validBox(box)) return false;
  Corners corners;
  clipCorners(box, corners);
  return outsideOnePlane(corners);
}

void Projector::outsideFrustum(const Aabb* boxes, std::size_t count, std::uint8_t* outside) const {
  for (std::size_t i = 0; i < count; ++i) outside[i] = outsideFrustum(boxes[i]);
}

BoxProjection Projector::visibleEverywhere(ProjectionClass cls) const {
  // Anything we cannot reason about is visible everywhere and drawn last.
  BoxProjection out;
  out.cls = cls;
  out.rect = viewportRect();
  out.near_key = near_key_;
  out.far_key = clear_key_;
  out.margin = 0;
  return out;
}

bool Projector::validBox(const Aabb& box) {
  return finite(box.min) && finite(box.max) && box.min.x <= box.max.x && box.min.y <= box.max.y &&
         box.min.z <= box.max.z;
}

namespace {

// One value per clip-space row (x, y, z, w), which the compiler keeps in vector registers.
struct Rows {
  double v[4];
};

inline Rows operator+(const Rows& a, const Rows& b) {
  Rows r;
  for (int k = 0; k < 4; ++k) r.v[k] = a.v[k] + b.v[k];
  return r;
}

// Column `j` of the column-major matrix m, times f.
inline Rows scaledColumn(const double* m, int j, double f) {
  Rows r;
  for (int k = 0; k < 4; ++k) r.v[k] = m[4 * j + k] * f;
  return r;
}

// sum = ((m0 a + m1 b) + m2 c) + m3 (m's columns) at the eight corners (bits a: 1, b: 2,
// c: 4) of the two values of a, b and c, into out[row][corner]: summed in the order of a
// four-term dot product, so each corner is bit for bit what the dot product gives, while
// each product is computed once.
void cornerSums(const double* m, const double a[2], const double b[2], const double c[2],
                double out[4][8]) {
  const Rows x[2] = {scaledColumn(m, 0, a[0]), scaledColumn(m, 0, a[1])};
  const Rows y[2] = {scaledColumn(m, 1, b[0]), scaledColumn(m, 1, b[1])};
  const Rows z[2] = {scaledColumn(m, 2, c[0]), scaledColumn(m, 2, c[1])};
  const Rows t = {{m[12], m[13], m[14], m[15]}};
  const Rows xy[4] = {x[0] + y[0], x[1] + y[0], x[0] + y[1], x[1] + y[1]};
  for (int i = 0; i < 8; ++i) {
    const Rows sum = (xy[i & 3] + z[i >> 2]) + t;
    for (int r = 0; r < 4; ++r) out[r][i] = sum.v[r];
  }
}

}  // namespace

void Projector::clipCorners(const Aabb& box, Corners& k) const {
  // Corner i (bits x: 1, y: 2, z: 4) relative to the render origin, in clip space.
  const double qx[2] = {double(box.min.x) - origin_.x, double(box.max.x) - origin_.x};
  const double qy[2] = {double(box.min.y) - origin_.y, double(box.max.y) - origin_.y};
  const double qz[2] = {double(box.min.z) - origin_.z, double(box.max.z) - origin_.z};
  cornerSums(render_, qx, qy, qz, k.c);
  for (int a = 0; a < 2; ++a) {
    k.q_abs[0][a] = std::fabs(qx[a]);
    k.q_abs[1][a] = std::fabs(qy[a]);
    k.q_abs[2][a] = std::fabs(qz[a]);
  }
}

void Projector::termMagnitudes(Corners& k) const {
  // S per corner (see "Why the margins have their values"): the same sums over |m| and
  // |q| (clipCorners() left |q| of the two values per axis in q_abs[axis][0..1]).
  const double ax[2] = {k.q_abs[0][0], k.q_abs[0][1]};
  const double ay[2] = {k.q_abs[1][0], k.q_abs[1][1]};
  const double az[2] = {k.q_abs[2][0], k.q_abs[2][1]};
  cornerSums(render_abs_, ax, ay, az, k.s);
}

bool Projector::outsideOnePlane(const Corners& k) const {
  // All eight corners beyond one plane of the view frustum: -w <= x, y <= w, near, far.
  int outside[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 8; ++i) {
    const double w = k.c[3][i];
    outside[0] += (w + k.c[0][i] < 0);
    outside[1] += (w - k.c[0][i] < 0);
    outside[2] += (w + k.c[1][i] < 0);
    outside[3] += (w - k.c[1][i] < 0);
    outside[4] += (planeDistance(near_plane_, k, i) < 0);
    outside[5] += (planeDistance(far_plane_, k, i) < 0);
  }
  for (int count : outside) {
    if (count == 8) return true;
  }
  return false;
}

int Projector::clipToNear(const Corners& k, ClipPoint* points, bool& crosses_near) const {
  // The part of the box on the visible side of the near plane: corners inside, plus
  // the points where edges cross the plane (LOG §5 clips the boxes in software too).
  double d[8];
  crosses_near = false;
  for (int i = 0; i < 8; ++i) {
    d[i] = planeDistance(near_plane_, k, i);
    crosses_near |= d[i] < 0;
  }
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    if (d[i] >= 0) points[count++] = k.point(i);
  }
  if (!crosses_near) return count;
  for (const auto& edge : kEdges) {
    const double da = d[edge[0]], db = d[edge[1]];
    if ((da < 0) == (db < 0)) continue;
    const ClipPoint a = k.point(edge[0]), b = k.point(edge[1]);
    const double t = da / (da - db);
    ClipPoint& p = points[count++];
    for (int r = 0; r < 4; ++r) {
      p.c[r] = a.c[r] + t * (b.c[r] - a.c[r]);
      // |.| of a convex combination is at most the combination of the |.|s.
      p.s[r] = a.s[r] + t * (b.s[r] - a.s[r]);
    }
  }
  return count;
}

bool Projector::windowBounds(const ClipPoint* points, int count, WindowBounds& b) const {
  const double half_w = 0.5 * camera_.width;
  const double half_h = 0.5 * camera_.height;
  for (int i = 0; i < count; ++i) {
    const ClipPoint& p = points[i];
    const double w = p.c[3];
    // Points of the clipped box lie in front of the eye for any sane projection; if
    // not (w <= 0, a projection that puts the near plane behind the eye), give up.
    if (!(w > 0)) return false;
    b.w_min = std::min(b.w_min, w), b.w_max = std::max(b.w_max, w);
    const double inv_w = 1.0 / w;
    const double xn = p.c[0] * inv_w, yn = p.c[1] * inv_w, zn = p.c[2] * inv_w;
    const double wx = (xn + 1.0) * half_w, wy = (yn + 1.0) * half_h;
    const double key = key_sign_ * (depth_scale_ * zn + depth_offset_);
    b.x_min = std::min(b.x_min, wx), b.x_max = std::max(b.x_max, wx);
    b.y_min = std::min(b.y_min, wy), b.y_max = std::max(b.y_max, wy);
    b.key_min = std::min(b.key_min, key), b.key_max = std::max(b.key_max, key);
    b.err_x = std::max(b.err_x, (p.s[0] + std::fabs(xn) * p.s[3]) * inv_w * half_w);
    b.err_y = std::max(b.err_y, (p.s[1] + std::fabs(yn) * p.s[3]) * inv_w * half_h);
    b.err_z = std::max(b.err_z, (p.s[2] + std::fabs(zn) * p.s[3]) * inv_w * depth_scale_);
  }
  return true;
}

PixelRect Projector::pixelRect(const WindowBounds& b, double widen_x, double widen_y) const {
  const std::int32_t w_px = static_cast<std::int32_t>(camera_.width);
  const std::int32_t h_px = static_cast<std::int32_t>(camera_.height);
  PixelRect rect;
  if (camera_.multisample) {
    // Every pixel the widened footprint touches.
    rect.x0 = clampToInt(std::floor(b.x_min - widen_x), 0, w_px);
    rect.x1 = clampToInt(std::ceil(b.x_max + widen_x), 0, w_px);
    rect.y0 = clampToInt(std::floor(b.y_min - widen_y), 0, h_px);
    rect.y1 = clampToInt(std::ceil(b.y_max + widen_y), 0, h_px);
  } else {
    // Pixels whose centre i + 0.5 lies in the widened footprint.
    rect.x0 = clampToInt(std::ceil(b.x_min - widen_x - 0.5), 0, w_px);
    rect.x1 = clampToInt(std::floor(b.x_max + widen_x - 0.5) + 1.0, 0, w_px);
    rect.y0 = clampToInt(std::ceil(b.y_min - widen_y - 0.5), 0, h_px);
    rect.y1 = clampToInt(std::floor(b.y_max + widen_y - 0.5) + 1.0, 0, h_px);
  }
  return rect;
}

BoxProjection Projector::projectWith(const Aabb& box, Extent* extent) const {
  if (!validBox(box)) return visibleEverywhere(ProjectionClass::Invalid);
  Corners corners;
  clipCorners(box, corners);
  BoxProjection out;
  if (outsideOnePlane(corners)) {
    out.cls = ProjectionClass::Outside;
    return out;
  }
  termMagnitudes(corners);
  ClipPoint points[8 + 12];
  bool crosses_near = false;
  const int count = clipToNear(corners, points, crosses_near);
  WindowBounds b;
  if (!windowBounds(points, count, b)) return visibleEverywhere(ProjectionClass::CrossesNear);
  if (!(b.x_min <= b.x_max) || !(b.y_min <= b.y_max) || !(b.key_min <= b.key_max) ||
      !std::isfinite(b.err_z)) {
    return visibleEverywhere(ProjectionClass::Invalid);
  }

  const double k = settings_.render_error_ulps * kUnitRoundoff;
  const double widen_x = k * b.err_x + snap_px_;
  const double widen_y = k * b.err_y + snap_px_;
  if (extent) *extent = {widen_x, widen_y, b.w_min, b.w_max};
  out.rect = pixelRect(b, widen_x, widen_y);

  const double far_plane_key = clear_key_;
  const double key_min = std::clamp(b.key_min, double(near_key_), far_plane_key);
  const double key_max = std::clamp(b.key_max, double(near_key_), far_plane_key);
  const double largest_key = std::max(std::fabs(key_min), std::fabs(key_max));
  out.near_key = roundDown(key_min);
  out.far_key = roundUp(key_max);
  out.margin = roundUp(quantisation_ + k * (b.err_z + largest_key));
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
