// The scenes of the samples: geometry as far as culling and a readable picture need it
// (positions, indices, a flat colour per object), a camera path, and where the scene
// sits in the world.
//
// Coordinates are stored *local* to Scene::origin (double precision), so a scene
// placed a million units from the world origin keeps float positions near zero; the
// cameras compose the translation in double (see samples/scene/view.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/ext/vector_double3.hpp>

#include "logrid/types.hpp"
#include "scene/camera_path.hpp"
#include "scene/motion.hpp"

namespace logrid::samples {

struct SceneObject {
  std::uint32_t first_index = 0;      // into Scene::indices
  std::uint32_t index_count = 0;      // a multiple of 3
  std::uint32_t color = 0xFFFFFFFFu;  // RGBA8: r | g << 8 | b << 16 | a << 24
  Aabb box;                           // local coordinates, contains every vertex used
};

// Where generated movers may go (movers.hpp). The generators set it; a scene from a
// file gets the floor of its bounds.
enum class MoverKind : std::uint8_t { Animals, Vehicles };
struct MoverSite {
  MoverKind kind = MoverKind::Animals;
  std::function<double(double, double)> ground;  // height at (x, z); empty: the floor
  std::vector<double> streets_x;                 // vehicles: streets along z, at these x
  std::vector<double> streets_z;                 // ... and along x, at these z
  double size = 0;                               // metres per mesh unit; 0: from the bounds
};

// A simpler occluder for one object, for the CPU occlusion buffer (logrid/cpu/
// occluder_mesh.hpp, OccluderObject::inside_solid): triangles of the object as they are,
// and triangles that lie inside closed solids bounded by the object's own triangles
// (e.g. the convex hull of some of a convex crown's vertices) or, for a scene split by
// triangles, by the triangles of several objects (OccluderSolid). Positions are
// bit-identical copies of the object's where they are its vertices.
struct OccluderModel {
  std::vector<float> positions;  // xyz, local coordinates
  std::vector<std::uint32_t> indices;
  // Closed boxes inside solids of several objects (OccluderSolid::inside), which may
  // reach beyond this object's box, and `reach`, the box of the real geometry they stand
  // for (the union of the solids' `around`; empty, min > max, without boxes). The buffer
  // is given the union of reach and the object's box: it uses the model only while that
  // lies wholly beyond the near plane, and bounds GL's vertex snapping by it. Methods
  // with occlusion-state semantics (anything drawn hides what is tested next, sound
  // because it lies in front by the two-list order) get the boxes clipped to the
  // object's box (scene/occluders.hpp).
  std::vector<Aabb> boxes;
  Aabb reach{{1, 1, 1}, {0, 0, 0}};
};

// A closed solid of a scene split by triangles (the city's buildings), for occluder
// models: `inside`, a box inside the solid that the triangles tagged with it
// (Scene::triangle_solids) bound, and `around`, the box of those triangles. The chunks
// of such a scene are cut by the hierarchy, not by solid: every chunk holding a tagged
// triangle gets the box as (part of) its model (prepare.cpp), although its own
// triangles need not enclose it. Why the box hides only what GL's picture hides: the
// model is used only while `around` lies wholly beyond the near plane (reach above),
// so the eye is outside the solid and GL clips none of it. Where the buffer claims the
// box at a pixel with key k, the ray meets the solid's surface nearer than the box (the
// generator derives by how much, with GL's snapping), at a triangle of some chunk D.
// Frustum culling cannot remove D (the point lies between the eye and the box, beyond
// the near plane). If D is drawn, GL holds that nearer depth at the pixel; if D is
// culled, its test found every pixel of its rectangle, this one included, holding a key
// nearer than D's box, hence nearer than k. Keys only get nearer during a frame, so at
// a pixel's final key the first case holds: whatever is culled behind a key at a pixel
// lies behind a surface GL draws there. Methods with occlusion-state semantics compare
// no depths (a pixel holding anything hides a box the two-list order tests after the
// drawing object, whose box lies in front of it): for them each box is clipped to its
// chunk's box, so a claim lies in front of the tested box, the surface GL draws there
// nearer still, and the same descent (a culled D had its pixel claimed by something in
// front of D's box) holds. Unclipped boxes claim pixels behind the tested box: log-state
// then missed visible objects (tests/oracle/walk_oracle_test.cpp, CpuBufferCityModels).
struct OccluderSolid {
  Aabb inside;
  Aabb around;
};
inline constexpr std::uint32_t kNoSolid = 0xFFFFFFFFu;

struct Scene {
  std::string name;
  glm::dvec3 origin{0.0};              // world position of the local origin
  std::vector<float> positions;        // xyz per vertex, local coordinates
  std::vector<std::uint32_t> indices;  // three per triangle
  // Optional RGBA8 colour per vertex; when present it replaces the objects' colours.
  std::vector<std::uint32_t> vertex_colors;
  // One entry per object (a tree, a terrain patch, a mesh of a file). For scenes whose
  // hierarchy is built over triangles (the city, LOG §5: "each triangle is a primitive
  // object"), leave it empty and set split_by_triangles: the objects are then the
  // hierarchy's leaf chunks of at most BuildArgs::max_leaf_size triangles.
  std::vector<SceneObject> objects;
  bool split_by_triangles = false;
  // Objects that move (movers.hpp, motion.hpp): drawn with a transform, not part of the
  // static hierarchy. Their index ranges may be shared (movers of one shape), and their
  // box is the mesh's box in its own coordinates. Scene::motion has one mover for each.
  std::vector<SceneObject> moving;
  Motion motion;
  MoverSite mover_site;
  // Optional occluder models, one per object (an empty model: none); object scenes only.
  std::vector<OccluderModel> occluder_models;
  // Optional occluder solids of a split scene, and the solid of each triangle of the
  // static geometry (kNoSolid: the triangle is its own occluder); movers have none.
  std::vector<OccluderSolid> occluder_solids;
  std::vector<std::uint32_t> triangle_solids;
  Aabb bounds;      // local, of all positions
  CameraPath path;  // the default walkthrough
  // Suggested clip planes for the walkthrough (world units).
  double near_plane = 0.1;
  double far_plane = 1000.0;

  std::size_t triangleCount() const { return indices.size() / 3; }
};

// The union of a box and a point / box.
void growBox(Aabb& box, const float* p);
void growBox(Aabb& box, const Aabb& other);
Aabb emptyBox();

// Recomputes `bounds` and every object's box from the geometry.
void computeBounds(Scene& scene);

// Checks the scene's invariants (indices in range, finite positions, objects inside the
// index array, non-empty) and throws logrid::Error(BadInput) naming the first problem.
void validateScene(const Scene& scene);

}  // namespace logrid::samples
