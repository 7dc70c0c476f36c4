#include "scene/obj_writer.hpp"

#include <cstdio>
#include <fstream>
#include <unordered_map>

#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) {
    throw Error(ErrorCode::Environment,
                "cannot write '" + path + "': check that its folder exists and is writable");
  }
  return out;
}

}  // namespace

void writeObj(const Scene& scene, const std::string& path) {
  if (scene.split_by_triangles || scene.objects.empty()) {
    throw Error(ErrorCode::InvalidArgument,
                "scene '" + scene.name +
                    "' has no objects of its own (its objects are the hierarchy's chunks); "
                    "export an object scene such as forest or office");
  }
  std::ofstream out = openForWriting(path);
  out << "# " << scene.name << ", written by logrid export\n";
  char line[128];
  std::size_t written = 0;  // vertices written so far (OBJ indices are global, 1-based)
  std::unordered_map<std::uint32_t, std::size_t> local;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& object = scene.objects[o];
    out << "o object_" << o << "\n";
    local.clear();
    for (std::uint32_t i = object.first_index; i < object.first_index + object.index_count; ++i) {
      const std::uint32_t v = scene.indices[i];
      if (local.emplace(v, written + 1).second) {
        const float* p = &scene.positions[std::size_t(v) * 3];
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(p[0]), double(p[1]),
                      double(p[2]));
        out << line;
        ++written;
      }
    }
    for (std::uint32_t i = object.first_index; i + 2 < object.first_index + object.index_count;
         i += 3) {
      out << "f " << local[scene.indices[i]] << " " << local[scene.indices[i + 1]] << " "
          << local[scene.indices[i + 2]] << "\n";
    }
  }
  if (!out.flush()) throw Error(ErrorCode::Environment, "writing '" + path + "' failed");
}

void writeCameraPathJson(const CameraPath& path, const std::string& file) {
  std::ofstream out = openForWriting(file);
  char line[256];
  out << "{\"keys\": [\n";
  for (std::size_t i = 0; i < path.keys().size(); ++i) {
    const CameraKey& k = path.keys()[i];
    std::snprintf(line, sizeof line,
                  "  {\"position\": [%.17g, %.17g, %.17g], \"look_at\": [%.17g, %.17g, %.17g]}%s\n",
                  k.position.x, k.position.y, k.position.z, k.look_at.x, k.look_at.y, k.look_at.z,
                  i + 1 < path.keys().size() ? "," : "");
    out << line;
  }
  out << "]}\n";
  if (!out.flush()) throw Error(ErrorCode::Environment, "writing '" + file + "' failed");
}

}  // namespace logrid::samples
