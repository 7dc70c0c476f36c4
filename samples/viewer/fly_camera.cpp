#include "viewer/fly_camera.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "logrid/error.hpp"

namespace logrid::viewer {

FlyCamera::FlyCamera(const samples::CameraPose& pose, double speed) {
  const double up_length = glm::length(pose.up);
  if (!(up_length > 0) || !std::isfinite(up_length)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: the path's up vector must be finite and non-zero");
  }
  if (!(speed > 0) || !std::isfinite(speed)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: speed " + std::to_string(speed) + " must be finite and positive");
  }
  up_ = pose.up / up_length;
  // East: the world axis least aligned with up, made perpendicular to it.
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  const glm::dvec3* best = &axes[0];
  for (const glm::dvec3& a : axes) {
    if (std::fabs(glm::dot(a, up_)) < std::fabs(glm::dot(*best, up_))) best = &a;
  }
  east_ = glm::normalize(*best - up_ * glm::dot(*best, up_));
  north_ = glm::cross(up_, east_);
  speed_ = initial_speed_ = speed;
  setPose(pose);
}

void FlyCamera::setPose(const samples::CameraPose& pose) {
  const glm::dvec3 d = pose.look_at - pose.position;
  const double distance = glm::length(d);
  if (!(distance > 0) || !std::isfinite(distance)) {
    throw Error(ErrorCode::InvalidArgument,
                "fly camera: a pose's look_at must differ from its position");
  }
  position_ = pose.position;
  focus_ = distance;
  const glm::dvec3 f = d / distance;
  pitch_ = std::clamp(std::asin(std::clamp(glm::dot(f, up_), -1.0, 1.0)), -kMaxPitch, kMaxPitch);
  yaw_ = std::atan2(glm::dot(f, north_), glm::dot(f, east_));
}

glm::dvec3 FlyCamera::forward() const {
  const double c = std::cos(pitch_);
  return east_ * (c * std::cos(yaw_)) + north_ * (c * std::sin(yaw_)) + up_ * std::sin(pitch_);
}

glm::dvec3 FlyCamera::right() const {
  // Horizontal: east and north turned by yaw, a quarter turn clockwise seen from above.
  return east_ * std::sin(yaw_) - north_ * std::cos(yaw_);
}

samples::CameraPose FlyCamera::pose() const {
  samples::CameraPose p;
  p.position = position_;
  p.look_at = position_ + forward() * focus_;
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
  position_ += forward() * (c(forward_amount) * step) + right() * (c(right_amount) * step) +
               up_ * (c(up_amount) * step);
}

void FlyCamera::scaleSpeed(double steps) {
  if (!std::isfinite(steps)) return;
  speed_ = std::clamp(speed_ * std::pow(1.25, steps), initial_speed_ * 1e-6, initial_speed_ * 1e6);
}

}  // namespace logrid::viewer
