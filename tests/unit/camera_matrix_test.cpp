// The matrix helpers of camera.hpp (built with GLM): every depth set-up maps the near
// plane to its near depth and the far plane to its far depth, for perspective (finite
// and infinite far) and orthographic projections, and lookAt/multiply/translation
// compose as the conventions say.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"

namespace logrid {
namespace {

// Clip-space (x, y, z, w) of the eye-space point (x, y, z, 1).
struct Clip {
  double x, y, z, w;
};
Clip apply(const Mat4d& m, double x, double y, double z) {
  const double p[4] = {x, y, z, 1};
  double c[4];
  for (int r = 0; r < 4; ++r) {
    c[r] = 0;
    for (int k = 0; k < 4; ++k) c[r] += m(r, k) * p[k];
  }
  return {c[0], c[1], c[2], c[3]};
}

struct DepthCase {
  const char* name;
  DepthSetup depth;
  double near_ndc;  // the NDC depth the near plane must map to
  double far_ndc;
};

const DepthCase kSetups[] = {
    {"standard -1..1", {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne}, -1, 1},
    {"standard 0..1", {DepthConvention::Standard, ClipDepthRange::ZeroToOne}, 0, 1},
    {"reversed 0..1", {DepthConvention::Reversed, ClipDepthRange::ZeroToOne}, 1, 0},
    {"reversed -1..1", {DepthConvention::Reversed, ClipDepthRange::NegativeOneToOne}, 1, -1},
};

TEST(CameraMatrix, PerspectiveMapsNearAndFarPlanesToTheSetupsDepths) {
  for (const DepthCase& s : kSetups) {
    for (const auto& [near, far] : {std::pair{0.1, 1000.0}, std::pair{2.0, 3.0}}) {
      const Mat4d p = perspective(1.0, 1.5, near, far, s.depth);
      const Clip n = apply(p, 0, 0, -near), f = apply(p, 0, 0, -far);
      EXPECT_NEAR(n.z / n.w, s.near_ndc, 1e-12) << s.name << " near " << near;
      EXPECT_NEAR(f.z / f.w, s.far_ndc, 1e-12) << s.name << " far " << far;
      EXPECT_DOUBLE_EQ(n.w, near);  // w is the distance in front of the eye
      // The frustum's top edge at the near plane lands on y_ndc = 1, its right edge on 1.
      const double top = near * std::tan(0.5);
      const Clip corner = apply(p, top * 1.5, top, -near);
      EXPECT_NEAR(corner.x / corner.w, 1.0, 1e-12) << s.name;
      EXPECT_NEAR(corner.y / corner.w, 1.0, 1e-12) << s.name;
    }
  }
}

TEST(CameraMatrix, InfinitePerspectiveApproachesTheFarDepthAndKeepsTheFrustum) {
  const double inf = std::numeric_limits<double>::infinity();
  for (const DepthCase& s : kSetups) {
    const Mat4d p = perspective(1.0, 1.5, 0.5, inf, s.depth);
    const Mat4d finite = perspective(1.0, 1.5, 0.5, 1000.0, s.depth);
    const Clip n = apply(p, 0, 0, -0.5), f = apply(p, 0, 0, -1e12);
    EXPECT_NEAR(n.z / n.w, s.near_ndc, 1e-12) << s.name;
    EXPECT_NEAR(f.z / f.w, s.far_ndc, 1e-9) << s.name;
    for (int i : {0, 5, 11, 15}) EXPECT_EQ(p.m[i], finite.m[i]) << s.name << " element " << i;
  }
  // Reversed, zero-to-one: the usual infinite reversed projection, z_clip = near.
  const Mat4d r = perspective(1.0, 1.0, 0.5, inf, kSetups[2].depth);
  EXPECT_EQ(r(2, 2), 0.0);
  EXPECT_EQ(r(2, 3), 0.5);
}

TEST(CameraMatrix, OrthographicMapsNearAndFarPlanesToTheSetupsDepths) {
  for (const DepthCase& s : kSetups) {
    const Mat4d p = orthographic(-2, 6, -1, 3, -0.5, 40, s.depth);
    const Clip n = apply(p, -2, -1, 0.5), f = apply(p, 6, 3, -40);
    EXPECT_NEAR(n.z, s.near_ndc, 1e-12) << s.name;
    EXPECT_NEAR(f.z, s.far_ndc, 1e-12) << s.name;
    EXPECT_NEAR(n.x, -1, 1e-12);
    EXPECT_NEAR(n.y, -1, 1e-12);
    EXPECT_NEAR(f.x, 1, 1e-12);
    EXPECT_NEAR(f.y, 1, 1e-12);
    EXPECT_EQ(n.w, 1.0);
  }
}

TEST(CameraMatrix, LookAtPutsTheTargetOnTheNegativeZAxis) {
  const Mat4d v = lookAt({1, 2, 3}, {4, 2, -1}, {0, 1, 0});
  const Clip eye = apply(v, 1, 2, 3), target = apply(v, 4, 2, -1), above = apply(v, 1, 3, 3);
  EXPECT_NEAR(eye.x, 0, 1e-15);
  EXPECT_NEAR(eye.y, 0, 1e-15);
  EXPECT_NEAR(eye.z, 0, 1e-15);
  EXPECT_NEAR(target.x, 0, 1e-14);
  EXPECT_NEAR(target.y, 0, 1e-14);
  EXPECT_NEAR(target.z, -5, 1e-14);
  EXPECT_NEAR(above.y, 1, 1e-15);  // up stays up
  EXPECT_THROW(lookAt({1, 2, 3}, {1, 2, 3}, {0, 1, 0}), Error);
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 5, 0}, {0, 1, 0}), Error);  // up along the view
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 0, -1}, {0, 0, 0}), Error);
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 0, -1}, {0, std::nan(""), 0}), Error);
}

TEST(CameraMatrix, MultiplyAndTranslationComposeColumnMajor) {
  const Mat4d t = translation({1, -2, 3});
  EXPECT_EQ(t.m[12], 1);
  EXPECT_EQ(t.m[13], -2);
  EXPECT_EQ(t.m[14], 3);
  Mat4d s;
  s(0, 0) = 2, s(1, 1) = 3, s(2, 2) = 4;
  // (s * t) p = s (p + offset): scale after translation.
  const Clip st = apply(multiply(s, t), 1, 1, 1);
  EXPECT_EQ(st.x, 4);
  EXPECT_EQ(st.y, -3);
  EXPECT_EQ(st.z, 16);
  const Clip ts = apply(multiply(t, s), 1, 1, 1);
  EXPECT_EQ(ts.x, 3);
  EXPECT_EQ(ts.y, 1);
  EXPECT_EQ(ts.z, 7);
  EXPECT_EQ(ts.w, 1);
}

}  // namespace
}  // namespace logrid
