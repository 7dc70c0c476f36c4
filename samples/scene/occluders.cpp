#include "scene/occluders.hpp"

#include <algorithm>
#include <limits>

namespace logrid::samples {

const char* toString(OccluderChoice choice) {
  return choice == OccluderChoice::Model ? "model" : "mesh";
}

std::optional<OccluderChoice> parseOccluderChoice(const std::string& name) {
  for (OccluderChoice c : {OccluderChoice::Mesh, OccluderChoice::Model}) {
    if (name == toString(c)) return c;
  }
  return std::nullopt;
}

namespace {

// The triangles of one draw, with its vertices renumbered from 0.
void addDrawnMesh(const PreparedScene& scene, ObjectId id, cpu::OccluderMeshes& out) {
  const gl::RenderMesh& mesh = scene.mesh;
  const gl::RenderMesh::Draw& d = mesh.draws[id];
  std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0;
  std::vector<std::uint32_t> indices(d.index_count);
  for (std::uint32_t i = 0; i < d.index_count; ++i) {
    const std::uint32_t k = d.first_index + i;
    indices[i] = mesh.indices16.empty() ? mesh.indices32[k] : mesh.indices16[k];
    lo = std::min(lo, indices[i]);
    hi = std::max(hi, indices[i]);
  }
  if (indices.empty()) lo = hi = 0;
  for (std::uint32_t& i : indices) i -= lo;
  const float* positions = &mesh.positions[(std::size_t(d.base_vertex) + lo) * 3];
  out.addObject(positions, indices.empty() ? 0 : hi - lo + 1, indices.data(), indices.size(),
                &scene.object_boxes[id]);
}

std::shared_ptr<const cpu::OccluderMeshes> build(const PreparedScene& scene,
                                                 OccluderChoice choice) {
  auto out = std::make_shared<cpu::OccluderMeshes>();
  const std::size_t objects = scene.mesh.draws.size();
  const bool models = choice == OccluderChoice::Model && !scene.occluder_models.empty();
  std::vector<ObjectId> modelled;
  for (ObjectId id = 0; id < objects; ++id) {
    // Movers (after the static objects) have no models.
    const OccluderModel* m =
        models && id < scene.occluder_models.size() ? &scene.occluder_models[id] : nullptr;
    if (m && !m->indices.empty()) {
      Aabb box = scene.object_boxes[id];
      if (m->reach.min.x <= m->reach.max.x) growBox(box, m->reach);
      out->addObject(m->positions.data(), m->positions.size() / 3, m->indices.data(),
                     m->indices.size(), &box);
      modelled.push_back(id);
    } else {
      addDrawnMesh(scene, id, *out);
    }
  }
  for (ObjectId id : modelled) {
    const std::uint32_t fallback = std::uint32_t(out->objectCount());
    addDrawnMesh(scene, id, *out);
    out->setInsideSolid(id, fallback);
  }
  return out;
}

}  // namespace

const cpu::OccluderMeshes& sceneOccluders(const PreparedScene& scene, OccluderChoice choice) {
  std::shared_ptr<const cpu::OccluderMeshes>& slot = scene.occluder_cache[int(choice)];
  if (!slot) slot = build(scene, choice);
  return *slot;
}

}  // namespace logrid::samples
