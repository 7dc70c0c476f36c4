// The viewer's camera: a position and a look direction (yaw about the path's up axis,
// pitch towards it), flown with keys and turned with the mouse, convertible to and from
// the camera-path poses that `walk` and `bench` use.
#pragma once

#include "scene/camera_path.hpp"

namespace logrid::viewer {

// Radians the view turns per pixel of mouse motion.
inline constexpr double kLookRadiansPerPixel = 0.004;
// Pitch stays this far from straight up or down (so the view never flips over).
inline constexpr double kMaxPitch = 1.5533;  // 89 degrees

class FlyCamera {
 public:
  // `speed`: world units per second. Throws logrid::Error(InvalidArgument) for a pose
  // whose position equals its look_at, or a zero or non-finite up vector or speed.
  FlyCamera(const samples::CameraPose& pose, double speed);

  // Takes a pose (e.g. from path playback); keeps up axis and speed. The distance to
  // look_at is kept as the focus distance (it sizes orthographic views).
  void setPose(const samples::CameraPose& pose);
  samples::CameraPose pose() const;

  // Mouse motion in window pixels (x right, y down): right turns right, up looks up.
  void look(double dx, double dy);
  // Moves along the view direction, its horizontal right and the up axis, each in
  // [-1, 1] (more is clamped), for `seconds` at the current speed.
  void move(double forward, double right, double up, double seconds);

  double speed() const { return speed_; }
  // Multiplies the speed by 1.25 per wheel step (negative steps slow down), kept within
  // [1e-6, 1e6] times the initial speed.
  void scaleSpeed(double steps);

  const glm::dvec3& position() const { return position_; }
  double yaw() const { return yaw_; }
  double pitch() const { return pitch_; }
  glm::dvec3 forward() const;
  glm::dvec3 right() const;  // horizontal, perpendicular to forward and up
  const glm::dvec3& up() const { return up_; }
  // The horizontal axes of a view from above: `east` to the right, `north` up the page.
  const glm::dvec3& east() const { return east_; }
  const glm::dvec3& north() const { return north_; }

 private:
  glm::dvec3 up_, east_, north_;  // orthonormal, right-handed: east x north = up
  glm::dvec3 position_;
  double yaw_ = 0;    // from east towards north
  double pitch_ = 0;  // towards up
  double focus_ = 1;  // distance to the look-at point
  double speed_ = 1;
  double initial_speed_ = 1;
};

}  // namespace logrid::viewer
