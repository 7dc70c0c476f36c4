// The viewer's fly camera (samples/viewer/fly_camera.hpp): poses in and out, turning
// and moving the way a person expects.
#include "viewer/fly_camera.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "expect_error.hpp"

namespace {

using DVec3 = glm::dvec3;
using logrid::samples::CameraPose;
using logrid::viewer::FlyCamera;

double dot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DVec3 sub(DVec3 a, DVec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double length(DVec3 a) { return std::sqrt(dot(a, a)); }

CameraPose pose(DVec3 position, DVec3 look_at, DVec3 up = {0, 1, 0}) {
  CameraPose p;
  p.position = position;
  p.look_at = look_at;
  p.up = up;
  return p;
}

TEST(FlyCameraTest, KeepsThePoseItIsGiven) {
  for (DVec3 up : {DVec3{0, 1, 0}, DVec3{0, 0, 1}, DVec3{0.3, 0.9, -0.2}}) {
    const CameraPose in = pose({1, 2, 3}, {4, 1, -5}, up);
    const FlyCamera camera(in, 1.0);
    const CameraPose out = camera.pose();
    EXPECT_NEAR(length(sub(out.position, in.position)), 0, 1e-12);
    EXPECT_NEAR(length(sub(out.look_at, in.look_at)), 0, 1e-9);
    EXPECT_NEAR(dot(camera.east(), camera.north()), 0, 1e-12);
    EXPECT_NEAR(dot(camera.right(), camera.forward()), 0, 1e-12);
    EXPECT_NEAR(dot(camera.right(), camera.up()), 0, 1e-12);
  }
}

TEST(FlyCameraTest, MouseRightTurnsRightAndMouseUpLooksUp) {
  FlyCamera camera(pose({0, 0, 0}, {0, 0, -10}), 1.0);
  const DVec3 right = camera.right();
  EXPECT_GT(right.x, 0.99);  // looking down -z with y up, right is +x
  camera.look(50, 0);
  EXPECT_GT(dot(camera.forward(), right), 0.1);
  camera.look(0, -50);  // mouse up (window y grows downwards)
  EXPECT_GT(camera.forward().y, 0.1);
  camera.look(0, -1e6);  // never over the top
  EXPECT_LT(camera.pitch(), logrid::viewer::kMaxPitch + 1e-12);
  EXPECT_GT(camera.forward().y, 0.99);
  EXPECT_GT(length(sub(camera.pose().look_at, camera.pose().position)), 0);
}

TEST(FlyCameraTest, MovesAtItsSpeedAlongItsAxes) {
  FlyCamera camera(pose({0, 0, 0}, {0, 0, -10}), 2.0);
  camera.move(1, 0, 0, 0.5);  // 1 unit forward
  EXPECT_NEAR(camera.position().z, -1, 1e-12);
  camera.move(0, -5, 0, 0.5);  // clamped to 1: 1 unit left
  EXPECT_NEAR(camera.position().x, -1, 1e-12);
  camera.move(0, 0, 1, 0.25);
  EXPECT_NEAR(camera.position().y, 0.5, 1e-12);
  camera.move(1, 0, 0, NAN);  // ignored
  EXPECT_NEAR(camera.position().z, -1, 1e-12);
  camera.scaleSpeed(2);
  EXPECT_NEAR(camera.speed(), 2 * 1.5625, 1e-12);
  camera.scaleSpeed(-1000);
  EXPECT_NEAR(camera.speed(), 2e-6, 1e-18);
}

TEST(FlyCameraTest, RefusesPosesItCannotFly) {
  logrid::test::expectError(
      [] {
        FlyCamera(pose({1, 1, 1}, {1, 1, 1}), 1.0);
      },
      logrid::ErrorCode::InvalidArgument, {"look_at"});
  logrid::test::expectError(
      [] {
        FlyCamera(pose({0, 0, 0}, {1, 0, 0}, {0, 0, 0}), 1.0);
      },
      logrid::ErrorCode::InvalidArgument, {"up vector"});
  logrid::test::expectError(
      [] {
        FlyCamera(pose({0, 0, 0}, {1, 0, 0}), 0.0);
      },
      logrid::ErrorCode::InvalidArgument, {"speed"});
}

}  // namespace
