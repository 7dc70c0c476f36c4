#include "logrid/coverage.hpp"

#include <algorithm>
#include <cmath>

namespace logrid {

CoverageRule coverageRule(const Camera& camera, const ProjectionSettings& settings) {
  CoverageRule rule;
  // As Projector: half a sub-pixel step, none at 16 bits (the margin tests' "no widening").
  rule.snap = settings.subpixel_bits >= 16 ? 0.0 : std::ldexp(0.5, -settings.subpixel_bits);
  rule.render_error = settings.render_error_ulps * kUnitRoundoff;
  rule.half_width = 0.5 * camera.width;
  rule.half_height = 0.5 * camera.height;
  rule.whole_pixels = camera.multisample;
  rule.near_limit = nearPlaneKey(camera.depth);
  rule.far_limit = clearKey(camera.depth);
  return rule;
}

QuadCoverage::QuadCoverage(const DrawnQuad& quad, const CoverageRule& rule) {
  // No fragment clipped by the near or far plane (NaN keys fail too).
  if (!(quad.near_key > rule.near_limit) || !(quad.far_key < rule.far_limit)) return;
  const double(*q)[2] = quad.window;
  // How far a drawn vertex may lie from q[i]: float rounding of its window position
  // (relative to the NDC magnitude, coverage.hpp) and sub-pixel snapping, per axis.
  double widen_x = 0, widen_y = 0;
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(q[i][0]) || !std::isfinite(q[i][1])) return;
    widen_x = std::max(widen_x, rule.half_width + std::fabs(q[i][0] - rule.half_width));
    widen_y = std::max(widen_y, rule.half_height + std::fabs(q[i][1] - rule.half_height));
  }
  const double edge =
      std::hypot(rule.render_error * widen_x + rule.snap, rule.render_error * widen_y + rule.snap);
  // Orientation, and convexity: every turn the same way, none straight.
  double area = 0;
  for (int i = 0; i < 4; ++i) area += q[i][0] * q[(i + 1) % 4][1] - q[(i + 1) % 4][0] * q[i][1];
  if (!(std::fabs(area) > 0)) return;  // seen edge-on
  const double orient = area > 0 ? 1.0 : -1.0;
  for (int i = 0; i < 4; ++i) {
    const double* a = q[i];
    const double* b = q[(i + 1) % 4];
    const double* c = q[(i + 2) % 4];
    const double turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
    if (!(turn * orient > 0)) return;
  }
  for (int i = 0; i < 4; ++i) {
    const double* a = q[i];
    const double* b = q[(i + 1) % 4];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double len = std::hypot(ex, ey);
    // Inward unit normal of edge a -> b; a point p is inside by more than the edge error
    // where nx * p.x + ny * p.y > offset.
    nx_[i] = -ey / len * orient;
    ny_[i] = ex / len * orient;
    offset_[i] = nx_[i] * a[0] + ny_[i] * a[1] + edge;
  }
  inset_ = rule.whole_pixels ? 0.0 : 0.5;
  usable_ = true;
}

bool QuadCoverage::covers(const PixelRect& rect) const {
  if (!usable_ || rect.empty()) return false;
  // The rectangle's extreme samples: the centres of its corner pixels, or its corners.
  const double px[2] = {rect.x0 + inset_, rect.x1 - inset_};
  const double py[2] = {rect.y0 + inset_, rect.y1 - inset_};
  for (int i = 0; i < 4; ++i) {
    for (double x : px) {
      for (double y : py) {
        if (!(nx_[i] * x + ny_[i] * y > offset_[i])) return false;
      }
    }
  }
  return true;
}

bool coversRect(const DrawnQuad& quad, const PixelRect& rect, const CoverageRule& rule) {
  return QuadCoverage(quad, rule).covers(rect);
}

}  // namespace logrid
