// Orientation of four points with a certified sign (or "too close to tell"). Internal to
// the preprocessing.
#pragma once

#include <cmath>

namespace logrid::ddo::detail {

// The sign of det[a - d; b - d; c - d] (positive when d lies below the plane through a,
// b, c seen counter-clockwise), or 0 when the double-precision value is within its
// error bound of zero. The bound is Shewchuk's static filter for orient3d (about 7.8e-16
// times the permanent), taken as 1e-15 times it.
inline int orient3d(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
  const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
  const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
  const double bc = bdx * cdy - bdy * cdx, ca = cdx * ady - cdy * adx, ab = adx * bdy - ady * bdx;
  const double det = adz * bc + bdz * ca + cdz * ab;
  const double permanent = std::fabs(adz) * (std::fabs(bdx * cdy) + std::fabs(bdy * cdx)) +
                           std::fabs(bdz) * (std::fabs(cdx * ady) + std::fabs(cdy * adx)) +
                           std::fabs(cdz) * (std::fabs(adx * bdy) + std::fabs(ady * bdx));
  const double bound = 1e-15 * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return 0;
}

enum class Crossing { Miss, Cross, Degenerate };

// Does the segment p-q pass through the interior of triangle (a, b, c)? Degenerate when
// the answer hangs on a sign too close to zero: the segment grazes an edge, a vertex or
// the triangle's plane.
inline Crossing segmentCrossesTriangle(const double* p, const double* q, const double* a,
                                       const double* b, const double* c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp != 0 && sp == sq) return Crossing::Miss;  // both ends on one side of the plane
  const int e0 = orient3d(p, q, a, b), e1 = orient3d(p, q, b, c), e2 = orient3d(p, q, c, a);
  const bool has_pos = e0 > 0 || e1 > 0 || e2 > 0, has_neg = e0 < 0 || e1 < 0 || e2 < 0;
  if (has_pos && has_neg) return Crossing::Miss;  // the line passes beside the triangle
  if (sp != 0 && sq != 0 && e0 != 0 && e1 != 0 && e2 != 0) return Crossing::Cross;
  return Crossing::Degenerate;
}

}  // namespace logrid::ddo::detail
