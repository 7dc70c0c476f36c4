#include "scene/view.hpp"

#include <cmath>

namespace logrid::samples {

DepthSetup depthSetupFor(DepthConvention convention, DepthFormat format) {
  return {convention,
          convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                  : ClipDepthRange::NegativeOneToOne,
          format};
}

Camera makeCamera(const CameraPose& pose, const DVec3& scene_origin, const ViewSettings& view) {
  Camera camera;
  camera.width = view.width;
  camera.height = view.height;
  camera.depth = view.depth;
  camera.multisample = view.samples > 1;
  const double aspect = double(view.width) / double(view.height);
  const double fovy = view.fov_degrees * M_PI / 180.0;
  Mat4d projection;
  if (view.orthographic) {
    const DVec3 d{pose.look_at.x - pose.position.x, pose.look_at.y - pose.position.y,
                  pose.look_at.z - pose.position.z};
    const double distance = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    const double half_h = distance * std::tan(fovy / 2), half_w = half_h * aspect;
    projection =
        orthographic(-half_w, half_w, -half_h, half_h, view.near_plane, view.far_plane, view.depth);
  } else {
    projection = perspective(fovy, aspect, view.near_plane, view.far_plane, view.depth);
  }
  const Mat4d view_matrix = lookAt(pose.position, pose.look_at, pose.up);
  camera.view_projection = multiply(multiply(projection, view_matrix), translation(scene_origin));
  camera.render_origin = {pose.position.x - scene_origin.x, pose.position.y - scene_origin.y,
                          pose.position.z - scene_origin.z};
  return camera;
}

}  // namespace logrid::samples
