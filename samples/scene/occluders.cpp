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

// The triangles of one draw, with its vertices renumbered from 0. `box`: every vertex's
// (nullptr: their bounds).
void addDrawnMesh(const PreparedScene& scene, ObjectId id, const Aabb* box,
                  cpu::OccluderMeshes& out) {
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
  out.addObject(positions, indices.empty() ? 0 : hi - lo + 1, indices.data(), indices.size(), box);
}

// A closed box, its 12 triangles counter-clockwise seen from outside.
void appendBox(const Aabb& b, std::vector<float>& positions, std::vector<std::uint32_t>& indices) {
  const std::uint32_t base = std::uint32_t(positions.size() / 3);
  for (int i = 0; i < 8; ++i) {  // corner i: x from bit 0, y from bit 1, z from bit 2
    positions.insert(positions.end(), {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                                       (i & 4) ? b.max.z : b.min.z});
  }
  constexpr std::uint32_t kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5},   // -x, +x
                                          {0, 1, 5, 4}, {2, 6, 7, 3},   // -y, +y
                                          {0, 2, 3, 1}, {4, 5, 7, 6}};  // -z, +z
  for (const auto& f : kFaces) {
    indices.insert(indices.end(),
                   {base + f[0], base + f[1], base + f[2], base + f[0], base + f[2], base + f[3]});
  }
}

// Adds object `id` as its model; false (nothing added) when no box is left of it.
bool addModel(const PreparedScene& scene, ObjectId id, const OccluderModel& m, bool within,
              cpu::OccluderMeshes& out) {
  const Aabb& own = scene.object_boxes[id];
  std::vector<float> positions = m.positions;
  std::vector<std::uint32_t> indices = m.indices;
  for (Aabb b : m.boxes) {
    if (within) {  // the part inside the object's box (still inside the solid)
      b.min = {std::max(b.min.x, own.min.x), std::max(b.min.y, own.min.y),
               std::max(b.min.z, own.min.z)};
      b.max = {std::min(b.max.x, own.max.x), std::min(b.max.y, own.max.y),
               std::min(b.max.z, own.max.z)};
      if (!(b.min.x < b.max.x && b.min.y < b.max.y && b.min.z < b.max.z)) continue;
    }
    appendBox(b, positions, indices);
  }
  if (indices.size() == m.indices.size() && !m.boxes.empty()) return false;
  if (indices.empty()) return false;
  Aabb box = own;
  if (m.reach.min.x <= m.reach.max.x) growBox(box, m.reach);
  out.addObject(positions.data(), positions.size() / 3, indices.data(), indices.size(), &box);
  return true;
}

std::shared_ptr<const cpu::OccluderMeshes> build(const PreparedScene& scene, int slot) {
  auto out = std::make_shared<cpu::OccluderMeshes>();
  const std::size_t objects = scene.mesh.draws.size();
  const bool models = slot != 0 && !scene.occluder_models.empty();
  std::vector<ObjectId> modelled;
  for (ObjectId id = 0; id < objects; ++id) {
    if (id >= scene.static_objects) {
      // A moving object (each its own draw): its triangles in its own coordinates, with
      // their own bounds (its box in the scene changes); the buffer places them where
      // the frame draws them (OcclusionBuffer::drawObject with its transform).
      addDrawnMesh(scene, id, nullptr, *out);
      continue;
    }
    if (models && id < scene.occluder_models.size() &&
        addModel(scene, id, scene.occluder_models[id], slot == 2, *out)) {
      modelled.push_back(id);
    } else {
      addDrawnMesh(scene, id, &scene.object_boxes[id], *out);
    }
  }
  for (ObjectId id : modelled) {
    const std::uint32_t fallback = std::uint32_t(out->objectCount());
    addDrawnMesh(scene, id, &scene.object_boxes[id], *out);
    out->setInsideSolid(id, fallback);
  }
  return out;
}

}  // namespace

const cpu::OccluderMeshes& sceneOccluders(const PreparedScene& scene, OccluderChoice choice,
                                          bool within_objects) {
  const int slot = choice == OccluderChoice::Mesh ? 0 : within_objects ? 2 : 1;
  std::shared_ptr<const cpu::OccluderMeshes>& cached = scene.occluder_cache[slot];
  if (!cached) cached = build(scene, slot);
  return *cached;
}

}  // namespace logrid::samples
