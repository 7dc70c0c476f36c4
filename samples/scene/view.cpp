#include "scene/view.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "logrid/glm_camera.hpp"

namespace logrid::samples {

DepthSetup depthSetupFor(DepthConvention convention, DepthFormat format) {
  return {convention,
          convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                  : ClipDepthRange::NegativeOneToOne,
          format};
}

Camera makeCamera(const CameraPose& pose, const glm::dvec3& scene_origin,
                  const ViewSettings& view) {
  const double aspect = double(view.width) / double(view.height);
  const double fovy = view.fov_degrees * M_PI / 180.0;
  // The projection comes from logrid's helper, which builds every depth set-up (reversed
  // and infinite depth included) from the same DepthSetup the camera carries; lookAt too,
  // for its check of the pose.
  Mat4d projection;
  if (view.orthographic) {
    const double distance = glm::distance(pose.position, pose.look_at);
    const double half_h = distance * std::tan(fovy / 2), half_w = half_h * aspect;
    projection =
        orthographic(-half_w, half_w, -half_h, half_h, view.near_plane, view.far_plane, view.depth);
  } else {
    projection = perspective(fovy, aspect, view.near_plane, view.far_plane, view.depth);
  }
  const Mat4d world_view = lookAt(toDVec3(pose.position), toDVec3(pose.look_at), toDVec3(pose.up));
  // Local (scene) coordinates to world, then to eye space, all in double and in logrid's
  // matrices: the pose's GLM vectors are converted once, here.
  Camera camera;
  camera.view_projection =
      multiply(projection, multiply(world_view, translation(toDVec3(scene_origin))));
  camera.width = view.width;
  camera.height = view.height;
  camera.depth = view.depth;
  camera.render_origin = toDVec3(pose.position - scene_origin);
  camera.multisample = view.samples > 1;
  return camera;
}

}  // namespace logrid::samples
