// libFuzzer target: the mesh-animation JSON of scenes from files (--animate FILE.json,
// samples/scene/motion.hpp) through animateMeshes on a scene of eight meshes, the first
// byte giving the scene's origin (0: none, else far from the world origin, where the paths
// are moved to local coordinates). Every input must either be refused with a
// logrid::Error(BadInput) naming the file, or animate some of the meshes (never all),
// each along a path of two or more finite points with a finite, positive length, at a
// finite speed, whose box at any time (before the start, on the way, after many laps,
// in its stops) is a box of finite floats that holds the mesh's box moved to its point on
// the path. A motion file never makes the culler or the oracle see NaN.
#include <unistd.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_check.hpp"
#include "logrid/error.hpp"
#include "scene/movers.hpp"
#include "scene/scene.hpp"

namespace {

namespace fs = std::filesystem;

// Eight unit boxes in a row (no triangles needed: only the boxes move).
logrid::samples::Scene eightMeshes(std::uint8_t origin) {
  logrid::samples::Scene s;
  for (int i = 0; i < 8; ++i) {
    logrid::samples::SceneObject o;
    o.box = {{float(2 * i), 0, 0}, {float(2 * i + 1), 1, 1}};
    s.objects.push_back(o);
  }
  if (origin) s.origin = {1e6 * origin, -3e5, 7e6};
  return s;
}

bool finiteBox(const logrid::Aabb& b) {
  return std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) &&
         std::isfinite(b.max.x) && std::isfinite(b.max.y) && std::isfinite(b.max.z) &&
         b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static logrid::fuzz::ScratchDir scratch("animation_fuzzer");
  if (size == 0) return 0;
  const std::string path = (scratch.dir / "motion.json").string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    LOGRID_FUZZ_CHECK(out.good(), "cannot write the input to %s", path.c_str());
  }
  logrid::samples::Scene scene = eightMeshes(data[0] % 4);
  try {
    logrid::samples::animateMeshes(scene, path);
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(e.code() == logrid::ErrorCode::BadInput, "unexpected error code %d: %s",
                      int(e.code()), e.what());
    LOGRID_FUZZ_CHECK(std::string(e.what()).find(path) != std::string::npos,
                      "the error does not name the file: %s", e.what());
    return 0;
  } catch (const std::exception& e) {
    LOGRID_FUZZ_CHECK(false, "not a logrid::Error: %s", e.what());
  }
  const logrid::samples::Motion& motion = scene.motion;
  LOGRID_FUZZ_CHECK(!scene.objects.empty(), "every mesh was animated");
  LOGRID_FUZZ_CHECK(motion.movers.size() == scene.moving.size(), "%zu movers, %zu moving meshes",
                    motion.movers.size(), scene.moving.size());
  LOGRID_FUZZ_CHECK(scene.objects.size() + scene.moving.size() == 8, "meshes lost or added");
  for (std::size_t i = 0; i < motion.movers.size(); ++i) {
    const logrid::samples::MoverSpec& m = motion.movers[i];
    LOGRID_FUZZ_CHECK(m.path < motion.paths.size(), "mover %zu: path %u", i, m.path);
    const logrid::samples::MotionPath& p = motion.paths[m.path];
    LOGRID_FUZZ_CHECK(p.points.size() >= 2 && std::isfinite(p.length()) && p.length() > 0,
                      "mover %zu: %zu points, length %.17g", i, p.points.size(), p.length());
    LOGRID_FUZZ_CHECK(std::isfinite(m.speed) && std::isfinite(m.offset) &&
                          std::isfinite(m.move_seconds) && std::isfinite(m.stop_seconds),
                      "mover %zu: speed %.17g offset %.17g move %.17g stop %.17g", i, m.speed,
                      m.offset, m.move_seconds, m.stop_seconds);
    for (double t : {-100.0, 0.0, 0.5, 7.25, 1e3, 1e6}) {
      const logrid::Aabb b = motion.boxAt(i, t);
      LOGRID_FUZZ_CHECK(finiteBox(b),
                        "mover %zu at time %g: box (%g, %g, %g)-(%g, %g, %g) is not a finite box",
                        i, t, double(b.min.x), double(b.min.y), double(b.min.z), double(b.max.x),
                        double(b.max.y), double(b.max.z));
    }
  }
  return 0;
}
