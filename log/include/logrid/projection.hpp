// Conservative projection of a world-space box to a pixel rectangle and a depth-key
// range, with the margins that make the answer hold on real rasterisers.
//
// What "conservative" means here: for every fragment that any geometry inside the box
// can produce when a renderer draws it with the camera's matrix,
//   * the fragment's pixel lies inside `rect`, and
//   * the fragment's depth key, after the depth buffer has stored it, is at least
//     `near_key - margin` and at most `far_key + margin`.
// Everything is computed in double precision and rounded outwards.
//
// Why the margins have their values
// ---------------------------------
// A renderer does not compute what logrid computes: it transforms vertices in single
// precision, divides by w, snaps to a sub-pixel grid, interpolates depth across the
// triangle and converts the result to the depth format. logrid bounds each step:
//
//   u = 2^-24, the unit roundoff of float.
//
// 1. Depth quantisation (`quantisationStep()`): a unorm buffer stores round(d * (2^n - 1))
//    (or a truncation; GL allows either), so a stored value can sit one step on either
//    side of the fragment depth: one step is 1/65535 for D16 and 1/16777215 for D24.
//    D32F stores the float fragment depth exactly: no step. Reading a D24 value back as
//    float rounds once more (u relative), which the relative term below covers.
// 2. Vertex transform and division (`kRenderErrorUlps`): clip z and w are dot products
//    of four float terms computed from a float matrix; each has an absolute error of a
//    few u times the sum of the magnitudes of its terms, S_z and S_w. After the division
//    by w, the error in NDC depth is about (S_z + |z_ndc| S_w) / w, times u and a small
//    constant. S_z and S_w are evaluated per box corner with the geometry measured from
//    Camera::render_origin, so a renderer that draws far from that point gets a
//    proportionally larger margin, and one that renders camera-relative gets a small one.
// 3. Interpolation: depth at a pixel centre is interpolated from the vertex depths with
//    plane equations or barycentrics in float: an absolute error of a few u times the
//    largest |depth| of the triangle, bounded by the box's largest |key|.
// 4. Sub-pixel snapping (`subpixel_bits`) and the x/y analogue of (2) widen the pixel
//    rectangle: a vertex moves by up to half a sub-pixel step (GL requires at least 4
//    sub-pixel bits, so 1/32 pixel), plus the float error of its window x and y.
//
// kRenderErrorUlps = 32 bounds (2) and (3) together: the float matrix (1 u per element),
// two four-term dot products (4 u each), the division (1 u), the viewport transform
// (2 u), the interpolation (4 u) and the conversion of the fragment depth (1 u) sum to
// about 17 u; 32 leaves a factor of two for renderers that multiply model, view and
// projection separately. The resulting margin is
//
//   margin = quantisationStep(format) + kRenderErrorUlps * u * (E + max|key|)
//   E      = max over the box corners of (S_z + |z_ndc| S_w) / w * window scale
//
// which is about 3.8e-6 for 32F standard depth at unit scale (E and the key both about
// 1), 6e-8 for reversed 32F at the same distance (keys and E shrink with distance), and
// 1.9e-5 for D16 (the step, 1.53e-5, plus the same render error).
//
// Each term is needed. tests/unit/margin_test.cpp (exact arithmetic, and the software
// rasteriser's float pipeline) and tests/gl/margin_gl_test.cpp (the GL rasteriser) shrink
// one term at a time and find a box that the renderer shows but logrid then culls; with
// the defaults the same box is drawn. The box always passes the depth test because of
// what is already in the buffer at its own depth: a face coplanar with an occluder, or a
// hair behind it but stored as the same value, drawn with GL_LEQUAL (GL_GEQUAL reversed).
//   (1) quantisation_scale = 0. D16: a wall stored as 30000 / 65535 and a box 0.9 step
//       behind it, stored as the same value; the box's nearest key lies 0.45 step
//       (6.9e-6) beyond the stored value, more than the rest of the margin (4.1e-6), and
//       every method culls it. D24 shows it with reversed depth far away (window depth
//       1e-3: the rest of the margin is 6e-9, a step 6e-8). A D24 step is about u, so it
//       matters only where E and the key are both small: reversed depth far away, or a
//       zero-to-one orthographic projection right at its near plane. With a standard
//       perspective E is at least about 1/2 and the render-error term alone is 16 D24
//       steps or more (4e-6 and up): there shrinking the D24 term changes no answer.
//   (2) render_error_ulps = 0. Coplanar duplicates of walls at 64 depths: the float
//       pipeline puts 3 or 4 of the walls in front of their exact depth (by one float step,
//       6e-8, camera-relative; by up to 9e-7 in world space 1e4 from the origin), and their
//       duplicates are culled. On llvmpipe 0.5 ulps would have kept them all.
//   (3) is not shown apart from (2): the one setting render_error_ulps covers both, and
//       the planes above have constant depth, which llvmpipe interpolates exactly; the
//       errors found are (2)'s.
//   (4) subpixel_bits = 16 (no widening). A left edge 3/8 of a sub-pixel step right of a
//       column of pixel centres snaps onto them and covers them (the top-left fill rule
//       of llvmpipe and GPUs: a left edge includes the centres it passes through), while
//       the exact footprint does not: a box seen only through that column, the rest being
//       behind an occluder, is culled. The default, 1/32 pixel, covers every rasteriser GL
//       allows; llvmpipe (8 bits) needs 1/512.
//
// Query boxes (Projector::queryBox)
// ---------------------------------
// A hardware occlusion query draws a box's faces against the depth buffer and counts
// the samples that pass (occlusion_queries.hpp). The faces are rasterised like any
// geometry, so the same four errors apply to them as to the geometry inside, and the
// query must show a sample wherever the geometry would show one:
//   * coverage (4): the geometry's fragments lie within the box's exact footprint
//     widened by (widen_x, widen_y) pixels, the box's own rasterised faces cover that
//     footprint shrunk by as much. queryBox() widens the box in world space by delta on
//     every axis, so that its exact footprint grows by at least r = 2 hypot(widen_x,
//     widen_y) + kQueryWidenPixels around every point of the box's footprint. Derivation:
//     with a, b the pixel-scaled x and y rows of the clip transform and d its w row, a
//     world displacement v with d.v = 0 keeps w and moves the window position by
//     (a.v, b.v) / w. Over |v| <= delta, v in the plane normal to d, those offsets fill an
//     ellipse containing the disc of radius delta sigma / w, where sigma^2 is the smaller
//     eigenvalue of the Gram matrix of a and b projected onto that plane. The widened box
//     contains every such p + v (|v| <= delta on each axis), so
//       delta = r * w_max / sigma,  w_max the largest clip w of the box's corners.
//     (Orthographic projections have d = 0: the plane is all of space.)
//   * depth (1)-(3): where the geometry's fragment shows, the widened box's faces have a
//     fragment no farther than the geometry point p + v above; v changes the depth by at
//     most depth_scale |c'| delta / w_min, c' the z row projected like a and b (0 for a
//     perspective, whose z and w rows are parallel). Both the faces and the geometry are
//     then rendered with errors bounded by the widened box's margin, so each face fragment
//     is moved nearer by depth_bias = 2 margin + depth_scale |c'| delta / w_min.
// A box whose biased faces would reach the near plane gets no query box (it is visible
// without a query, as a box crossing the near plane is). kQueryWidenPixels is a safety
// allowance beyond the proof's 1/32 pixel: a fragment extrapolated from a grazing
// triangle just outside its edge lies in front of the box's side face by its slope times
// that distance, which no depth margin bounds (docs/ANALYSIS.md, "Depth-extrapolation
// artifacts"); half a pixel of widening moves the side faces nearer to cover it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid {

inline constexpr double kUnitRoundoff = 1.0 / 16777216.0;  // 2^-24
inline constexpr double kRenderErrorUlps = 32.0;
inline constexpr double kQueryWidenPixels = 0.5;  // see "Query boxes" above

// One quantisation step of a depth format in window depth (see (1) above).
inline constexpr double quantisationStep(DepthFormat format) {
  switch (format) {
    case DepthFormat::D16: return 1.0 / 65535.0;
    case DepthFormat::D24: return 1.0 / 16777215.0;
    case DepthFormat::D32F: return 0.0;
  }
  return 1.0 / 65535.0;
}

// Tuning of the projection. The defaults are the safe ones; shrinking them is what the
// margin tests do to show each term is necessary.
struct ProjectionSettings {
  double render_error_ulps = kRenderErrorUlps;
  double quantisation_scale = 1.0;  // multiplies quantisationStep(format)
  int subpixel_bits = 4;            // GL's minimum; llvmpipe and current GPUs have 8;
                                    // 16 means no widening at all
};

// Returns an empty string if the settings are usable (subpixel_bits in [0, 16], the two
// scales finite and >= 0), else a message naming the field and its value.
std::string validateProjectionSettings(const ProjectionSettings& settings);

// Why a box's test result is forced rather than decided by the grid.
enum class ProjectionClass : std::uint8_t {
  Inside,       // in front of the near plane: the grid decides
  CrossesNear,  // reaches the near plane or the eye: always visible
  Outside,      // outside the view frustum, or covering no pixel centre: culled
  Invalid,      // NaN/infinite/inverted box: always visible, and counted
};

struct BoxProjection {
  ProjectionClass cls = ProjectionClass::Invalid;
  PixelRect rect;      // pixels the box may cover, clipped to the viewport
  float near_key = 0;  // lower bound of the keys of the box's fragments (rounded down)
  float far_key = 0;   // upper bound of the keys of the box's fragments (rounded up)
  float margin = 0;    // depth margin for this box (see above)
  // How far (pixels, per axis) a vertex of the box's geometry may land from its exact
  // window position on a GL rasteriser: sub-pixel snapping plus the float error of (4)
  // above. `rect` is the footprint widened by these.
  float widen_x = 0;
  float widen_y = 0;

  // The key a depth buffer value must reach for the box to show in front of it: a
  // pixel whose stored key is >= this may let the box's geometry through.
  float occlusionThreshold() const { return near_key - margin; }
};

// What a box query draws (see "Query boxes" above).
struct QueryBox {
  Aabb box;              // world space; contains the tested box
  float depth_bias = 0;  // key units (>= 0) every fragment of the faces is moved nearer by
};

// Projects boxes for one camera. Construction validates the camera and the settings
// (ErrorCode::InvalidArgument with validateCamera()'s or validateProjectionSettings()'s
// message) and precomputes per-frame constants; project() is then a pure function, safe
// to call from several threads.
class Projector {
 public:
  // The result form (error.hpp): the projector, or the problem.
  static Result<Projector> create(const Camera& camera, const ProjectionSettings& settings = {});
  // The throwing form: throws logrid::Error where create() fails.
  explicit Projector(const Camera& camera, const ProjectionSettings& settings = {});

  BoxProjection project(const Aabb& box) const;
  // The same for `count` boxes (a node's children, say): out[i] = project(boxes[i]).
  void project(const Aabb* boxes, std::size_t count, BoxProjection* out) const;
  // Frustum only: true where project(box) finds all eight corners beyond one plane of
  // the view frustum (and answers Outside without projecting). The first, cheap part of
  // project(); an invalid box is never outside.
  bool outsideFrustum(const Aabb& box) const;
  void outsideFrustum(const Aabb* boxes, std::size_t count, std::uint8_t* outside) const;
  // The box a hardware occlusion query draws for `box`, or nothing where no query can
  // answer conservatively (the box does not project Inside, or the widened, biased faces
  // would reach the near plane): such a box is visible without a query.
  std::optional<QueryBox> queryBox(const Aabb& box) const;

  const Camera& camera() const { return camera_; }
  // Window depth = depthScale() * z_ndc + offset: 0.5 or 1 by the clip range.
  double depthScale() const { return depth_scale_; }
  float clearKey() const { return clear_key_; }
  float nearKey() const { return near_key_; }
  PixelRect viewportRect() const {
    return {0, 0, static_cast<std::int32_t>(camera_.width),
            static_cast<std::int32_t>(camera_.height)};
  }

 private:
  struct Checked {};  // the camera and settings were validated
  Projector(Checked, const Camera& camera, const ProjectionSettings& settings);

  // What queryBox() needs beyond the projection: the pixel widening of the footprint
  // and the range of clip w over the box's corners.
  struct Extent {
    double widen_x = 0, widen_y = 0, w_min = 0, w_max = 0;
  };
  BoxProjection projectWith(const Aabb& box, Extent* extent) const;
  // The batch kernels (projection.cpp, "The batch kernels"): the same arithmetic as
  // projectWith(), over the eight corners of a box at once, and the steps they share
  // with it.
  struct Kernel;

  // The steps of projectWith(). A point of the (near-clipped) box in clip space, with S:
  // the sums of the magnitudes of the terms of its clip x, y, z and w ("Why the margins
  // have their values").
  struct ClipPoint {
    double c[4];
    double s[4];
  };
  // The eight corners as structure of arrays: c[row][corner], s[row][corner], and in
  // q_abs[axis][0 and 1] the magnitudes of the box's min and max relative to the render
  // origin.
  struct Corners {
    double c[4][8];
    double s[4][8];
    double q_abs[3][8];
    ClipPoint point(int i) const {
      return {{c[0][i], c[1][i], c[2][i], c[3][i]}, {s[0][i], s[1][i], s[2][i], s[3][i]}};
    }
  };
  // The window-space bounds of the clipped box and the largest rounding errors of its
  // points (pixels in x and y, window depth in z).
  struct WindowBounds {
    double x_min = kInf, x_max = -kInf, y_min = kInf, y_max = -kInf;
    double key_min = kInf, key_max = -kInf;
    double err_x = 0, err_y = 0, err_z = 0;
    double w_min = kInf, w_max = 0;
  };
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  BoxProjection visibleEverywhere(ProjectionClass cls) const;
  void clipCorners(const Aabb& box, Corners& corners) const;
  void termMagnitudes(Corners& corners) const;
  bool outsideOnePlane(const Corners& corners) const;
  // dot(plane, corner i's clip position), summed as a four-term dot product.
  static double planeDistance(const double* plane, const Corners& k, int i) {
    return plane[0] * k.c[0][i] + plane[1] * k.c[1][i] + plane[2] * k.c[2][i] +
           plane[3] * k.c[3][i];
  }
  // Writes the clipped box's points (at most 8 + 12); crosses_near when a corner lies
  // beyond the near plane.
  int clipToNear(const Corners& corners, ClipPoint* points, bool& crosses_near) const;
  // False when a point lies at or behind the eye (w <= 0).
  bool windowBounds(const ClipPoint* points, int count, WindowBounds& bounds) const;

  Camera camera_;
  ProjectionSettings settings_;
  double render_[16];      // view_projection * translation(render_origin), column-major
  double render_abs_[16];  // |render_|, element-wise
  DVec3 origin_;
  double near_plane_[4];  // clip-space half-spaces: dot(plane, clip) >= 0 is inside
  double far_plane_[4];
  // Every finite box's corners have finite clip coordinates (no sum can overflow): then
  // the batch kernels test the near and far planes, whose x and y coefficients are 0,
  // without those two terms.
  bool clip_finite_;
  double depth_scale_;  // window depth = depth_scale_ * z_ndc + depth_offset_
  double depth_offset_;
  double key_sign_;  // +1 standard, -1 reversed
  double quantisation_;
  double snap_px_;
  double half_width_;   // 0.5 * camera_.width: window x = (x_ndc + 1) * half_width_
  double half_height_;  // 0.5 * camera_.height
  double error_scale_;  // settings_.render_error_ulps * kUnitRoundoff
  float clear_key_;
  float near_key_;
};

#if LOGRID_HAS_EXCEPTIONS
inline Projector::Projector(const Camera& camera, const ProjectionSettings& settings)
    : Projector(orThrow(create(camera, settings))) {}
#endif

}  // namespace logrid
