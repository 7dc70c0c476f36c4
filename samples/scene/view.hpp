// Cameras for the samples: a pose on a camera path (world coordinates) and the
// viewport and depth settings of a run, turned into the logrid::Camera that both the
// culler and the renderer use. The camera maps the scene's *local* coordinates to clip
// space (projection * view * translation(scene origin), composed in double) and puts
// the render origin at the eye, so rendering is camera-relative (mesh_renderer.hpp).
#pragma once

#include "logrid/camera.hpp"
#include "scene/camera_path.hpp"

namespace logrid::samples {

struct ViewSettings {
  std::uint32_t width = 640;
  std::uint32_t height = 480;
  double fov_degrees = 60.0;  // vertical field of view (perspective)
  bool orthographic = false;  // then the view volume is as high as the perspective
                              // view's at the look-at distance
  double near_plane = 0.1;
  double far_plane = 1000.0;
  DepthSetup depth;
  // Samples per pixel of the framebuffer (0: single-sampled); sets Camera::multisample.
  std::uint32_t samples = 0;
  // The renderer culls back faces (counter-clockwise triangles face the viewer), in the
  // frames and the ID pass alike. What lets a clustered scene skip clusters that face
  // away (RunConfig::backface_clusters).
  bool cull_back_faces = false;
};

// The usual clip range for a convention: -1..1 (GL's default) for standard, 0..1 for
// reversed.
DepthSetup depthSetupFor(DepthConvention convention, DepthFormat format);

Camera makeCamera(const CameraPose& pose, const glm::dvec3& scene_origin, const ViewSettings& view);

}  // namespace logrid::samples
