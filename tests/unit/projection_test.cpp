// Conservative box projection: rectangles, depth keys, classes and margins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "logrid/error.hpp"
#include "logrid/projection.hpp"
#include "projection_isa.hpp"
#include "rounding.hpp"

namespace logrid {
namespace {

Camera makeCamera(DepthSetup depth, std::uint32_t w = 640, std::uint32_t h = 480, double near = 0.1,
                  double far = 1000.0) {
  Camera c;
  c.width = w;
  c.height = h;
  c.depth = depth;
  // Eye at the origin looking down -z.
  c.view_projection = multiply(perspective(M_PI / 3, double(w) / h, near, far, depth),
                               lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}));
  return c;
}

const DepthSetup kStandard{DepthConvention::Standard, ClipDepthRange::NegativeOneToOne,
                           DepthFormat::D32F};
const DepthSetup kReversed{DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D32F};

TEST(ProjectionTest, BoxInFrontProjectsToItsRectangleAndDepth) {
  const Camera cam = makeCamera(kStandard);
  const Projector p(cam);
  // A unit box centred 10 units ahead.
  const BoxProjection r = p.project({{-0.5f, -0.5f, -10.5f}, {0.5f, 0.5f, -9.5f}});
  ASSERT_EQ(r.cls, ProjectionClass::Inside);
  // Nearest face at distance 9.5: x spans +-0.5/9.5 * f / aspect in NDC.
  const double f = 1.0 / std::tan(M_PI / 6);
  const double half = 0.5 / 9.5 * f / (640.0 / 480.0) * 320.0;
  EXPECT_NEAR(r.rect.x0, std::ceil(320.0 - half - 0.5), 1.0);
  EXPECT_NEAR(r.rect.x1, std::floor(320.0 + half - 0.5) + 1, 1.0);
  EXPECT_LE(r.rect.x0, std::ceil(320.0 - half - 0.5));  // widened, never narrowed
  EXPECT_GE(r.rect.x1, std::floor(320.0 + half - 0.5) + 1);
  // Window depth of distance d for the -1..1 range: 0.5 * (a - b / d) + 0.5.
  auto depthAt = [](double d) {
    const double n = 0.1, fa = 1000.0;
    const double zndc = ((fa + n) / (fa - n) * d - 2 * fa * n / (fa - n)) / d;
    return 0.5 * zndc + 0.5;
  };
  EXPECT_LE(r.near_key, depthAt(9.5));
  EXPECT_NEAR(r.near_key, depthAt(9.5), 1e-7);
  EXPECT_GE(r.far_key, depthAt(10.5));
  EXPECT_NEAR(r.far_key, depthAt(10.5), 1e-7);
  EXPECT_GT(r.margin, 0.0f);
  EXPECT_LT(r.margin, 1e-5f);
}

TEST(ProjectionTest, ReversedKeysAreNegatedAndNearerIsSmaller) {
  const Camera cam = makeCamera(kReversed);
  const Projector p(cam);
  EXPECT_EQ(p.clearKey(), 0.0f);
  EXPECT_EQ(p.nearKey(), -1.0f);
  const BoxProjection a = p.project({{-0.5f, -0.5f, -10.5f}, {0.5f, 0.5f, -9.5f}});
  const BoxProjection b = p.project({{-0.5f, -0.5f, -100.5f}, {0.5f, 0.5f, -99.5f}});
  ASSERT_EQ(a.cls, ProjectionClass::Inside);
  ASSERT_EQ(b.cls, ProjectionClass::Inside);
  EXPECT_LT(a.far_key, b.near_key);  // the nearer box has the smaller keys
  // Reversed zero-to-one: window depth = n (f - d) / ((f - n) d), key = -depth.
  const double n = 0.1, fa = 1000.0, d = 9.5;
  EXPECT_NEAR(a.near_key, -(n * (fa - d) / ((fa - n) * d)), 1e-8);
  EXPECT_LE(a.near_key, -(n * (fa - d) / ((fa - n) * d)));
}

TEST(ProjectionTest, ClassifiesNearPlaneEyeOutsideAndInvalidBoxes) {
  for (const DepthSetup& depth : {kStandard, kReversed}) {
    const Projector p(makeCamera(depth));
    // Crossing the near plane (0.1 ahead) but in front of the eye.
    EXPECT_EQ(p.project({{-1, -1, -5}, {1, 1, -0.05f}}).cls, ProjectionClass::CrossesNear);
    // Containing the eye.
    EXPECT_EQ(p.project({{-1, -1, -1}, {1, 1, 1}}).cls, ProjectionClass::CrossesNear);
    // Behind the eye.
    EXPECT_EQ(p.project({{-1, -1, 1}, {1, 1, 3}}).cls, ProjectionClass::Outside);
    // Beyond the far plane.
    EXPECT_EQ(p.project({{-1, -1, -3000}, {1, 1, -2000}}).cls, ProjectionClass::Outside);
    // Far to the left.
    EXPECT_EQ(p.project({{-500, -1, -11}, {-400, 1, -10}}).cls, ProjectionClass::Outside);
    // NaN, infinite and inverted boxes.
    const float nan = std::nanf("");
    EXPECT_EQ(p.project({{nan, 0, -10}, {1, 1, -9}}).cls, ProjectionClass::Invalid);
    EXPECT_EQ(p.project({{0, 0, -INFINITY}, {1, 1, -9}}).cls, ProjectionClass::Invalid);
    EXPECT_EQ(p.project({{1, 0, -10}, {0, 1, -9}}).cls, ProjectionClass::Invalid);
    // A degenerate box (a quad) is valid.
    EXPECT_EQ(p.project({{-1, -1, -10}, {1, 1, -10}}).cls, ProjectionClass::Inside);
  }
}

TEST(ProjectionTest, InvalidBoxesAreVisibleEverywhereAndDrawnLast) {
  const Projector p(makeCamera(kStandard));
  const BoxProjection r = p.project({{1, 0, -10}, {0, 1, -9}});
  EXPECT_EQ(r.rect.x0, 0);
  EXPECT_EQ(r.rect.y0, 0);
  EXPECT_EQ(r.rect.x1, 640);
  EXPECT_EQ(r.rect.y1, 480);
  EXPECT_EQ(r.near_key, p.nearKey());
  EXPECT_EQ(r.far_key, p.clearKey());
}

TEST(ProjectionTest, NearCrossingBoxesKeepATightRectangleFromTheClippedPart) {
  const Projector p(makeCamera(kStandard));
  // A thin box from 0.05 to 50 ahead, 100 units to the right: only its far part is seen.
  const BoxProjection r = p.project({{30, -0.1f, -50}, {31, 0.1f, -0.05f}});
  ASSERT_EQ(r.cls, ProjectionClass::CrossesNear);
  EXPECT_EQ(r.near_key, p.nearKey());
  EXPECT_LT(r.rect.area(), 640 * 480);
  EXPECT_GT(r.rect.x0, 320);  // right half only
}

TEST(ProjectionTest, SubPixelBoxesBetweenPixelCentresAreCulledButNotOnACentre) {
  // Orthographic 8x8 camera over [0,8]^2: one world unit per pixel.
  Camera cam;
  cam.width = cam.height = 8;
  cam.depth = kStandard;
  cam.view_projection = orthographic(0, 8, 0, 8, 0.5, 10, kStandard);
  const Projector p(cam);
  // Between the centres (2.5, y) and (3.5, y): covers none, even after widening.
  const BoxProjection between = p.project({{2.6f, 2.6f, -2}, {2.9f, 2.9f, -1}});
  EXPECT_EQ(between.cls, ProjectionClass::Outside);
  // Over the centre of pixel (3, 3).
  const BoxProjection over = p.project({{3.4f, 3.4f, -2}, {3.6f, 3.6f, -1}});
  ASSERT_EQ(over.cls, ProjectionClass::Inside);
  EXPECT_EQ(over.rect.x0, 3);
  EXPECT_EQ(over.rect.x1, 4);
  EXPECT_EQ(over.rect.y0, 3);
  EXPECT_EQ(over.rect.y1, 4);
  // Touching the centre exactly: included.
  const BoxProjection edge = p.project({{3.5f, 3.5f, -2}, {3.7f, 3.7f, -1}});
  EXPECT_EQ(edge.cls, ProjectionClass::Inside);
  // Multisampling counts every pixel touched.
  cam.multisample = true;
  EXPECT_EQ(Projector(cam).project({{2.6f, 2.6f, -2}, {2.9f, 2.9f, -1}}).cls,
            ProjectionClass::Inside);
}

TEST(ProjectionTest, EveryPointOfARandomBoxLandsInsideItsRectangleAndDepthRange) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-20, 20), size(0.001f, 8), unit(0, 1);
  for (const DepthSetup& depth :
       {kStandard, kReversed,
        DepthSetup{DepthConvention::Standard, ClipDepthRange::ZeroToOne, DepthFormat::D24}}) {
    Camera cam = makeCamera(depth, 317, 211, 0.5, 200);
    cam.view_projection = multiply(perspective(1.1, 317.0 / 211, 0.5, 200, depth),
                                   lookAt({0, 2, 30}, {0, 0, 0}, {0, 1, 0}));
    const Projector p(cam);
    int inside = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 lo{pos(rng), pos(rng), pos(rng)};
      const Aabb box{lo, {lo.x + size(rng), lo.y + size(rng), lo.z + size(rng)}};
      const BoxProjection r = p.project(box);
      if (r.cls != ProjectionClass::Inside) continue;
      ++inside;
      for (int k = 0; k < 16; ++k) {
        const double q[3] = {box.min.x + unit(rng) * (box.max.x - box.min.x),
                             box.min.y + unit(rng) * (box.max.y - box.min.y),
                             box.min.z + unit(rng) * (box.max.z - box.min.z)};
        const Mat4d& m = cam.view_projection;
        double c[4];
        for (int row = 0; row < 4; ++row) {
          c[row] = m(row, 0) * q[0] + m(row, 1) * q[1] + m(row, 2) * q[2] + m(row, 3);
        }
        const double wx = (c[0] / c[3] * 0.5 + 0.5) * cam.width;
        const double wy = (c[1] / c[3] * 0.5 + 0.5) * cam.height;
        const double scale = depth.clip_range == ClipDepthRange::ZeroToOne ? 1.0 : 0.5;
        const double wz = c[2] / c[3] * scale + (1.0 - scale);
        const double key = depth.convention == DepthConvention::Reversed ? -wz : wz;
        if (wx >= 0 && wx < cam.width && wy >= 0 && wy < cam.height) {
          // The pixel whose centre is nearest to the point is in the rectangle.
          const int px = int(std::floor(wx)), py = int(std::floor(wy));
          EXPECT_GE(px + 1, r.rect.x0);
          EXPECT_LE(px - 1, r.rect.x1);
          EXPECT_GE(py + 1, r.rect.y0);
          EXPECT_LE(py - 1, r.rect.y1);
        }
        EXPECT_GE(key, double(r.near_key));
        EXPECT_LE(key, double(r.far_key));
      }
    }
    EXPECT_GT(inside, 1000);
  }
}

TEST(ProjectionTest, MarginsScaleWithFormatAndDistanceFromTheRenderOrigin) {
  const Aabb box{{-0.5f, -0.5f, -10.5f}, {0.5f, 0.5f, -9.5f}};
  DepthSetup d16 = kStandard, d24 = kStandard;
  d16.format = DepthFormat::D16;
  d24.format = DepthFormat::D24;
  const float m32 = Projector(makeCamera(kStandard)).project(box).margin;
  const float m24 = Projector(makeCamera(d24)).project(box).margin;
  const float m16 = Projector(makeCamera(d16)).project(box).margin;
  EXPECT_LT(m32, m24);
  EXPECT_LT(m24, m16);
  EXPECT_GE(m16, 1.0 / 65535.0);
  EXPECT_GE(m24, 1.0 / 16777215.0);
  EXPECT_LT(m32, 2e-5f);

  // The same view far from the origin along the view axis: clip z then sums terms of
  // size 1e5 that cancel, so a world-space renderer needs a far larger margin; a
  // camera-relative one (render_origin = eye) the same as at the origin.
  const double off = 1e5;
  Camera far_cam = makeCamera(kStandard);
  far_cam.view_projection = multiply(perspective(M_PI / 3, 640.0 / 480, 0.1, 1000, kStandard),
                                     lookAt({0, 0, off}, {0, 0, off - 1}, {0, 1, 0}));
  const Aabb far_box{{-0.5f, -0.5f, float(off) - 10.5f}, {0.5f, 0.5f, float(off) - 9.5f}};
  const BoxProjection world = Projector(far_cam).project(far_box);
  far_cam.render_origin = {0, 0, off};
  const BoxProjection relative = Projector(far_cam).project(far_box);
  EXPECT_GT(world.margin, 100 * m32);
  EXPECT_NEAR(relative.margin, m32, 0.5 * m32);

  // Offset sideways, clip x carries the large terms: the rectangle widens instead.
  Camera side = makeCamera(kStandard);
  side.view_projection = multiply(perspective(M_PI / 3, 640.0 / 480, 0.1, 1000, kStandard),
                                  lookAt({3e6, 0, 0}, {3e6, 0, -1}, {0, 1, 0}));
  const Aabb side_box{{3e6f - 0.5f, -0.5f, -10.5f}, {3e6f + 0.5f, 0.5f, -9.5f}};
  const BoxProjection side_world = Projector(side).project(side_box);
  side.render_origin = {3e6, 0, 0};
  const BoxProjection side_relative = Projector(side).project(side_box);
  EXPECT_GT(side_world.rect.x1 - side_world.rect.x0, side_relative.rect.x1 - side_relative.rect.x0);
}

TEST(ProjectionTest, InvalidCamerasThrowWithTheFieldNamed) {
  Camera cam = makeCamera(kStandard);
  cam.view_projection.m[5] = std::nan("");
  try {
    Projector p(cam);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("element 5"), std::string::npos) << e.what();
  }
  cam = makeCamera(kStandard);
  cam.width = 0;
  try {
    Projector p(cam);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0x480"), std::string::npos) << e.what();
  }
  cam = makeCamera(kStandard);
  cam.height = kMaxViewportSide + 1;
  EXPECT_THROW(Projector{cam}, Error);
  cam = makeCamera(kStandard);
  cam.view_projection.m[3] = cam.view_projection.m[7] = cam.view_projection.m[11] =
      cam.view_projection.m[15] = 0;
  EXPECT_THROW(Projector{cam}, Error);
  cam = makeCamera(kStandard);
  cam.render_origin.x = INFINITY;
  EXPECT_THROW(Projector{cam}, Error);
}

TEST(ProjectionTest, MatrixHelpersRejectBadArguments) {
  EXPECT_THROW(perspective(1.0, 1.0, 0.0, 10.0, kStandard), Error);
  EXPECT_THROW(perspective(1.0, 1.0, 1.0, 0.5, kStandard), Error);
  EXPECT_THROW(perspective(0.0, 1.0, 0.1, 10.0, kStandard), Error);
  EXPECT_THROW(perspective(1.0, std::nan(""), 0.1, 10.0, kStandard), Error);
  EXPECT_THROW(orthographic(1, 0, 0, 1, 0, 1, kStandard), Error);
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 0, 0}, {0, 1, 0}), Error);
  EXPECT_THROW(lookAt({0, 0, 0}, {0, 1, 0}, {0, 1, 0}), Error);
  EXPECT_NO_THROW(perspective(1.0, 1.0, 0.1, INFINITY, kReversed));
}

TEST(ProjectionTest, PerspectiveMapsNearAndFarToTheConventionsDepths) {
  for (const DepthSetup& depth :
       {kStandard, kReversed,
        DepthSetup{DepthConvention::Standard, ClipDepthRange::ZeroToOne, DepthFormat::D32F},
        DepthSetup{DepthConvention::Reversed, ClipDepthRange::NegativeOneToOne,
                   DepthFormat::D32F}}) {
    const Mat4d m = perspective(1.0, 1.0, 0.5, 50, depth);
    auto ndc = [&](double z) { return (m(2, 2) * z + m(2, 3)) / (m(3, 2) * z + m(3, 3)); };
    const double low = depth.clip_range == ClipDepthRange::ZeroToOne ? 0.0 : -1.0;
    const bool rev = depth.convention == DepthConvention::Reversed;
    EXPECT_NEAR(ndc(-0.5), rev ? 1.0 : low, 1e-12);
    EXPECT_NEAR(ndc(-50), rev ? low : 1.0, 1e-12);
  }
}

// The bits of a float: the batch kernels must give the very same values, signed zeros
// included, not values that compare equal.
std::uint32_t bitsOf(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// A random camera of one of the depth set-ups: perspective or orthographic, near and
// far from 1e-4 to 1e7 (infinite far with reversed depth), eyes and render origins
// from the origin out to 1e7, viewports from 1 x 1 to 4096 x 3072, multisampled or not,
// and some with the margins' settings shrunk.
struct RandomCamera {
  Camera camera;
  ProjectionSettings settings;
  DVec3 eye, dir;  // where it looks from, and along
};

RandomCamera randomCamera(std::mt19937& rng, const DepthSetup& depth) {
  std::uniform_real_distribution<double> unit(0, 1);
  auto logUniform = [&](double lo, double hi) {
    return std::exp(std::log(lo) + unit(rng) * (std::log(hi) - std::log(lo)));
  };
  RandomCamera r;
  Camera& c = r.camera;
  c.depth = depth;
  c.width = 1 + std::uint32_t(unit(rng) < 0.1 ? 0 : logUniform(1, 4096));
  c.height = 1 + std::uint32_t(unit(rng) < 0.1 ? 0 : logUniform(1, 3072));
  c.multisample = unit(rng) < 0.3;
  const double scale = unit(rng) < 0.3 ? 0.0 : logUniform(1, 1e7);
  const DVec3 eye{scale * (unit(rng) - 0.5), scale * (unit(rng) - 0.5), scale * (unit(rng) - 0.5)};
  const DVec3 dir{unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5};
  r.eye = eye, r.dir = dir;
  const Mat4d view = lookAt(eye, {eye.x + dir.x, eye.y + dir.y, eye.z + dir.z}, {0, 1, 0});
  const double near = logUniform(1e-4, 10);
  const bool infinite = depth.convention == DepthConvention::Reversed && unit(rng) < 0.3;
  const double far =
      infinite ? std::numeric_limits<double>::infinity() : near * logUniform(2, 1e7 / near);
  const double aspect = double(c.width) / c.height;
  if (unit(rng) < 0.2 && !infinite) {
    const double half = logUniform(1e-2, 1e4);
    c.view_projection =
        multiply(orthographic(-half * aspect, half * aspect, -half, half, near, far, depth), view);
  } else {
    c.view_projection = multiply(perspective(logUniform(0.05, 3), aspect, near, far, depth), view);
  }
  c.render_origin = unit(rng) < 0.5 ? eye : DVec3{};
  if (unit(rng) < 0.2) {
    r.settings.subpixel_bits = int(unit(rng) * 17);
    r.settings.render_error_ulps = unit(rng) * 64;
    r.settings.quantisation_scale = unit(rng) * 2;
  }
  return r;
}

// Boxes around a camera: in front of it at every distance up to beyond the far plane,
// behind it, crossing the near plane, around the eye, flat or a single point, huge and
// far out, and invalid (NaN, infinite, inverted).
std::vector<Aabb> randomBoxes(std::mt19937& rng, const RandomCamera& camera, std::size_t count) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Aabb> boxes;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < count; ++i) {
    const double kind = unit(rng);
    const double reach = std::exp(std::log(1e-3) + unit(rng) * (std::log(1e9) - std::log(1e-3)));
    // Along the view direction (both ways) at any distance, and scattered around that.
    const double along = (unit(rng) < 0.8 ? 1 : -1) * reach * unit(rng) * 4;
    const DVec3 o{camera.eye.x + along * camera.dir.x, camera.eye.y + along * camera.dir.y,
                  camera.eye.z + along * camera.dir.z};
    const double spread = unit(rng) < 0.7 ? std::fabs(along) * 0.3 : reach * 2;
    DVec3 lo{o.x + spread * (unit(rng) - 0.5), o.y + spread * (unit(rng) - 0.5),
             o.z + spread * (unit(rng) - 0.5)};
    const double size = unit(rng) < 0.1 ? 0.0 : reach * unit(rng) * unit(rng);
    DVec3 hi{lo.x + size * unit(rng), lo.y + size * unit(rng), lo.z + size * unit(rng)};
    Aabb b{{float(lo.x), float(lo.y), float(lo.z)}, {float(hi.x), float(hi.y), float(hi.z)}};
    if (kind < 0.02)
      b.min.x = nan;
    else if (kind < 0.04)
      b.max.z = inf;
    else if (kind < 0.06)
      std::swap(b.min.y, b.max.y);
    else if (kind < 0.1)
      b.min = b.max;  // a point
    else if (kind < 0.12)
      b = {{-3e38f, -3e38f, -3e38f}, {3e38f, 3e38f, 3e38f}};
    boxes.push_back(b);
  }
  return boxes;
}

// What roundUp() and roundDown() must give, by the library's nextafter: the float
// nearest to v if it lies on the safe side, else the next one beyond it.
float referenceRoundUp(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
float referenceRoundDown(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}

TEST(ProjectionTest, DirectedRoundingGivesTheNearestFloatOnTheSafeSide) {
  // The projection's bounds go through detail::roundUp() and roundDown() (rounding.hpp,
  // computed without a branch on the value): every bit as nextafter gives it, at the
  // zeros, subnormals, the largest float, infinities, NaN, and random values of every
  // magnitude and sign.
  constexpr double kFltMax = std::numeric_limits<float>::max();
  constexpr double kDenorm = std::numeric_limits<float>::denorm_min();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> values = {0.0,
                                -0.0,
                                kDenorm,
                                -kDenorm,
                                kDenorm / 3,
                                -kDenorm / 3,
                                3 * kDenorm,
                                -3 * kDenorm,
                                1e-300,
                                -1e-300,
                                kFltMax,
                                -kFltMax,
                                kFltMax * 1.5,
                                -kFltMax * 1.5,
                                kFltMax * (1 + 1e-9),
                                -kFltMax * (1 + 1e-9),
                                kInf,
                                -kInf,
                                1.0,
                                -1.0,
                                1.0 + 1e-12,
                                -1.0 - 1e-12,
                                0.1,
                                -0.1};
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> mantissa(0.5, 1.0);
  std::uniform_int_distribution<int> exponent(-160, 140);
  for (int i = 0; i < 100000; ++i) {
    const double m = mantissa(rng);
    const double v = std::ldexp(m, exponent(rng));
    values.push_back(i % 2 ? v : -v);
    values.push_back(double(static_cast<float>(v)));  // a float: no step
  }
  for (const double v : values) {
    SCOPED_TRACE(::testing::Message() << "v = " << v);
    ASSERT_EQ(bitsOf(detail::roundUp(v)), bitsOf(referenceRoundUp(v)));
    ASSERT_EQ(bitsOf(detail::roundDown(v)), bitsOf(referenceRoundDown(v)));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(detail::roundUp(nan)));
  EXPECT_TRUE(std::isnan(detail::roundDown(nan)));
}

// Runs the batch calls on one instruction set's kernels while it lives.
class ForcedIsa {
 public:
  explicit ForcedIsa(detail::ProjectionIsa isa) : ok_(detail::forceProjectionIsa(isa)) {}
  ~ForcedIsa() { detail::resetProjectionIsa(); }
  ForcedIsa(const ForcedIsa&) = delete;
  ForcedIsa& operator=(const ForcedIsa&) = delete;
  bool ok() const { return ok_; }

 private:
  bool ok_;
};

void expectBatchKernelsAnswerAsTheSingleBoxPath();

TEST(ProjectionTest, BatchKernelsAnswerExactlyAsTheSingleBoxPath) {
  // Projector::project(boxes, count, out) and outsideFrustum(boxes, count, outside) run
  // the vectorised kernels; project(box) and outsideFrustum(box) the reference path.
  // Every field must be the same, bit for bit, for every box, in every set-up, with each
  // instruction set's kernels this CPU can run (the baseline's always).
  for (const auto isa : {detail::ProjectionIsa::Baseline, detail::ProjectionIsa::Avx2}) {
    if (!detail::projectionIsaAvailable(isa)) {
      std::printf("instruction set %d: not on this CPU or build\n", int(isa));
      continue;
    }
    const ForcedIsa forced(isa);
    ASSERT_TRUE(forced.ok());
    ASSERT_EQ(detail::projectionIsa(), isa);
    SCOPED_TRACE(::testing::Message() << "instruction set " << int(isa));
    expectBatchKernelsAnswerAsTheSingleBoxPath();
    if (HasFatalFailure()) return;
  }
  EXPECT_TRUE(detail::projectionIsaAvailable(detail::ProjectionIsa::Baseline));
}

// The batch kernels' answers for `boxes`, in batches of every size a node's children come
// in (1 to 8, and again).
struct BatchAnswers {
  std::vector<BoxProjection> projections;
  std::vector<std::uint8_t> outside;
};
BatchAnswers projectInBatches(const Projector& projector, const std::vector<Aabb>& boxes) {
  BatchAnswers out{std::vector<BoxProjection>(boxes.size()),
                   std::vector<std::uint8_t>(boxes.size())};
  for (std::size_t at = 0, n = 1; at < boxes.size(); at += n, n = n % 8 + 1) {
    const std::size_t len = std::min(n, boxes.size() - at);
    projector.project(boxes.data() + at, len, out.projections.data() + at);
    projector.outsideFrustum(boxes.data() + at, len, out.outside.data() + at);
  }
  return out;
}

// Whether box i's batch answer is the reference path's, every field bit for bit; names
// the first field that differs.
testing::AssertionResult sameAsSingleBox(const Projector& projector, const Aabb& box,
                                         const BatchAnswers& batch, std::size_t i) {
  const BoxProjection ref = projector.project(box);
  const BoxProjection& got = batch.projections[i];
  const auto differs = [](const char* field) {
    return testing::AssertionFailure() << field << " differs from the single-box path's";
  };
  if (got.cls != ref.cls) return differs("cls");
  if (got.rect.x0 != ref.rect.x0 || got.rect.y0 != ref.rect.y0 || got.rect.x1 != ref.rect.x1 ||
      got.rect.y1 != ref.rect.y1) {
    return differs("rect");
  }
  if (bitsOf(got.near_key) != bitsOf(ref.near_key)) return differs("near_key");
  if (bitsOf(got.far_key) != bitsOf(ref.far_key)) return differs("far_key");
  if (bitsOf(got.margin) != bitsOf(ref.margin)) return differs("margin");
  if (bitsOf(got.widen_x) != bitsOf(ref.widen_x)) return differs("widen_x");
  if (bitsOf(got.widen_y) != bitsOf(ref.widen_y)) return differs("widen_y");
  if (bool(batch.outside[i]) != projector.outsideFrustum(box)) return differs("outsideFrustum");
  return testing::AssertionSuccess();
}

TEST(ProjectionTest, BatchKernelsAnswerAsTheSingleBoxPathWhereClipCoordinatesOverflow) {
  // The kernels test the near and far planes without their x and y terms (zero
  // coefficients) only where no clip coordinate can overflow; with a matrix of huge
  // (finite, valid) elements, clip x or y reaches infinity, 0 * infinity is NaN in the
  // reference's sum, and the kernels must take the full sums to answer alike.
  for (const auto isa : {detail::ProjectionIsa::Baseline, detail::ProjectionIsa::Avx2}) {
    if (!detail::projectionIsaAvailable(isa)) continue;
    const ForcedIsa forced(isa);
    ASSERT_TRUE(forced.ok());
    SCOPED_TRACE(::testing::Message() << "instruction set " << int(isa));
    for (const double scale : {1e270, 1e290, 1e300}) {
      for (const DepthSetup& depth : {kStandard, kReversed}) {
        Camera camera = makeCamera(depth);
        for (double& m : camera.view_projection.m) m *= scale;
        const Projector projector(camera);
        std::vector<Aabb> boxes;
        for (const float reach : {1.0f, 1e10f, 1e20f, 1e30f, 3e38f}) {
          // Ahead, wide to the sides, beside and behind the eye, across the near plane.
          boxes.push_back({{-reach, -reach, -reach}, {reach, reach, -reach * 0.5f}});
          boxes.push_back({{reach * 0.5f, -1, -reach}, {reach, 1, -reach * 0.9f}});
          boxes.push_back({{-reach, -reach, 0}, {-reach * 0.5f, reach, reach}});
          boxes.push_back({{-1, -1, -reach}, {1, 1, reach}});
          boxes.push_back({{-reach, -reach, -reach}, {reach, reach, reach}});
        }
        SCOPED_TRACE(::testing::Message()
                     << "scale " << scale << ", depth " << int(depth.convention));
        const BatchAnswers batch = projectInBatches(projector, boxes);
        for (std::size_t i = 0; i < boxes.size(); ++i) {
          EXPECT_TRUE(sameAsSingleBox(projector, boxes[i], batch, i)) << "box " << i;
        }
      }
    }
  }
}

void expectBatchKernelsAnswerAsTheSingleBoxPath() {
  const DepthSetup setups[] = {
      {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F},
      {DepthConvention::Standard, ClipDepthRange::ZeroToOne, DepthFormat::D24},
      {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D16},
      {DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D32F},
      {DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D24},
  };
  std::mt19937 rng(26);
  std::size_t compared = 0, inside = 0, crossing = 0, outside = 0, invalid = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const RandomCamera rc = randomCamera(rng, setups[trial % 5]);
    const Projector projector(rc.camera, rc.settings);
    const std::vector<Aabb> boxes = randomBoxes(rng, rc, 256);
    const BatchAnswers batch = projectInBatches(projector, boxes);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      ASSERT_TRUE(sameAsSingleBox(projector, boxes[i], batch, i))
          << "trial " << trial << ", box " << i;
      ++compared;
      switch (batch.projections[i].cls) {
        case ProjectionClass::Inside: ++inside; break;
        case ProjectionClass::CrossesNear: ++crossing; break;
        case ProjectionClass::Outside: ++outside; break;
        case ProjectionClass::Invalid: ++invalid; break;
      }
    }
  }
  // Each class met often enough for the comparison to mean something.
  EXPECT_EQ(compared, 400u * 256u);
  EXPECT_GT(inside, 5000u);
  EXPECT_GT(crossing, 2000u);
  EXPECT_GT(outside, 5000u);
  EXPECT_GT(invalid, 2000u);
}

}  // namespace
}  // namespace logrid
