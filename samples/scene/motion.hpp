// Motion in the sample scenes: objects that move rigidly along paths, evaluated at a
// time, so that every method and the oracle see the same motion on the same frames.
//
// Time. Frame f of a walkthrough has the time of its camera pose on the scene's camera
// path (CameraPath::frameTime: the path's own times, or for untimed paths the distance
// walked at one unit per second); movers are evaluated at that time.
//
// A mover follows a polyline path at a constant speed (negative: the other way round),
// around it for a loop and back and forth otherwise, and may stop and start again: it
// moves for move_seconds, stands for stop_seconds, and so on (stop_seconds 0: never
// stops). Its transform is a rotation about its mesh's local origin (a turn about +y
// that points the mesh's +x along its direction of travel, when `turn`), then a
// translation to its point on the path minus `anchor`, with the height taken from the
// ground when the path asks for it.
//
// Boxes. boxAt() is the box of the transformed mesh box (its eight corners in double),
// widened by the float rounding the renderer adds when it applies the rotation (16 ulps
// of the corners' size, mesh_renderer.hpp) and rounded outwards to float, so that it
// holds every vertex as the renderer draws it.
//
// JSON format for scenes from files (--animate FILE.json): meshes of the file move along
// paths, by translation (the mesh as modelled sits at the path's first point):
//   { "objects": [ { "mesh": 3, "path": [[x, y, z], ...], "speed": 2.0,
//                    "loop": false, "move_seconds": 10, "stop_seconds": 5,
//                    "offset": 0 }, ... ] }
// "mesh" is the object index in the loaded scene (meshes in file order); "path" has at
// least two points (scene coordinates, before the scene's origin is applied);
// "loop" (default false: back and forth), "move_seconds"/"stop_seconds" (default 0: no
// stops) and "offset" (metres along the path at time 0, default 0) are optional.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "logrid/types.hpp"

namespace logrid::samples {

struct MotionPath {
  std::vector<DVec3> points;       // local scene coordinates, at least two
  bool loop = false;               // closed: the last point joins the first
  bool follow_ground = false;      // y from Motion::ground at each point of travel
  std::vector<double> cumulative;  // arc length at each point (and back to the first)

  // Fills `cumulative`; throws logrid::Error(BadInput) for fewer than two points, a
  // non-finite point or a path of zero length.
  void finish(const std::string& what);
  double length() const { return cumulative.empty() ? 0.0 : cumulative.back(); }
};

// A rigid transform, in double: rotation (3x3, column-major) then translation.
struct RigidTransform {
  double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  DVec3 translation;
};

struct MoverSpec {
  std::uint32_t path = 0;   // into Motion::paths
  double speed = 1;         // units per second along the path; negative: backwards
  double offset = 0;        // arc length at time 0
  double move_seconds = 0;  // stop-and-go: moving this long,
  double stop_seconds = 0;  // then standing this long (0: never stops)
  double phase = 0;         // seconds into the stop-and-go cycle at time 0
  bool turn = true;         // rotate to face the direction of travel
  DVec3 anchor;             // subtracted from the path point (file meshes: the first point)
  Aabb mesh_box;            // the mesh's box in its own coordinates
  std::uint32_t triangles = 0;
};

// Part of a mover drawn as an object of its own: with clusters (prepare.hpp) each
// cluster of a mover's mesh is a moving object, culled on its own box, and moves with
// its mover.
struct MovingPart {
  std::uint32_t mover = 0;  // into Motion::movers
  Aabb mesh_box;            // the part's box in the mesh's own coordinates
};

struct Motion {
  std::vector<MotionPath> paths;
  std::vector<MoverSpec> movers;
  // The moving objects, in order: moving object k is parts[k], a part of mover
  // parts[k].mover (a mover's parts one after the other). Empty: moving object k is
  // mover k, whole.
  std::vector<MovingPart> parts;
  // Ground height at (x, z), for paths that follow it; empty: the path's own heights.
  std::function<double(double, double)> ground;

  bool empty() const { return movers.empty(); }
  std::size_t movingObjects() const { return parts.empty() ? movers.size() : parts.size(); }
  std::uint32_t moverOf(std::size_t moving_object) const;
  // Moving object k's box in its mesh's own coordinates (its part, or the whole mesh).
  const Aabb& meshBoxOf(std::size_t moving_object) const;
  // Arc length travelled by mover i at `time` (stops included).
  double travelled(std::size_t mover, double time) const;
  RigidTransform transformAt(std::size_t mover, double time) const;
  // The box of mover i's mesh at `time` (see above). Conservative for the renderer.
  Aabb boxAt(std::size_t mover, double time) const;
  // The box of moving object k (its part of its mover's mesh) at `time`, likewise.
  Aabb movingBoxAt(std::size_t moving_object, double time) const;
};

// The state of every object at one time: what a frame hands the renderer, the
// hierarchy and the oracle.
struct MotionFrame {
  double time = 0;
  std::vector<Aabb> boxes;                 // every object's box, indexed by ObjectId
  std::vector<RigidTransform> transforms;  // per moving object (its mover's)
  std::vector<ObjectId> moved;             // objects whose box changed in the last evaluate()
};

// Sets `frame` to the state at `time`: the moving objects' boxes (objects first_mover + k)
// and transforms, and `moved` to those whose box differs from what `frame` held.
// `frame.boxes` must already hold every object (static ones are left alone).
void evaluateMotion(const Motion& motion, ObjectId first_mover, double time, MotionFrame& frame);

// Reads the JSON format above for a scene of `object_count` objects; throws
// logrid::Error naming the file and the problem (Environment: unreadable; BadInput:
// syntax, fields, a mesh index out of range or listed twice, a bad path).
struct MeshAnimation {
  std::uint32_t mesh = 0;
  MotionPath path;
  MoverSpec spec;  // path index left 0; anchor set to the path's first point
};
std::vector<MeshAnimation> loadMeshAnimations(const std::string& file, std::size_t object_count);

}  // namespace logrid::samples
