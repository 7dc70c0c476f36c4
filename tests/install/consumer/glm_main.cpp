// A user of an installed logrid whose application keeps its matrices in GLM: builds the
// camera with the optional header logrid/glm_camera.hpp (which needs GLM, found by the
// consumer itself) and projects a box in front of the eye and one behind it.
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <cstdio>
#include <string>

#include "logrid/glm_camera.hpp"
#include "logrid/projection.hpp"

int main() {
  const glm::mat4 projection = glm::perspective(1.0f, 4.0f / 3.0f, 0.5f, 100.0f);
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
  const logrid::Camera camera = logrid::cameraFromGlm(
      projection, view, 320, 240,
      {logrid::DepthConvention::Standard, logrid::glmClipDepthRange(), logrid::DepthFormat::D32F});
  const std::string problem = logrid::validateCamera(camera);
  if (!problem.empty()) {
    std::printf("consumer_glm: FAIL: %s\n", problem.c_str());
    return 1;
  }
  const logrid::Projector projector(camera);
  const bool front =
      projector.project({{-1, -1, -1}, {1, 1, 1}}).cls == logrid::ProjectionClass::Inside;
  const bool behind =
      projector.project({{-1, -1, 8}, {1, 1, 9}}).cls == logrid::ProjectionClass::Outside;
  std::printf("consumer_glm: box in front %s, box behind the eye %s\n",
              front ? "inside" : "NOT inside", behind ? "outside" : "NOT outside");
  return front && behind ? 0 : 1;
}
