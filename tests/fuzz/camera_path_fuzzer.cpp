// libFuzzer target: the camera-path JSON reader (CameraPath::fromJsonText) and the
// poses and cameras of a path it accepts. Every input must either be refused with a
// logrid::Error or give a path whose poses, at any time and for any frame count, are
// finite with position != look_at, and whose cameras (makeCamera, both depth
// conventions) either pass validateCamera or are refused by lookAt with a logrid::Error
// (up parallel to the view direction). A path never makes the culler see NaN.
#include <cmath>
#include <exception>
#include <string>

#include <glm/glm.hpp>

#include "fuzz_check.hpp"
#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "scene/camera_path.hpp"
#include "scene/view.hpp"

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkPose(const logrid::samples::CameraPose& pose, double time) {
  LOGRID_FUZZ_CHECK(finite(pose.position) && finite(pose.look_at) && finite(pose.up),
                    "pose at time %.17g is not finite", time);
  LOGRID_FUZZ_CHECK(pose.position.x != pose.look_at.x || pose.position.y != pose.look_at.y ||
                        pose.position.z != pose.look_at.z,
                    "pose at time %.17g has position == look_at", time);
  for (bool reversed : {false, true}) {
    logrid::samples::ViewSettings view;
    view.width = 64;
    view.height = 48;
    view.depth = logrid::samples::depthSetupFor(
        reversed ? logrid::DepthConvention::Reversed : logrid::DepthConvention::Standard,
        logrid::DepthFormat::D32F);
    try {
      const logrid::Camera camera = logrid::samples::makeCamera(pose, {0, 0, 0}, view);
      const std::string problem = logrid::validateCamera(camera);
      LOGRID_FUZZ_CHECK(problem.empty(), "the camera at time %.17g is invalid: %s", time,
                        problem.c_str());
    } catch (const logrid::Error& e) {
      LOGRID_FUZZ_CHECK(std::string(e.what()).find("lookAt") != std::string::npos,
                        "makeCamera at time %.17g: unexpected error: %s", time, e.what());
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  logrid::samples::CameraPath path;
  try {
    path = logrid::samples::CameraPath::fromJsonText(text, "fuzz.json");
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(
        e.code() == logrid::ErrorCode::BadInput || e.code() == logrid::ErrorCode::InvalidArgument,
        "unexpected error code %d: %s", int(e.code()), e.what());
    LOGRID_FUZZ_CHECK(std::string(e.what()).find("fuzz.json") != std::string::npos,
                      "the error does not name the file: %s", e.what());
    return 0;
  } catch (const std::exception& e) {
    LOGRID_FUZZ_CHECK(false, "not a logrid::Error: %s", e.what());
  }
  LOGRID_FUZZ_CHECK(!path.empty(), "accepted a path without keys");
  const double start = path.keys().front().time, duration = path.duration();
  LOGRID_FUZZ_CHECK(std::isfinite(duration) && duration >= 0, "duration %.17g", duration);
  // Key times, the middle of every segment (a few hundred at most), and beyond both ends.
  const std::size_t keys = path.keys().size();
  const std::size_t step = keys > 256 ? keys / 256 : 1;
  for (std::size_t i = 0; i < keys; i += step) {
    const double t = path.keys()[i].time;
    checkPose(path.at(t), t);
    if (i + 1 < keys) {
      const double mid = 0.5 * (t + path.keys()[i + 1].time);
      checkPose(path.at(mid), mid);
    }
  }
  for (double t : {start - 1.0, start + duration + 1.0, start + duration * 0.3}) {
    checkPose(path.at(t), t);
  }
  for (std::size_t frames : {std::size_t(1), std::size_t(7)}) {
    for (std::size_t f = 0; f < frames; ++f) checkPose(path.frame(f, frames), double(f));
  }
  return 0;
}
