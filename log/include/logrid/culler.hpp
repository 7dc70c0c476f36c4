// The culler: walks a Hierarchy front to back for one camera, tests each box against
// the lazy occlusion grid (or a comparison method), and hands the objects of every
// potentially visible node to the application's draw callback.
//
// Typical use, once per frame:
//
//   glClear(GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT);      // the frame starts cleared
//   logrid::FrameStats stats = culler.cullFrame(camera, hierarchy, depth_source,
//       [&](logrid::ObjectId id) { drawObject(id); });        // draws with the depth test
//
// Contract for the frame: the depth buffer is cleared before cullFrame() and everything
// drawn during it is drawn through the callback, with a depth test that keeps the nearer
// fragment (GL_LESS/LEQUAL standard, GL_GREATER/GEQUAL reversed) and depth writes on.
// Anything drawn without the callback must be announced with noteDrawn().
//
// Traversals (LOG §3, §4):
//   * two-list (occlusion state, and every method that shares its order): a test-list
//     ordered by nearest key and a draw-list ordered by farthest key; a visible node's
//     objects are drawn only once they lie in front of every box still to be tested.
//   * approximate front to back (zfar, vfc): the test-list only; visible objects are
//     drawn at once. Correct for zfar, which compares depths.
// View-frustum culling is hierarchical: an outside node's children are never visited.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/depth_pyramid.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/grid.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/projection.hpp"
#include "logrid/stats.hpp"

namespace logrid {

// The culling methods compared in DESIGN.md (the oracle lives in integration/).
enum class Method : std::uint8_t {
  LogState,  // lazy occlusion grid, occlusion-state variant, two-list traversal
  LogZfar,   // lazy occlusion grid, zfar variant, approximate traversal
  Bog,       // busy occlusion grid: tiles refreshed right after each draw (LOG §5)
  Hzb,       // hierarchical z-buffer refreshed from the drawn box's area after each draw
  Pq,        // one pixel-level query over each tested box's whole rectangle
  Vfc,       // view-frustum culling only
};

const char* toString(Method method);
// Parses "log-state", "log-zfar", "bog", "hzb", "pq" or "vfc".
std::optional<Method> parseMethod(const std::string& name);

struct CullerDesc {
  Method method = Method::LogState;
  std::uint32_t tile_size = 32;  // pixels per tile side (LOG §5 uses 32)
  ProjectionSettings projection;

  // Speed for accuracy (grid.hpp, GridApproximation). Off by default. What each knob
  // gives up, measured on the forest and the city, is in docs/TRADEOFF.md:
  //   visible_pixels      boxes showing at most N pixels are culled: objects whose
  //                       visible part is that small vanish (log-*, bog, pq; with the
  //                       query reader the count comes from GL_SAMPLES_PASSED);
  //   full_free_fraction  tiles with at most this fraction of free pixels count as full:
  //                       objects seen only through such gaps vanish (log-state, bog);
  //   row_stride          reads sample every k-th row: objects seen only through rows
  //                       that were skipped vanish (log-*, bog).
  // Knobs combine: with visible_pixels and full_free_fraction together, tiles counted
  // as full contribute no pixels to the visible-pixel count. HZB and VFC take none.
  GridApproximation approximation;
};

// Returns an empty string if the descriptor is usable, else a message naming the field.
std::string validateCullerDesc(const CullerDesc& desc);

using DrawCallback = std::function<void(ObjectId)>;

// Optional hooks for overlays and debugging; called synchronously during cullFrame().
class CullObserver {
 public:
  virtual ~CullObserver() = default;
  virtual void onTested(NodeId, const BoxProjection&, Visibility) {}
  virtual void onDrawn(NodeId, const BoxProjection&) {}
};

class Culler {
 public:
  // Throws logrid::Error if validateCullerDesc() finds a problem.
  explicit Culler(const CullerDesc& desc = {});
  ~Culler();
  Culler(Culler&&) noexcept;
  Culler& operator=(Culler&&) noexcept;

  const CullerDesc& desc() const { return desc_; }

  // Culls and draws one frame. Throws logrid::Error for an invalid camera (validateCamera)
  // or a depth source that cannot serve it; boxes with NaN or inverted bounds are drawn
  // and counted in FrameStats::invalid_boxes.
  FrameStats cullFrame(const Camera& camera, const Hierarchy& hierarchy, DepthSource& depth,
                       const DrawCallback& draw);

  // For use inside the draw callback: the application drew something over `rect`
  // outside the callback's own object.
  void noteDrawn(const PixelRect& rect);

  // The grid of the last frame (nullptr for methods without one), for overlays.
  const OcclusionGrid* grid() const { return grid_ ? &*grid_ : nullptr; }
  void setObserver(CullObserver* observer) { observer_ = observer; }

 private:
  struct Entry {
    float order;  // test-list: nearest key - margin; draw-list: farthest key + margin
    NodeId node;
    BoxProjection projection;
  };
  bool usesTwoLists() const;
  void prepare(const Camera& camera);
  void pushTest(const Hierarchy& hierarchy, NodeId node);
  Visibility testEntry(const Entry& entry, DepthSource& depth);
  void drawEntry(const Entry& entry, const Hierarchy& hierarchy, DepthSource& depth,
                 const DrawCallback& draw);
  void noteDrawnWith(const PixelRect& rect, DepthSource& depth);

  CullerDesc desc_;
  std::optional<Projector> projector_;
  std::optional<OcclusionGrid> grid_;
  std::unique_ptr<DepthPyramid> pyramid_;
  std::uint32_t last_width_ = 0;
  std::uint32_t last_height_ = 0;
  CullObserver* observer_ = nullptr;
  DepthSource* current_source_ = nullptr;  // set during cullFrame()
  FrameStats stats_;
  GridTestCounts grid_counts_;
  float drawn_back_ = 0;  // farthest key + margin of anything drawn so far this frame
  std::vector<Entry> test_list_;
  std::vector<Entry> draw_list_;
};

}  // namespace logrid
