#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "logrid/error.hpp"
#include "scene/generators.hpp"

namespace logrid::samples {

void checkScale(const char* scene, double scale, double max, const char* note) {
  if (scale > 0 && scale <= max) return;
  std::ostringstream out;
  out << scene << ": scale " << scale << " is out of range; use a value in (0, " << max << "]"
      << note;
  throw Error(ErrorCode::InvalidArgument, out.str());
}

Aabb emptyBox() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

void growBox(Aabb& b, const float* p) {
  b.min.x = std::min(b.min.x, p[0]), b.min.y = std::min(b.min.y, p[1]);
  b.min.z = std::min(b.min.z, p[2]), b.max.x = std::max(b.max.x, p[0]);
  b.max.y = std::max(b.max.y, p[1]), b.max.z = std::max(b.max.z, p[2]);
}

void growBox(Aabb& b, const Aabb& o) {
  growBox(b, &o.min.x);
  growBox(b, &o.max.x);
}

void computeBounds(Scene& scene) {
  scene.bounds = emptyBox();
  for (std::size_t v = 0; v + 2 < scene.positions.size(); v += 3) {
    growBox(scene.bounds, &scene.positions[v]);
  }
  for (SceneObject& o : scene.objects) {
    o.box = emptyBox();
    for (std::uint32_t i = o.first_index; i < o.first_index + o.index_count; ++i) {
      growBox(o.box, &scene.positions[std::size_t(scene.indices[i]) * 3]);
    }
  }
}

void validateScene(const Scene& scene) {
  auto fail = [&](const std::string& what) {
    throw Error(ErrorCode::BadInput, "scene '" + scene.name + "': " + what);
  };
  if (scene.positions.size() % 3 != 0) fail("positions are not xyz triples");
  if (scene.indices.empty() || scene.indices.size() % 3 != 0) {
    fail("has no triangles (or an index count that is not a multiple of 3)");
  }
  const std::size_t vertices = scene.positions.size() / 3;
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    if (!std::isfinite(scene.positions[i])) {
      std::ostringstream out;
      out << "vertex " << i / 3 << " has a non-finite coordinate (" << scene.positions[i] << ")";
      fail(out.str());
    }
  }
  for (std::size_t i = 0; i < scene.indices.size(); ++i) {
    if (scene.indices[i] >= vertices) {
      std::ostringstream out;
      out << "triangle " << i / 3 << " uses vertex " << scene.indices[i] << " but there are "
          << vertices << " vertices";
      fail(out.str());
    }
  }
  if (!scene.vertex_colors.empty() && scene.vertex_colors.size() != vertices) {
    fail("has " + std::to_string(scene.vertex_colors.size()) + " vertex colours for " +
         std::to_string(vertices) + " vertices");
  }
  auto checkObjects = [&](const std::vector<SceneObject>& objects, const char* what) {
    for (std::size_t o = 0; o < objects.size(); ++o) {
      const SceneObject& obj = objects[o];
      if (obj.index_count == 0 || obj.index_count % 3 != 0 ||
          std::uint64_t(obj.first_index) + obj.index_count > scene.indices.size()) {
        std::ostringstream out;
        out << what << " " << o << " covers indices [" << obj.first_index << ", "
            << std::uint64_t(obj.first_index) + obj.index_count << ") of " << scene.indices.size();
        fail(out.str());
      }
    }
  };
  checkObjects(scene.moving, "moving object");
  if (scene.moving.size() != scene.motion.movers.size()) {
    fail("has " + std::to_string(scene.moving.size()) + " moving objects but " +
         std::to_string(scene.motion.movers.size()) + " movers");
  }
  if (scene.triangle_solids.size() > scene.triangleCount()) {
    fail("has occluder solids for " + std::to_string(scene.triangle_solids.size()) +
         " triangles but " + std::to_string(scene.triangleCount()) + " triangles");
  }
  for (std::size_t t = 0; t < scene.triangle_solids.size(); ++t) {
    const std::uint32_t solid = scene.triangle_solids[t];
    if (solid != kNoSolid && solid >= scene.occluder_solids.size()) {
      fail("triangle " + std::to_string(t) + " names occluder solid " + std::to_string(solid) +
           " but there are " + std::to_string(scene.occluder_solids.size()));
    }
  }
  if (scene.split_by_triangles) return;
  if (!scene.triangle_solids.empty()) {
    fail("has occluder solids but is not split by triangles; give its objects models");
  }
  if (scene.objects.empty()) fail("has no objects");
  checkObjects(scene.objects, "object");
  if (!scene.occluder_models.empty() && scene.occluder_models.size() != scene.objects.size()) {
    fail("has " + std::to_string(scene.occluder_models.size()) + " occluder models for " +
         std::to_string(scene.objects.size()) + " objects");
  }
}

}  // namespace logrid::samples
