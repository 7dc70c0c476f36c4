// Camera paths: key frames (eye position, look-at point, optional time) interpolated
// smoothly, in world coordinates (double precision, GLM vectors as everywhere in the
// samples).
//
// JSON format (--path FILE.json):
//   { "keys": [ { "position": [x, y, z], "look_at": [x, y, z], "time": 0.0 }, ... ],
//     "up": [0, 1, 0] }                                    // optional, default +y
// "time" is optional for every key or for none: without times, keys are spaced by the
// distance travelled (constant speed). Times must increase strictly. At least one key.
// In C++, keys that all leave `time` at 0 are untimed in the same way.
#pragma once

#include <string>
#include <vector>

#include <glm/ext/vector_double3.hpp>

namespace logrid::samples {

struct CameraKey {
  glm::dvec3 position{0.0};
  glm::dvec3 look_at{0.0};
  double time = 0.0;
};

struct CameraPose {
  glm::dvec3 position{0.0};
  glm::dvec3 look_at{0.0};
  glm::dvec3 up{0, 1, 0};
};

class CameraPath {
 public:
  CameraPath() = default;
  // Throws logrid::Error(InvalidArgument) for no keys, non-finite values, a key whose
  // position equals its look_at, or times that do not increase (keys whose times are all
  // 0 are first spaced at constant speed).
  CameraPath(std::vector<CameraKey> keys, glm::dvec3 up = {0, 1, 0});

  // Reads the JSON format above; throws logrid::Error with the file name and what is
  // wrong: Environment for a missing, unreadable or directory path; BadInput for a file
  // over 64 MiB, a JSON syntax error (with its byte position), missing or mistyped
  // fields, more than 1,000,000 keys, and the checks of the constructor.
  static CameraPath fromJsonFile(const std::string& path);
  static CameraPath fromJsonText(const std::string& text, const std::string& name = "<json>");

  bool empty() const { return keys_.empty(); }
  const std::vector<CameraKey>& keys() const { return keys_; }
  double duration() const;

  // The pose at `time` (clamped to the path), interpolated with a centripetal
  // Catmull-Rom spline through the keys (positions and look-at points alike).
  CameraPose at(double time) const;
  // The pose of frame `frame` of `frames` frames spread evenly over the whole path.
  CameraPose frame(std::size_t frame, std::size_t frames) const;
  // The time of that frame (the time moving objects are evaluated at, motion.hpp).
  // Throws like frame().
  double frameTime(std::size_t frame, std::size_t frames) const;

 private:
  std::vector<CameraKey> keys_;
  glm::dvec3 up_{0, 1, 0};
};

}  // namespace logrid::samples
