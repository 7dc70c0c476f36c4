// libFuzzer target: model files through loadSceneFile (samples/scene/loader.hpp), the
// loader's own pre-checks (file, PLY header and data, glTF JSON and node graph) and
// assimp behind them. The first byte picks the format by extension (OBJ, PLY, STL, glTF,
// GLB: the formats the loader tests cover; assimp's other importers are not fuzzed here),
// the rest is the file. Every input must either load into a scene that passes
// validateScene, with finite boxes around every object, or be refused with a
// logrid::Error naming the file. Anything else (another exception, a crash, a sanitizer
// report, a hang past libFuzzer's -timeout) is a finding.
#include <unistd.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_check.hpp"
#include "logrid/error.hpp"
#include "scene/loader.hpp"
#include "scene/scene.hpp"

// Assimp 5.2 leaks on the error paths of some importers (tests/fuzz/loader_fuzz_test.cpp);
// only leaks whose stack runs through assimp are suppressed.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so"; }

namespace {

namespace fs = std::filesystem;

constexpr const char* kExtensions[] = {".obj", ".ply", ".stl", ".gltf", ".glb"};

bool finiteBox(const logrid::Aabb& b) {
  return std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) &&
         std::isfinite(b.max.x) && std::isfinite(b.max.y) && std::isfinite(b.max.z) &&
         b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static logrid::fuzz::ScratchDir scratch("loader_fuzzer");
  if (size == 0) return 0;
  const char* extension = kExtensions[data[0] % (sizeof kExtensions / sizeof *kExtensions)];
  const std::string path = (scratch.dir / (std::string("input") + extension)).string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    LOGRID_FUZZ_CHECK(out.good(), "cannot write the input to %s", path.c_str());
  }
  logrid::samples::LoadOptions options;
  // Small inputs must not be allowed to ask for more than the fuzzer's memory limit.
  options.max_triangles = 1'000'000;
  try {
    const logrid::samples::Scene scene = logrid::samples::loadSceneFile(path, options);
    try {
      logrid::samples::validateScene(scene);
    } catch (const logrid::Error& e) {
      LOGRID_FUZZ_CHECK(false, "loaded a scene that fails validateScene: %s", e.what());
    }
    LOGRID_FUZZ_CHECK(!scene.objects.empty() || scene.split_by_triangles,
                      "loaded a scene without objects");
    LOGRID_FUZZ_CHECK(finiteBox(scene.bounds), "scene bounds are not a finite box");
    for (const logrid::samples::SceneObject& o : scene.objects) {
      LOGRID_FUZZ_CHECK(finiteBox(o.box), "an object's box is not a finite box");
    }
    LOGRID_FUZZ_CHECK(!scene.path.empty(), "loaded a scene without a camera path");
  } catch (const logrid::Error& e) {
    LOGRID_FUZZ_CHECK(std::string(e.what()).find(path) != std::string::npos,
                      "the error does not name the file: %s", e.what());
  } catch (const std::exception& e) {
    LOGRID_FUZZ_CHECK(false, "not a logrid::Error: %s", e.what());
  }
  return 0;
}
