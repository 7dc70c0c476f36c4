// From a Scene to what a frame needs: the hierarchy logrid walks and the mesh the
// renderer draws, one draw per object. For scenes split by triangles (the city) the
// objects are the hierarchy's leaf chunks. Vertices are regrouped per object so every
// draw indexes at most 65536 vertices through 16-bit indices and a base vertex (6 bytes
// per triangle instead of 12), falling back to 32-bit indices for larger objects.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/camera.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "scene/clusters.hpp"
#include "scene/scene.hpp"

namespace logrid::cpu {
class OccluderMeshes;
}
namespace logrid::ddo {
class Octree;
}

namespace logrid::samples {

struct PreparedScene {
  std::string name;
  glm::dvec3 origin{0.0};
  Aabb bounds;  // local, of the static objects
  CameraPath path;
  double near_plane = 0.1;
  double far_plane = 1000.0;

  // The hierarchy of the static objects [0, static_objects); moving objects are not in
  // it (a walk with movers culls with a motion hierarchy over all objects, motion.hpp).
  bvh::FlatHierarchy hierarchy;
  gl::RenderMesh mesh;
  // Local, indexed by ObjectId; the movers' at time 0 (MotionFrame has them per frame).
  std::vector<Aabb> object_boxes;
  // Objects [static_objects, static_objects + motion.movingObjects()) move: moving
  // object k (mover k, or with clusters a cluster of mover motion.moverOf(k)) is object
  // static_objects + k, drawn with its mover's transform (mesh_renderer.hpp).
  std::uint32_t static_objects = 0;
  Motion motion;
  // Occluder models by ObjectId of the static objects (Scene::occluder_models; for split
  // scenes, the chunks' models from Scene::occluder_solids), empty when the scene has none.
  std::vector<OccluderModel> occluder_models;
  // With clusters (prepareScene's ClusterOptions) every ObjectId is a cluster:
  // cluster_objects[id] is the object it belongs to (the chunk, for split scenes; the
  // movers' objects follow the static ones) and cluster_cones[id] its normal cone (a
  // moving cluster's in its mesh's coordinates). Empty for whole objects.
  std::vector<std::uint32_t> cluster_objects;
  std::vector<ClusterCone> cluster_cones;
  // The CPU occlusion buffer's meshes, built on first use (scene/occluders.hpp).
  mutable std::shared_ptr<const cpu::OccluderMeshes> occluder_cache[3];
  // The DDO octree over the static mesh, when a method needs it (scene/ddo_scene.hpp).
  std::shared_ptr<const ddo::Octree> ddo;

  std::uint64_t triangles = 0;
  std::uint64_t source_objects = 0;  // objects before splitting (0 for split scenes)
  double cluster_ms = 0;             // splitting the objects into clusters
  double bvh_build_ms = 0;           // building the hierarchy
  double prepare_ms = 0;             // everything in prepareScene, the build included
  std::size_t memoryBytes() const;

  bool clustered() const { return !cluster_objects.empty(); }
  // The object an ObjectId draws part of (itself without clusters); the movers follow
  // the static objects. objectCount(): how many objects there are, movers included.
  std::uint32_t objectOf(ObjectId id) const;
  std::uint32_t objectCount() const;
};

// Whether GL, culling back faces (counter-clockwise front), draws nothing of draw `d` of
// `mesh`, its vertices placed by `t` (nullptr: as they are), seen by `camera`, whose
// window corners GL snaps to `snap_step` pixels (1 / 2^GL_SUBPIXEL_BITS).
bool drawsNothingWithBackFacesCulled(const gl::RenderMesh& mesh, const gl::RenderMesh::Draw& d,
                                     const RigidTransform* t, const Camera& camera,
                                     double snap_step);

// Whether a renderer that culls back faces (counter-clockwise front) draws nothing of
// cluster `id` of a clustered scene seen by `camera` from `eye`, the moving clusters
// where `motion` has them: its cone faces away (facesAway, clusters.hpp) and GL draws
// nothing of it (drawsNothingWithBackFacesCulled).
bool clusterFacesAway(const PreparedScene& scene, const MotionFrame& motion, ObjectId id,
                      const Camera& camera, const DVec3& eye, double snap_step);

// Consumes the scene (its arrays are released as soon as they are no longer needed).
// Moving objects are appended after the static ones; movers of one shape share one copy
// of its geometry.
// args.max_leaf_size: objects per leaf for object scenes, triangles per chunk for split
// scenes. `clusters`: whole objects (the default) or each object split into clusters
// (clusters.hpp; a mover's shape is clustered once). Throws logrid::Error(BadInput) through
// validateScene for broken geometry, InvalidArgument for invalid cluster options.
PreparedScene prepareScene(Scene&& scene, const bvh::BuildArgs& args,
                           const ClusterOptions& clusters = {});

// The default build arguments: one object per leaf (LOG §5 forest: "each tree is an
// object with an own bounding box"), or 1500 triangles per chunk for split scenes.
bvh::BuildArgs defaultBuildArgs(const Scene& scene);

}  // namespace logrid::samples
