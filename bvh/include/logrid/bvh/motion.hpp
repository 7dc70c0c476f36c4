// Hierarchies for scenes whose objects move, behind one interface: each is a
// logrid::Hierarchy the culler walks unchanged, updated once per frame with the objects'
// new boxes before the frame is culled.
//
//   refit     FlatHierarchy built over the object boxes; each frame the leaves of the
//             objects that moved and their ancestors are refitted; rebuilt when its
//             quality has degraded: when the sum of the surface areas of all its nodes
//             (the SAH cost with unit costs, up to a constant) has grown by more than
//             MotionDesc::rebuild_growth since the last build.
//   rebuild   FlatHierarchy rebuilt from all object boxes every frame (the baseline).
//   ternary   the ternary tree of Kovalčík and Sochor (ternary_tree.hpp): straddling
//             objects in a third child, tight boxes for still nodes, split and merge of
//             leaves from per-node pixel statistics, view-dependent split planes.
//   ternary-objects  the ternary tree with each object of a node shown as a child with
//             its own box, so that the culler tests objects one by one (not in the
//             paper: there every test is a hardware query; a grid test is cheap).
//   binary    the same tree without those improvements: the axis-aligned BSP tree of
//             the paper's "old" algorithm, straddling objects kept in the inner node.
//
// Frame protocol (samples/cli/frame_runner.cpp does exactly this):
//   1. update(): every object's box now, the objects that may have moved, the camera's
//      view direction;
//   2. cull the frame with the culler's observer set to observer() (when not null);
//   3. measure(): per-node pixel statistics of that frame, for the next update().
// Node ids that are reassigned in update() change revision(), so the culler's temporal
// coherence forgets them. Boxes may change in every update without it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/camera.hpp"
#include "logrid/culler.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/error.hpp"
#include "logrid/hierarchy.hpp"

namespace logrid::bvh {

// What changed since the last update.
struct MotionUpdate {
  // Every object's box now, indexed by ObjectId (as many as the hierarchy was built
  // over). Must be finite with min <= max.
  const std::vector<Aabb>* boxes = nullptr;
  // Objects whose box may have changed since the last update (duplicates and unchanged
  // objects are allowed); any object not listed must keep its box.
  const std::vector<ObjectId>* moved = nullptr;
  // The camera's viewing direction (world space, need not be normalised; zero: unknown).
  // The ternary tree chooses its split planes from it (§3.4).
  DVec3 view_direction;
};

// What one update() did.
struct UpdateStats {
  double seconds = 0;             // wall time of update()
  std::uint32_t moved = 0;        // objects whose box had changed
  std::uint32_t relocated = 0;    // ternary/binary: objects that changed node
  std::uint32_t splits = 0;       // ternary: leaves split (§3.4)
  std::uint32_t merges = 0;       // ternary: sibling leaves merged into their parent
  std::uint32_t tight_boxes = 0;  // ternary: tight boxes computed (§3.2)
  std::uint32_t rebuilds = 0;     // refit: 1 when the quality criterion rebuilt it
  double quality = 1;             // refit: surface-area sum / its value after the build
};

// What one measure() asked the depth source.
struct MeasureStats {
  double seconds = 0;
  std::uint64_t counted = 0;   // nodes counted: the paper's "additional queries" (§3.3)
  std::uint64_t requests = 0;  // Count requests made for them (rows, for pixel readers)
  std::uint64_t pixels = 0;    // pixels the source read or scanned for them
  std::uint64_t queries = 0;   // hardware occlusion queries among them
  std::uint64_t nodes = 0;     // nodes whose statistics were updated (counted or not)
};

class MotionHierarchy : public Hierarchy {
 public:
  // The update, in both forms (logrid/error.hpp): tryUpdate() returns the error,
  // update() throws it as logrid::Error. Fails when boxes or moved is missing or an id
  // is out of range (ErrorCode::InvalidArgument) or a box is not finite with min <= max
  // (ErrorCode::BadInput), naming the object; the hierarchy is then unchanged for that
  // object.
  virtual Result<UpdateStats> tryUpdate(const MotionUpdate& update) = 0;
  UpdateStats update(const MotionUpdate& update);
  // An observer for the culler of the coming frame, recording the tested nodes' boxes
  // and answers; nullptr when the hierarchy uses no feedback.
  virtual CullObserver* observer() { return nullptr; }
  // After the culled frame, with the depth buffer as it was drawn: per-node pixel
  // statistics through `depth` (Count requests), used by the next update().
  virtual MeasureStats measure(const Camera& camera, DepthSource& depth) {
    (void)camera;
    (void)depth;
    return {};
  }
  // Objects the hierarchy holds.
  virtual std::size_t objectTotal() const = 0;
};

enum class MotionKind : std::uint8_t { Refit, Rebuild, Ternary, TernaryObjects, Binary };

struct MotionInfo {
  MotionKind kind;
  const char* name;         // as parsed and printed
  const char* description;  // one line
};

const std::vector<MotionInfo>& motionTable();
const MotionInfo& motionInfo(MotionKind kind);
std::optional<MotionKind> parseMotionKind(const std::string& name);
std::string motionNames();  // "refit, rebuild, ternary, ternary-objects, binary"

// The ternary tree's settings (ternary_tree.hpp explains each against the paper).
struct TernaryDesc {
  bool third_child = true;  // §3.1; false: straddling objects stay in the inner node
  bool tight_boxes = true;  // §3.2
  // §3.2 "objects which haven't moved for a few frames": a node's box is tightened once
  // nothing in its subtree has changed for this many updates.
  std::uint32_t still_frames = 3;
  bool split_merge = true;  // §3.3 statistics and §3.4 split/merge
  double r_split = 0.25;    // §3.4 constants
  std::uint32_t o_split = 12;
  double r_merge = 0.75;
  std::uint32_t o_merge = 5;
  bool view_dependent_split = true;  // §3.4 split plane from the view direction
  std::uint32_t max_depth = 24;      // no split below this depth
  // The initial tree: leaves with at least this many objects are split (longest axis,
  // in halves) down to max_depth. 0: o_split.
  std::uint32_t build_leaf = 0;
  // Not in the paper: show each object of a node as a child with its own box, so the
  // culler tests objects one by one (MotionKind::TernaryObjects, ternary_tree.hpp).
  bool object_nodes = false;
};

// The paper's "old" algorithm as this library reads it: `base` with straddling objects
// kept in the inner node, the nodes' own cells as boxes and no split or merge.
TernaryDesc binaryTreeDesc(const TernaryDesc& base = {});

struct MotionDesc {
  BuildArgs build;               // refit, rebuild
  double rebuild_growth = 0.25;  // refit: rebuild when the surface-area sum grew by more
  TernaryDesc ternary;           // ternary (binary uses binaryTreeDesc())
};

// Returns an empty string if the settings are usable, else a message naming the field.
std::string validateMotionDesc(const MotionDesc& desc);

// Builds a hierarchy of `kind` over `boxes` (object i has box boxes[i]). In both forms
// (logrid/error.hpp): fails with ErrorCode::InvalidArgument for settings
// validateMotionDesc() refuses and ErrorCode::BadInput for a bad box (naming it).
Result<std::unique_ptr<MotionHierarchy>> tryMakeMotionHierarchy(MotionKind kind,
                                                                const std::vector<Aabb>& boxes,
                                                                const MotionDesc& desc = {});
std::unique_ptr<MotionHierarchy> makeMotionHierarchy(MotionKind kind,
                                                     const std::vector<Aabb>& boxes,
                                                     const MotionDesc& desc = {});

#if LOGRID_HAS_EXCEPTIONS
inline UpdateStats MotionHierarchy::update(const MotionUpdate& update) {
  return logrid::orThrow(tryUpdate(update));
}
inline std::unique_ptr<MotionHierarchy> makeMotionHierarchy(MotionKind kind,
                                                            const std::vector<Aabb>& boxes,
                                                            const MotionDesc& desc) {
  return logrid::orThrow(tryMakeMotionHierarchy(kind, boxes, desc));
}
#endif

}  // namespace logrid::bvh
