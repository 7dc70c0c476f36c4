// Projector::queryBox (projection.hpp, "Query boxes"): the box a hardware occlusion
// query draws contains the tested box, its footprint grows by at least the widening the
// derivation promises on every side, its depth bias covers both renders' margins, and no
// query box is given where its biased faces would reach the near plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "logrid/projection.hpp"

namespace logrid {
namespace {

Camera makeCamera(DepthConvention convention, bool ortho, double yaw) {
  Camera cam;
  cam.width = 320;
  cam.height = 200;
  cam.depth = {convention,
               convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                       : ClipDepthRange::NegativeOneToOne,
               DepthFormat::D32F};
  const Mat4d projection = ortho ? orthographic(-30, 30, -18.75, 18.75, 0.5, 400, cam.depth)
                                 : perspective(1.0, 320.0 / 200.0, 0.5, 400, cam.depth);
  const DVec3 eye{3, 2, 5};
  cam.view_projection = multiply(
      projection, lookAt(eye, {eye.x + std::sin(yaw), 1.5, eye.z - std::cos(yaw)}, {0, 1, 0}));
  return cam;
}

// Window x and y of a world point, exactly as the projection defines them (double).
void window(const Camera& cam, double x, double y, double z, double& wx, double& wy) {
  const Mat4d& m = cam.view_projection;
  const double c[4] = {m(0, 0) * x + m(0, 1) * y + m(0, 2) * z + m(0, 3),
                       m(1, 0) * x + m(1, 1) * y + m(1, 2) * z + m(1, 3), 0,
                       m(3, 0) * x + m(3, 1) * y + m(3, 2) * z + m(3, 3)};
  wx = (c[0] / c[3] + 1) * 0.5 * cam.width;
  wy = (c[1] / c[3] + 1) * 0.5 * cam.height;
}

struct Footprint {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
};

Footprint footprint(const Camera& cam, const Aabb& b) {
  Footprint f;
  for (int i = 0; i < 8; ++i) {
    double wx, wy;
    window(cam, (i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
           (i & 4) ? b.max.z : b.min.z, wx, wy);
    f.x0 = std::min(f.x0, wx), f.x1 = std::max(f.x1, wx);
    f.y0 = std::min(f.y0, wy), f.y1 = std::max(f.y1, wy);
  }
  return f;
}

class QueryBoxTest : public testing::TestWithParam<std::pair<DepthConvention, bool>> {};

TEST_P(QueryBoxTest, ContainsTheBoxGrowsItsFootprintAndBiasesItsDepth) {
  const auto [convention, ortho] = GetParam();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-40, 40), size(0.05f, 6), yaw(-3, 3);
  int boxes = 0;
  for (int k = 0; k < 2000; ++k) {
    const Camera cam = makeCamera(convention, ortho, yaw(rng));
    const Projector projector(cam);
    const Vec3 lo{pos(rng), pos(rng) * 0.2f, pos(rng)};
    const Aabb box{lo, {lo.x + size(rng), lo.y + size(rng), lo.z + size(rng)}};
    const BoxProjection p = projector.project(box);
    const std::optional<QueryBox> q = projector.queryBox(box);
    if (p.cls != ProjectionClass::Inside) {
      EXPECT_FALSE(q) << "a query box for a box that does not project inside";
      continue;
    }
    if (!q) {
      // Only where the biased faces would reach the near plane.
      EXPECT_LE(double(p.near_key) - 1e-2, double(projector.nearKey()));
      continue;
    }
    ++boxes;
    EXPECT_LE(q->box.min.x, box.min.x);
    EXPECT_LE(q->box.min.y, box.min.y);
    EXPECT_LE(q->box.min.z, box.min.z);
    EXPECT_GE(q->box.max.x, box.max.x);
    EXPECT_GE(q->box.max.y, box.max.y);
    EXPECT_GE(q->box.max.z, box.max.z);
    const BoxProjection qp = projector.project(q->box);
    EXPECT_GE(q->depth_bias, 2 * qp.margin);
    EXPECT_GT(double(qp.near_key) - double(q->depth_bias), double(projector.nearKey()));
    // The extreme corners move out by at least the half pixel of kQueryWidenPixels.
    const Footprint a = footprint(cam, box), b = footprint(cam, q->box);
    EXPECT_LE(b.x0, a.x0 - kQueryWidenPixels);
    EXPECT_GE(b.x1, a.x1 + kQueryWidenPixels);
    EXPECT_LE(b.y0, a.y0 - kQueryWidenPixels);
    EXPECT_GE(b.y1, a.y1 + kQueryWidenPixels);
  }
  EXPECT_GT(boxes, 200) << "too few boxes in view to test anything";
}

INSTANTIATE_TEST_SUITE_P(Cameras, QueryBoxTest,
                         testing::Values(std::pair{DepthConvention::Standard, false},
                                         std::pair{DepthConvention::Reversed, false},
                                         std::pair{DepthConvention::Standard, true},
                                         std::pair{DepthConvention::Reversed, true}),
                         [](const auto& p) {
                           return std::string(toString(p.param.first)) +
                                  (p.param.second ? "_ortho" : "_perspective");
                         });

TEST(QueryBox, NoneForBoxesAtOrNearTheNearPlane) {
  const Camera cam = makeCamera(DepthConvention::Standard, false, 0);
  const Projector projector(cam);
  // The eye is at (3, 2, 5) looking down -z; the near plane is 0.5 in front.
  EXPECT_FALSE(projector.queryBox({{2, 1, 3}, {4, 3, 6}}));                    // contains the eye
  EXPECT_FALSE(projector.queryBox({{2.9f, 1.9f, 4.4f}, {3.1f, 2.1f, 4.6f}}));  // crosses near
  EXPECT_FALSE(projector.queryBox({{2, 1, 20}, {4, 3, 22}}));                  // behind the eye
  // Just beyond the near plane: its widened box reaches it.
  EXPECT_FALSE(projector.queryBox({{2.9f, 1.9f, 4.2f}, {3.1f, 2.1f, 4.49f}}));
  EXPECT_TRUE(projector.queryBox({{2, 1, -10}, {4, 3, -8}}));
}

}  // namespace
}  // namespace logrid
