#include "logrid/projection.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "projection_isa.hpp"
#include "rounding.hpp"

#include "logrid/error.hpp"

namespace logrid {
namespace {

using detail::roundDown;
using detail::roundUp;

// Clamps an integral-valued double into [lo, hi] before converting it (NaN: lo). As
// selects, not branches: whether a box reaches the viewport's edge is data, not pattern.
std::int32_t clampToInt(double v, std::int32_t lo, std::int32_t hi) {
  const double above_lo = v > lo ? v : double(lo);
  return static_cast<std::int32_t>(above_lo < hi ? above_lo : double(hi));
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

  // A clip coordinate sums three products of a matrix element and a corner coordinate
  // relative to the origin (at most the largest float plus the origin's largest) and a
  // fourth element; far below the largest double, rounding cannot take it to infinity.
  const double q_max = double(std::numeric_limits<float>::max()) +
                       std::max({std::fabs(origin_.x), std::fabs(origin_.y), std::fabs(origin_.z)});
  clip_finite_ = true;
  for (int r = 0; r < 4; ++r) {
    const double bound =
        (render_abs_[r] + render_abs_[4 + r] + render_abs_[8 + r]) * q_max + render_abs_[12 + r];
    clip_finite_ = clip_finite_ && bound < 1e300;
  }

  depth_scale_ = zero_to_one ? 1.0 : 0.5;
  depth_offset_ = zero_to_one ? 0.0 : 0.5;
  key_sign_ = reversed ? -1.0 : 1.0;
  quantisation_ = quantisationStep(camera.depth.format) * settings.quantisation_scale;
  snap_px_ = settings.subpixel_bits >= 16 ? 0.0 : std::ldexp(0.5, -settings.subpixel_bits);
  half_width_ = 0.5 * camera.width;
  half_height_ = 0.5 * camera.height;
  error_scale_ = settings.render_error_ulps * kUnitRoundoff;
  clear_key_ = logrid::clearKey(camera.depth);
  near_key_ = logrid::nearPlaneKey(camera.depth);
}

// The batch kernels
// -----------------
// project(boxes, count, out) and outsideFrustum(boxes, count, outside) compute what
// projectWith() computes, laid out as structure of arrays over a box's eight corners
// (a value per corner, corner i with bits x: 1, y: 2, z: 4), so that each step is a few
// vector operations instead of eight scalar ones. Every value is the one the reference
// path computes, by the same operations in the same order: the corner sums as
// cornerSums() adds them, the plane distances as planeDistance(), the window
// coordinates and error terms as windowBounds(). Only the reductions over the corners
// (the smallest and largest window x, y and key, the largest errors) are taken in
// another order, a tree instead of corner by corner, and they give the same values:
//   * a NaN value is skipped in both (std::min(acc, v) keeps acc when v is NaN; the tree
//     first replaces a NaN by the starting value, +-infinity or 0);
//   * the minimum and maximum of doubles that are not NaN do not depend on the order,
//     except which of +0 and -0 is kept when both occur as the extreme. Neither order
//     can meet both: window x and y are (ndc + 1) * half, and a sum that is zero is +0
//     (round to nearest), so they are never -0; a key is +-(depth_scale z + offset),
//     whose inner sum is +0 where it is zero (a zero offset adds +0), so every zero key
//     is +0 with the standard convention and -0 with the reversed one; the error terms
//     are sums of products of magnitudes, never -0.
// A box that reaches the near plane (its clipped outline has up to 20 points) takes the
// reference path; tests/unit/projection_test.cpp compares both paths field by field.
//
// Built with GCC's vector extension (other compilers run the reference path box by box),
// the kernels are compiled twice on x86-64, each with every step inlined (flatten): for
// the baseline (SSE2) and for AVX2; projectionIsa() (projection_isa.hpp) picks one at
// the first batch by what the CPU reports, and a test can ask for either. Not with
// target_clones: its resolver runs while the program is being loaded, before a
// sanitizer's runtime is up, and an instrumented resolver crashes there. Not for FMA: a
// fused multiply-add rounds once where the reference rounds twice, and the answers would
// change (logrid_core is compiled with -ffp-contract=off for the same reason,
// log/CMakeLists.txt).
#if defined(__GNUC__) && !defined(__clang__)
#define LOGRID_PROJECTION_VECTORS 1
#else
#define LOGRID_PROJECTION_VECTORS 0
#endif
#if LOGRID_PROJECTION_VECTORS && defined(__x86_64__)
#define LOGRID_PROJECTION_AVX2 1
#else
#define LOGRID_PROJECTION_AVX2 0
#endif

struct Projector::Kernel {
  // The steps projectWith() shares with the batch kernels.
  static bool validBox(const Aabb& box) {
    return finite(box.min) && finite(box.max) && box.min.x <= box.max.x && box.min.y <= box.max.y &&
           box.min.z <= box.max.z;
  }

  // The finishing steps that the batch kernels take four values at a time (Lanes,
  // below), here one by one: clampToInt() of the rectangle's edges (x0, y0, x1, y1) into
  // the viewport, and roundUp() of four bounds.
  struct Scalar {
    static PixelRect clampRect(const double e[4], std::int32_t w_px, std::int32_t h_px) {
      return {clampToInt(e[0], 0, w_px), clampToInt(e[1], 0, h_px), clampToInt(e[2], 0, w_px),
              clampToInt(e[3], 0, h_px)};
    }
    static void roundUp4(const double v[4], float out[4]) {
      for (int i = 0; i < 4; ++i) out[i] = roundUp(v[i]);
    }
  };

  template <class Finish>
  static PixelRect pixelRect(const Projector& p, const WindowBounds& b, double widen_x,
                             double widen_y) {
    const std::int32_t w_px = static_cast<std::int32_t>(p.camera_.width);
    const std::int32_t h_px = static_cast<std::int32_t>(p.camera_.height);
    if (p.camera_.multisample) {
      // Every pixel the widened footprint touches.
      const double e[4] = {std::floor(b.x_min - widen_x), std::floor(b.y_min - widen_y),
                           std::ceil(b.x_max + widen_x), std::ceil(b.y_max + widen_y)};
      return Finish::clampRect(e, w_px, h_px);
    }
    // Pixels whose centre i + 0.5 lies in the widened footprint.
    const double e[4] = {std::ceil(b.x_min - widen_x - 0.5), std::ceil(b.y_min - widen_y - 0.5),
                         std::floor(b.x_max + widen_x - 0.5) + 1.0,
                         std::floor(b.y_max + widen_y - 0.5) + 1.0};
    return Finish::clampRect(e, w_px, h_px);
  }

  // What projectWith() answers from the window bounds of a box not outside the frustum,
  // written field by field into `out` (the batch kernel writes straight into its array:
  // a whole BoxProjection built and copied costs as much as the rest of the kernel).
  template <class Finish = Scalar>
  static void fromBounds(const Projector& p, const WindowBounds& b, bool crosses_near,
                         Extent* extent, BoxProjection& out) {
    if (!(b.x_min <= b.x_max) || !(b.y_min <= b.y_max) || !(b.key_min <= b.key_max) ||
        !std::isfinite(b.err_z)) {
      out = p.visibleEverywhere(ProjectionClass::Invalid);
      return;
    }

    const double k = p.error_scale_;
    const double widen_x = k * b.err_x + p.snap_px_;
    const double widen_y = k * b.err_y + p.snap_px_;
    if (extent) *extent = {widen_x, widen_y, b.w_min, b.w_max};
    const PixelRect rect = pixelRect<Finish>(p, b, widen_x, widen_y);
    out.rect = rect;

    const double far_plane_key = p.clear_key_;
    const double key_min = std::clamp(b.key_min, double(p.near_key_), far_plane_key);
    const double key_max = std::clamp(b.key_max, double(p.near_key_), far_plane_key);
    const double largest_key = std::max(std::fabs(key_min), std::fabs(key_max));
    const double up[4] = {key_max, p.quantisation_ + k * (b.err_z + largest_key), widen_x, widen_y};
    float rounded[4];
    Finish::roundUp4(up, rounded);
    out.far_key = rounded[0];
    out.margin = rounded[1];
    out.widen_x = rounded[2];
    out.widen_y = rounded[3];

    if (crosses_near) {
      out.cls = ProjectionClass::CrossesNear;
      out.near_key = p.near_key_;
    } else {
      out.near_key = roundDown(key_min);
      // Covering no pixel centre, the box draws nothing.
      out.cls = rect.empty() ? ProjectionClass::Outside : ProjectionClass::Inside;
    }
  }

#if LOGRID_PROJECTION_VECTORS
  // Every function below is inlined into the kernels (flatten), so no vector crosses a
  // call and the ABI note on passing them does not apply. GCC reports it at the end of
  // the file, so it stays off to the end of the file.
#pragma GCC diagnostic ignored "-Wpsabi"
  // Four lanes of doubles (GCC's vector extension: one AVX register, or two SSE2
  // registers in the baseline clone); a value of the eight corners is two of them,
  // corners 0-3 and 4-7. Lane-wise operations round exactly as the scalar ones.
  using V4 = double __attribute__((vector_size(32)));
  using M4 = decltype(V4{} < V4{});  // a lane mask: all bits set or none

  static V4 splat(double x) { return V4{x, x, x, x}; }
  static V4 magnitude(const V4& v) { return (V4)((M4)v & ~(M4)splat(-0.0)); }
  // Any lane, all lanes of a mask: the two halves combined in the vector first.
  static M4 swapHalves(const M4& m) { return __builtin_shuffle(m, M4{2, 3, 0, 1}); }
  static bool anyLane(const M4& m) {
    const M4 x = m | swapHalves(m);
    return (x[0] | x[1]) != 0;
  }
  static bool allLanes(const M4& m) {
    const M4 x = m & swapHalves(m);
    return (x[0] & x[1]) != 0;
  }

  // Clip row r of the eight corners: ((m[r] qx + m[4 + r] qy) + m[8 + r] qz) + m[12 + r],
  // summed as cornerSums() sums it.
  static void cornerRows(const double* m, const double qx[2], const double qy[2],
                         const double qz[2], V4 out[4][2]) {
    const V4 px = {qx[0], qx[1], qx[0], qx[1]};
    const V4 py = {qy[0], qy[0], qy[1], qy[1]};
    for (int r = 0; r < 4; ++r) {
      const V4 xy = splat(m[r]) * px + splat(m[4 + r]) * py;
      out[r][0] = (xy + splat(m[8 + r] * qz[0])) + splat(m[12 + r]);
      out[r][1] = (xy + splat(m[8 + r] * qz[1])) + splat(m[12 + r]);
    }
  }

  // The box's corners relative to the render origin (q) and their clip positions (c).
  struct Box {
    double qx[2], qy[2], qz[2];
    V4 c[4][2];
    V4 to_near[2];  // the corners' distances to the near plane (compared with 0 only)
  };

  static void clip(const Projector& p, const Aabb& box, Box& k) {
    k.qx[0] = double(box.min.x) - p.origin_.x, k.qx[1] = double(box.max.x) - p.origin_.x;
    k.qy[0] = double(box.min.y) - p.origin_.y, k.qy[1] = double(box.max.y) - p.origin_.y;
    k.qz[0] = double(box.min.z) - p.origin_.z, k.qz[1] = double(box.max.z) - p.origin_.z;
    cornerRows(p.render_, k.qx, k.qy, k.qz, k.c);
  }

  static V4 planeDistance(const double* plane, const Box& k, int h) {
    return splat(plane[0]) * k.c[0][h] + splat(plane[1]) * k.c[1][h] + splat(plane[2]) * k.c[2][h] +
           splat(plane[3]) * k.c[3][h];
  }

  // planeDistance() of the near or the far plane, whose x and y coefficients are 0,
  // where the clip coordinates are finite (clip_finite_): 0 x and 0 y are zeros then,
  // which change the sum at most in the sign of a zero result, and the kernels only
  // compare these distances with 0.
  static V4 zwDistance(const double* plane, const Box& k, int h) {
    return splat(plane[2]) * k.c[2][h] + splat(plane[3]) * k.c[3][h];
  }

  // outsideOnePlane(): all eight corners beyond one plane; fills k.to_near.
  static bool outside(const Projector& p, Box& k) {
    const V4 zero = splat(0.0);
    M4 beyond[6];
    for (int h = 0; h < 2; ++h) {
      V4 to_far;
      if (p.clip_finite_) {
        k.to_near[h] = zwDistance(p.near_plane_, k, h);
        to_far = zwDistance(p.far_plane_, k, h);
      } else {
        k.to_near[h] = planeDistance(p.near_plane_, k, h);
        to_far = planeDistance(p.far_plane_, k, h);
      }
      const V4 w = k.c[3][h], x = k.c[0][h], y = k.c[1][h];
      const M4 m[6] = {w + x < zero, w - x < zero,        w + y < zero,
                       w - y < zero, k.to_near[h] < zero, to_far < zero};
      for (int j = 0; j < 6; ++j) beyond[j] = h == 0 ? m[j] : beyond[j] & m[j];
    }
    return anyAllLanes(beyond);
  }

  // Whether all four lanes of one of six masks are set: the six reduced together by
  // shuffles (lane moves within the vectors, or the choice of a register in the baseline
  // clone), not lane by lane through the scalar registers. Pairs of masks first, each
  // lane's low and high half together, (m0 m1), (m2 m3), (m4 m5); then those.
  static bool anyAllLanes(const M4 m[6]) {
    using Index = M4;
    const Index lows = {0, 1, 4, 5}, highs = {2, 3, 6, 7};
    const M4 t0 = __builtin_shuffle(m[0], m[1], lows) & __builtin_shuffle(m[0], m[1], highs);
    const M4 t1 = __builtin_shuffle(m[2], m[3], lows) & __builtin_shuffle(m[2], m[3], highs);
    const M4 t2 = __builtin_shuffle(m[4], m[5], lows) & __builtin_shuffle(m[4], m[5], highs);
    // All of m0, m2, m1, m3 (in these lanes), and all of m4, m4, m5, m5.
    const M4 u =
        __builtin_shuffle(t0, t1, Index{0, 4, 2, 6}) & __builtin_shuffle(t0, t1, Index{1, 5, 3, 7});
    const M4 v = t2 & __builtin_shuffle(t2, Index{1, 0, 3, 2});
    return anyLane(u | v);
  }

  // Scalar's finishing steps, four lanes at a time, each lane as the scalar step:
  // the clamps as selects (NaN to 0, as clampToInt()) and the truncating conversion; the
  // conversion to float rounds each lane as the scalar one does, and the step to the next
  // float up is roundUp()'s arithmetic on the bit patterns (rounding.hpp), taken where
  // the float lies below the value.
  using F4 = float __attribute__((vector_size(16)));
  using U4 = std::uint32_t __attribute__((vector_size(16)));
  using I4 = std::int32_t __attribute__((vector_size(16)));
  struct Lanes {
    static PixelRect clampRect(const double e[4], std::int32_t w_px, std::int32_t h_px) {
      const V4 x = {e[0], e[1], e[2], e[3]}, zero = splat(0.0);
      const V4 hi = {double(w_px), double(h_px), double(w_px), double(h_px)};
      const V4 above_lo = x > zero ? x : zero;
      const I4 r = __builtin_convertvector(above_lo < hi ? above_lo : hi, I4);
      return {r[0], r[1], r[2], r[3]};
    }
    static void roundUp4(const double v[4], float out[4]) {
      const V4 x = {v[0], v[1], v[2], v[3]};
      const F4 f = __builtin_convertvector(x, F4);
      const U4 take = (U4) __builtin_convertvector(__builtin_convertvector(f, V4) < x, I4);
      const U4 bits_f = (U4)f;
      const U4 bits_g = (U4)(f + F4{0, 0, 0, 0});  // -0 becomes +0
      const U4 up = bits_g + 1 - ((bits_g >> 31) << 1);
      const F4 r = (F4)(bits_f + ((up - bits_f) & take));
      std::memcpy(out, &r, sizeof r);
    }
  };

  // std::min(acc, v) and std::max(acc, v), as windowBounds() accumulates, lane-wise.
  static V4 lower(const V4& acc, const V4& v) { return v < acc ? v : acc; }  // minpd's rule
  static V4 upper(const V4& acc, const V4& v) { return acc < v ? v : acc; }
  static double lower(double acc, double v) { return v < acc ? v : acc; }
  static double upper(double acc, double v) { return acc < v ? v : acc; }
  // The least and the greatest of the eight values (two halves) as the accumulation from
  // kInf (least) or `start` gives them: NaNs skipped (see the reduction argument above).
  static double least(const V4 v[2]) {
    const V4 inf = splat(kInf);
    const V4 m = lower(lower(inf, v[0]), v[1]);
    return lower(lower(m[0], m[2]), lower(m[1], m[3]));
  }
  static double greatest(const V4 v[2], double start) {
    const V4 s = splat(start);
    const V4 m = upper(upper(s, v[0]), v[1]);
    return upper(upper(m[0], m[2]), upper(m[1], m[3]));
  }

  // windowBounds() over the eight corners of a box in front of the near plane; false
  // where a corner lies at or behind the eye.
  static bool windowBounds(const Projector& p, const Box& k, WindowBounds& b) {
    const V4 zero = splat(0.0);
    if (!allLanes((k.c[3][0] > zero) & (k.c[3][1] > zero))) return false;
    const double ax[2] = {std::fabs(k.qx[0]), std::fabs(k.qx[1])};
    const double ay[2] = {std::fabs(k.qy[0]), std::fabs(k.qy[1])};
    const double az[2] = {std::fabs(k.qz[0]), std::fabs(k.qz[1])};
    V4 s[4][2];
    cornerRows(p.render_abs_, ax, ay, az, s);
    const V4 one = splat(1.0), half_w = splat(p.half_width_), half_h = splat(p.half_height_);
    const V4 depth_scale = splat(p.depth_scale_);
    V4 wx[2], wy[2], key[2], ex[2], ey[2], ez[2];
    for (int h = 0; h < 2; ++h) {
      const V4 inv_w = one / k.c[3][h];
      const V4 xn = k.c[0][h] * inv_w, yn = k.c[1][h] * inv_w, zn = k.c[2][h] * inv_w;
      wx[h] = (xn + one) * half_w;
      wy[h] = (yn + one) * half_h;
      key[h] = splat(p.key_sign_) * (depth_scale * zn + splat(p.depth_offset_));
      ex[h] = (s[0][h] + magnitude(xn) * s[3][h]) * inv_w * half_w;
      ey[h] = (s[1][h] + magnitude(yn) * s[3][h]) * inv_w * half_h;
      ez[h] = (s[2][h] + magnitude(zn) * s[3][h]) * inv_w * depth_scale;
    }
    b.x_min = least(wx), b.x_max = greatest(wx, -kInf);
    b.y_min = least(wy), b.y_max = greatest(wy, -kInf);
    b.key_min = least(key), b.key_max = greatest(key, -kInf);
    b.err_x = greatest(ex, 0.0), b.err_y = greatest(ey, 0.0), b.err_z = greatest(ez, 0.0);
    return true;  // w_min and w_max stay unset: only queryBox() needs them
  }

  static void project(const Projector& p, const Aabb* boxes, std::size_t count,
                      BoxProjection* out) {
    for (std::size_t i = 0; i < count; ++i) {
      const Aabb& box = boxes[i];
      if (!validBox(box)) {
        out[i] = p.visibleEverywhere(ProjectionClass::Invalid);
        continue;
      }
      Box k;
      clip(p, box, k);
      if (outside(p, k)) {
        out[i] = BoxProjection{};
        out[i].cls = ProjectionClass::Outside;
        continue;
      }
      // Clipped by the reference path; also where a distance is NaN (a clip coordinate
      // overflowed), as clipToNear() leaves such a corner out of the outline.
      const V4 zero = splat(0.0);
      if (!allLanes((k.to_near[0] >= zero) & (k.to_near[1] >= zero))) {
        out[i] = p.projectWith(box, nullptr);
        continue;
      }
      WindowBounds b;
      if (windowBounds(p, k, b)) {
        fromBounds<Lanes>(p, b, false, nullptr, out[i]);
      } else {
        out[i] = p.visibleEverywhere(ProjectionClass::CrossesNear);
      }
    }
  }

  static void outsideFrustum(const Projector& p, const Aabb* boxes, std::size_t count,
                             std::uint8_t* result) {
    for (std::size_t i = 0; i < count; ++i) {
      if (!validBox(boxes[i])) {
        result[i] = 0;
        continue;
      }
      Box k;
      clip(p, boxes[i], k);
      result[i] = outside(p, k);
    }
  }

  // The entry points, one per instruction set, each with the whole kernel inlined.
  __attribute__((flatten)) static void projectBaseline(const Projector& p, const Aabb* boxes,
                                                       std::size_t count, BoxProjection* out) {
    project(p, boxes, count, out);
  }
  __attribute__((flatten)) static void outsideBaseline(const Projector& p, const Aabb* boxes,
                                                       std::size_t count, std::uint8_t* result) {
    outsideFrustum(p, boxes, count, result);
  }
#if LOGRID_PROJECTION_AVX2
  __attribute__((target("avx2"), flatten)) static void projectAvx2(const Projector& p,
                                                                   const Aabb* boxes,
                                                                   std::size_t count,
                                                                   BoxProjection* out) {
    project(p, boxes, count, out);
  }
  __attribute__((target("avx2"), flatten)) static void outsideAvx2(const Projector& p,
                                                                   const Aabb* boxes,
                                                                   std::size_t count,
                                                                   std::uint8_t* result) {
    outsideFrustum(p, boxes, count, result);
  }
#endif
#else
  // Other compilers (Clang among them, whose vectors lack the conditional operator used
  // above): the reference path, box by box.
  static void project(const Projector& p, const Aabb* boxes, std::size_t count,
                      BoxProjection* out) {
    for (std::size_t i = 0; i < count; ++i) out[i] = p.projectWith(boxes[i], nullptr);
  }
  static void outsideFrustum(const Projector& p, const Aabb* boxes, std::size_t count,
                             std::uint8_t* result) {
    for (std::size_t i = 0; i < count; ++i) result[i] = p.outsideFrustum(boxes[i]);
  }
  static void projectBaseline(const Projector& p, const Aabb* boxes, std::size_t count,
                              BoxProjection* out) {
    project(p, boxes, count, out);
  }
  static void outsideBaseline(const Projector& p, const Aabb* boxes, std::size_t count,
                              std::uint8_t* result) {
    outsideFrustum(p, boxes, count, result);
  }
#endif
};

BoxProjection Projector::project(const Aabb& box) const { return projectWith(box, nullptr); }

bool Projector::outsideFrustum(const Aabb& box) const {
  if (!Kernel::validBox(box)) return false;
  Corners corners;
  clipCorners(box, corners);
  return outsideOnePlane(corners);
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
  const double half_w = half_width_;
  const double half_h = half_height_;
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

BoxProjection Projector::projectWith(const Aabb& box, Extent* extent) const {
  if (!Kernel::validBox(box)) return visibleEverywhere(ProjectionClass::Invalid);
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
  Kernel::fromBounds(*this, b, crosses_near, extent, out);
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

void Projector::project(const Aabb* boxes, std::size_t count, BoxProjection* out) const {
#if LOGRID_PROJECTION_AVX2
  if (detail::projectionIsa() == detail::ProjectionIsa::Avx2) {
    return Kernel::projectAvx2(*this, boxes, count, out);
  }
#endif
  Kernel::projectBaseline(*this, boxes, count, out);
}

void Projector::outsideFrustum(const Aabb* boxes, std::size_t count, std::uint8_t* outside) const {
#if LOGRID_PROJECTION_AVX2
  if (detail::projectionIsa() == detail::ProjectionIsa::Avx2) {
    return Kernel::outsideAvx2(*this, boxes, count, outside);
  }
#endif
  Kernel::outsideBaseline(*this, boxes, count, outside);
}

namespace detail {
namespace {

ProjectionIsa widestProjectionIsa() {
#if LOGRID_PROJECTION_AVX2
  if (__builtin_cpu_supports("avx2")) return ProjectionIsa::Avx2;
#endif
  return ProjectionIsa::Baseline;
}

// The set asked for by a test; relaxed: only the value matters, not what it orders.
std::atomic<int> forced_isa{-1};

}  // namespace

ProjectionIsa projectionIsa() {
  static const ProjectionIsa widest = widestProjectionIsa();
  const int forced = forced_isa.load(std::memory_order_relaxed);
  return forced < 0 ? widest : static_cast<ProjectionIsa>(forced);
}

bool projectionIsaAvailable(ProjectionIsa isa) {
  return isa == ProjectionIsa::Baseline || isa == widestProjectionIsa();
}

bool forceProjectionIsa(ProjectionIsa isa) {
  if (!projectionIsaAvailable(isa)) return false;
  forced_isa.store(static_cast<int>(isa), std::memory_order_relaxed);
  return true;
}

void resetProjectionIsa() { forced_isa.store(-1, std::memory_order_relaxed); }

}  // namespace detail

}  // namespace logrid
