#include "viewer/fly_camera.hpp"

#include <algorithm>
#include <cmath>

#include "logrid/error.hpp"

namespace logrid::viewer {
namespace {

DVec3 add(DVec3 a, DVec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
DVec3 sub(DVec3 a, DVec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
DVec3 mul(DVec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DVec3 cross(DVec3 a, DVec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(DVec3 a) { return std::sqrt(dot(a, a)); }

}  // namespace

FlyCamera::FlyCamera(const samples::CameraPose& pose, double speed) {
  const double up_length = length(pose.up);
  if (!(up_length > 0) || !std::isfinite(up_length)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: the path's up vector must be finite and non-zero");
  }
  if (!(speed > 0) || !std::isfinite(speed)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: speed " + std::to_string(speed) + " must be finite and positive");
  }
  up_ = mul(pose.up, 1 / up_length);
  // East: the world axis least aligned with up, made perpendicular to it.
  const DVec3 axes[3] = {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  const DVec3* best = &axes[0];
  for (const DVec3& a : axes) {
    if (std::fabs(dot(a, up_)) < std::fabs(dot(*best, up_))) best = &a;
  }
  east_ = sub(*best, mul(up_, dot(*best, up_)));
  east_ = mul(east_, 1 / length(east_));
  north_ = cross(up_, east_);
  speed_ = initial_speed_ = speed;
  setPose(pose);
}

void FlyCamera::setPose(const samples::CameraPose& pose) {
  const DVec3 d = sub(pose.look_at, pose.position);
  const double distance = length(d);
  if (!(distance > 0) || !std::isfinite(distance)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: a pose's look_at must differ from its position");
  }
  position_ = pose.position;
  focus_ = distance;
  const DVec3 f = mul(d, 1 / distance);
  pitch_ = std::clamp(std::asin(std::clamp(dot(f, up_), -1.0, 1.0)), -kMaxPitch, kMaxPitch);
  yaw_ = std::atan2(dot(f, north_), dot(f, east_));
}

DVec3 FlyCamera::forward() const {
  const double c = std::cos(pitch_);
  return add(add(mul(east_, c * std::cos(yaw_)), mul(north_, c * std::sin(yaw_))),
             mul(up_, std::sin(pitch_)));
}

DVec3 FlyCamera::right() const {
  // Horizontal: east and north turned by yaw, a quarter turn clockwise seen from above.
  return sub(mul(east_, std::sin(yaw_)), mul(north_, std::cos(yaw_)));
}

samples::CameraPose FlyCamera::pose() const {
  samples::CameraPose p;
  p.position = position_;
  p.look_at = add(position_, mul(forward(), focus_));
  p.up = up_;
  return p;
}

void FlyCamera::look(double dx, double dy) {
  if (!std::isfinite(dx) || !std::isfinite(dy)) return;
  yaw_ = std::remainder(yaw_ - dx * kLookRadiansPerPixel, 2 * M_PI);
  pitch_ = std::clamp(pitch_ - dy * kLookRadiansPerPixel, -kMaxPitch, kMaxPitch);
}

void FlyCamera::move(double forward_amount, double right_amount, double up_amount, double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds)) return;
  const double step = speed_ * seconds;
  auto c = [](double v) { return std::isfinite(v) ? std::clamp(v, -1.0, 1.0) : 0.0; };
  position_ = add(position_, mul(forward(), c(forward_amount) * step));
  position_ = add(position_, mul(right(), c(right_amount) * step));
  position_ = add(position_, mul(up_, c(up_amount) * step));
}

void FlyCamera::scaleSpeed(double steps) {
  if (!std::isfinite(steps)) return;
  speed_ = std::clamp(speed_ * std::pow(1.25, steps), initial_speed_ * 1e-6, initial_speed_ * 1e6);
}

}  // namespace logrid::viewer
