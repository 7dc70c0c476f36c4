#include "logrid/ddo/regions.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace logrid::ddo {

std::optional<RegionLayout> RegionLayout::forCount(std::uint32_t regions) {
  if (regions == 64) return RegionLayout(8, 8);
  if (regions == 32) return RegionLayout(8, 4);
  return std::nullopt;
}

double RegionLayout::edge(std::uint32_t bins, std::uint32_t i) {
  assert(bins > 0 && i <= bins && "RegionLayout::edge: edge out of range");
  const double degrees = -kMaxViewAngleDegrees + 2.0 * kMaxViewAngleDegrees * double(i) / bins;
  if (2 * i == bins) return 0.0;  // exactly 0, not tan of a rounded zero
  return std::tan(degrees * M_PI / 180.0);
}

void RegionLayout::binsMeeting(std::uint32_t bins, double lo, double hi, int& first, int& last) {
  first = int(bins);
  last = -1;
  for (std::uint32_t b = 0; b < bins; ++b) {
    if (edge(bins, b + 1) >= lo && edge(bins, b) <= hi) {
      first = std::min(first, int(b));
      last = std::max(last, int(b));
    }
  }
}

SlopeCell RegionLayout::cell(std::uint32_t region) const {
  assert(region < count() && "RegionLayout::cell: region out of range");
  const std::uint32_t b1 = region / bins2_, b2 = region % bins2_;
  return {edge(bins1_, b1), edge(bins1_, b1 + 1), edge(bins2_, b2), edge(bins2_, b2 + 1)};
}

FaceFrame faceFrame(const double* lo, const double* hi, double side, int face,
                    double margin_fraction) {
  FaceFrame f;
  f.axis = faceAxis(face);
  f.t1 = (f.axis + 1) % 3;
  f.t2 = (f.axis + 2) % 3;
  const bool high = faceSide(face) == 1;
  const double low_plane = lo[f.axis], high_plane = hi[f.axis];
  f.plane = high ? high_plane : low_plane;
  f.clip_plane = high ? low_plane : high_plane;
  f.dir = high ? -1.0 : 1.0;
  f.height = side;
  f.lo1 = lo[f.t1];
  f.hi1 = hi[f.t1];
  f.lo2 = lo[f.t2];
  f.hi2 = hi[f.t2];
  f.margin = margin_fraction * side;
  return f;
}

ViewspaceFrustum::ViewspaceFrustum(const FaceFrame& f, const SlopeCell& s) {
  for (auto& row : n) row[0] = row[1] = row[2] = 0;
  const int a = f.axis;
  const double lo1 = f.lo1 - f.margin, hi1 = f.hi1 + f.margin;
  const double lo2 = f.lo2 - f.margin, hi2 = f.hi2 + f.margin;
  // h >= 0 and h <= H, h = dir * (x[a] - plane).
  n[0][a] = f.dir;
  c[0] = -f.dir * f.plane;
  n[1][a] = -f.dir;
  c[1] = f.height + f.dir * f.plane;
  // u1 >= lo1 + h * s.lo1, u1 <= hi1 + h * s.hi1, and the same on t2.
  n[2][f.t1] = 1;
  n[2][a] = -s.lo1 * f.dir;
  c[2] = -lo1 + s.lo1 * f.dir * f.plane;
  n[3][f.t1] = -1;
  n[3][a] = s.hi1 * f.dir;
  c[3] = hi1 - s.hi1 * f.dir * f.plane;
  n[4][f.t2] = 1;
  n[4][a] = -s.lo2 * f.dir;
  c[4] = -lo2 + s.lo2 * f.dir * f.plane;
  n[5][f.t2] = -1;
  n[5][a] = s.hi2 * f.dir;
  c[5] = hi2 - s.hi2 * f.dir * f.plane;

  for (int i = 0; i < 6; ++i) {
    length[i] = std::sqrt(n[i][0] * n[i][0] + n[i][1] * n[i][1] + n[i][2] * n[i][2]);
  }
  for (int k = 0; k < 3; ++k) lo[k] = HUGE_VAL, hi[k] = -HUGE_VAL;
  for (int i = 0; i < 8; ++i) {
    const double h = (i & 1) ? f.height : 0.0;
    const double u1 = (i & 2) ? hi1 + h * s.hi1 : lo1 + h * s.lo1;
    const double u2 = (i & 4) ? hi2 + h * s.hi2 : lo2 + h * s.lo2;
    f.toWorld(h, u1, u2, corners[i]);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], corners[i][k]);
      hi[k] = std::max(hi[k], corners[i][k]);
    }
  }
}

bool ViewspaceFrustum::meetsSegment(const double* a, const double* b, double tolerance) const {
  // Liang-Barsky clipping of a + t (b - a), t in [0, 1], by each half-space, each
  // loosened by `tolerance` along its normal; decided early when an end lies inside.
  double ga[6], gb[6];
  bool a_in = true, b_in = true;
  for (int i = 0; i < 6; ++i) {
    const double slack = tolerance * length[i];
    ga[i] = n[i][0] * a[0] + n[i][1] * a[1] + n[i][2] * a[2] + c[i] + slack;
    gb[i] = n[i][0] * b[0] + n[i][1] * b[1] + n[i][2] * b[2] + c[i] + slack;
    if (ga[i] < 0 && gb[i] < 0) return false;
    a_in = a_in && ga[i] >= 0;
    b_in = b_in && gb[i] >= 0;
  }
  if (a_in || b_in) return true;
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 6; ++i) {
    if (ga[i] >= 0 && gb[i] >= 0) continue;
    const double t = ga[i] / (ga[i] - gb[i]);
    if (ga[i] < 0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace logrid::ddo
