// The view-direction regions of an octree face and its viewspace frustum (DDO §3,
// figures 3 and 4).
//
// Faces. A node's cell is a cube; face f = 2 * axis + side is its face on `axis`
// (0 x, 1 y, 2 z) at the low (side 0) or high (side 1) end. A face is a candidate
// occluder only when seen from the half-space that holds its node (§3): for the low face
// the viewer lies at larger coordinates on `axis`. The face's frame measures a point by
// its height h above the face plane into that half-space and by its lateral coordinates
// on the tangent axes t1 = (axis + 1) % 3 and t2 = (axis + 2) % 3.
//
// Regions. The paper's figure 3 partitions the directions of one half-space into sectors
// but does not say how in 3D. Here a direction d is described by its two slopes
// (d[t1] / h, d[t2] / h), each turned into an angle in (-90, 90) degrees and binned
// separately: 8 bins of 20 degrees from -80 to 80 on both tangent axes (64 regions), or
// 8 on t1 and 4 of 40 degrees on t2 (32 regions). Directions more than 80 degrees from
// the face normal on either axis belong to no region: their frustum would be unbounded,
// so no finite geometry could make them valid.
//
// Clipping plane. Viewpoints must lie at height >= H (figure 4). The paper puts the
// plane beyond the node without saying how far; here H is the cell side, i.e. the plane
// of the node's opposite face, so the frustum of every face of a level spans exactly one
// slab of cells (the preprocessing shares work along that slab).
//
// Viewspace frustum. A region r of face f is the set of viewpoints v with height >= H
// whose slopes, taken from some anchor point of the face, fall in r's cell. Every segment
// from such a v to a point of the face, cut at height H, lies in
//   P(f, r) = { (h, u1, u2) : 0 <= h <= H, u in face + h * cell },
// a convex polytope whose cross-sections are axis-aligned rectangles growing linearly
// with h (the paper's "convolution of the face with the region"). The face is enlarged
// by a margin (face_margin times the side on each lateral side) before building P: the
// validity test then also covers a band around the face, which lets the run time draw
// faces without shrinking them by the rasteriser's snapping (selector.hpp).
#pragma once

#include <cstdint>
#include <optional>

namespace logrid::ddo {

inline constexpr double kMaxViewAngleDegrees = 80.0;
// Face enlargement for the validity test, as a fraction of the cell side.
inline constexpr double kFaceMargin = 1.0 / 32.0;

struct SlopeCell {
  double lo1 = 0, hi1 = 0;  // slope range along t1
  double lo2 = 0, hi2 = 0;  // slope range along t2
};

class RegionLayout {
 public:
  // 32 or 64 regions; nullopt for any other count.
  static std::optional<RegionLayout> forCount(std::uint32_t regions);

  std::uint32_t count() const { return bins1_ * bins2_; }
  std::uint32_t bins1() const { return bins1_; }
  std::uint32_t bins2() const { return bins2_; }
  // Region of bins (b1, b2).
  std::uint32_t region(std::uint32_t b1, std::uint32_t b2) const { return b1 * bins2_ + b2; }
  SlopeCell cell(std::uint32_t region) const;

  // The slope at edge i (0..bins) of an axis with `bins` bins: tan(-80 + i * 160 / bins
  // degrees). The look-up table the run time bins slopes with.
  static double edge(std::uint32_t bins, std::uint32_t i);
  // The bins whose closed slope range meets [lo, hi]: [first, last], or first > last when
  // none does (the range lies beyond 80 degrees).
  static void binsMeeting(std::uint32_t bins, double lo, double hi, int& first, int& last);

 private:
  RegionLayout(std::uint32_t b1, std::uint32_t b2) : bins1_(b1), bins2_(b2) {}
  std::uint32_t bins1_ = 8;
  std::uint32_t bins2_ = 8;
};

inline constexpr int kFaces = 6;
inline int faceAxis(int face) { return face / 2; }
inline int faceSide(int face) { return face % 2; }

// A face in its own frame.
struct FaceFrame {
  int axis = 0, t1 = 1, t2 = 2;
  double plane = 0;       // coordinate of the face plane on `axis`
  double clip_plane = 0;  // coordinate of the clipping plane (height H) on `axis`
  double dir = 1;         // +1: heights grow with the coordinate on `axis`; -1: they shrink
  double height = 0;      // H, the cell side
  double lo1 = 0, hi1 = 0, lo2 = 0, hi2 = 0;  // the face, laterally
  double margin = 0;                          // enlargement on each lateral side

  // Height of a world point above the face plane (into the node's half-space).
  double heightOf(const double* p) const { return dir * (p[axis] - plane); }
  // The world point at height h and lateral position (u1, u2).
  void toWorld(double h, double u1, double u2, double* out) const {
    out[axis] = plane + dir * h;
    out[t1] = u1;
    out[t2] = u2;
  }
};

// The face `face` of the cube [lo, hi] of side `side` (hi - lo up to rounding; the
// planes are taken as given so that neighbouring cells share them bit for bit). The
// clipping plane is the opposite face's plane; `margin_fraction` enlarges the face for P.
FaceFrame faceFrame(const double* lo, const double* hi, double side, int face,
                    double margin_fraction = kFaceMargin);

// The viewspace frustum P(face, cell) as six half-spaces g(x) >= 0 in world coordinates,
// g(x) = n . x + c: height >= 0, height <= H, and the four lateral sides.
struct ViewspaceFrustum {
  double n[6][3];
  double c[6];
  double length[6];     // |n|
  double lo[3], hi[3];  // its bounding box
  double corners[8][3];

  ViewspaceFrustum(const FaceFrame& face, const SlopeCell& cell);
  // Does the closed segment a-b meet the closed frustum? Answers yes when within
  // `tolerance` (world units) of it, so that rounding only ever adds meetings.
  bool meetsSegment(const double* a, const double* b, double tolerance) const;
};

}  // namespace logrid::ddo
