// The occlusion tests the methods share (log/src/methods/ picks one per method through
// MethodDef::make_tester). Internal to logrid::core.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/culler.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/grid.hpp"

namespace logrid::detail {

class BoxTester {
 public:
  virtual ~BoxTester() = default;

  // A new frame whose depth buffer is cleared to `clear_key`, with the frame's sources
  // (those the method needs are there: MethodInfo::needs); an error if the tester cannot
  // work with them (the culler's frame then does not begin).
  virtual Status beginFrame(const Camera& camera, float clear_key, const CullSources& sources) = 0;
  // The approximate knobs of the next frames (CullerDesc::budget_ms); before beginFrame.
  // Only the grid's testers take them.
  virtual void setApproximation(const GridApproximation& approximation) { (void)approximation; }
  // Is any pixel of `rect` at or beyond `threshold`? Tested on its own. `hidden` is the
  // box's depth threshold (BoxProjection::occlusionThreshold()), for the keys known
  // hidden without a read (recordCovered()); testers that record none ignore it.
  virtual Visibility test(const PixelRect& rect, float threshold, float hidden,
                          GridTestCounts& counts) = 0;
  // Would test() read pixels that `undrawn` (the rectangles of what is to be drawn but is
  // not drawn yet) may cover? Then that must be drawn first; else the test may read now,
  // and reads what it would read after. Counts nothing.
  virtual bool readsUnder(const PixelRect& rect, float threshold, float hidden,
                          const std::vector<PixelRect>& undrawn) {
    (void)rect;
    (void)threshold;
    (void)hidden;
    (void)undrawn;
    return false;
  }

  // test() over what it reads away from `undrawn`: Visible where that shows the box,
  // else nothing (the rest must wait for `undrawn` to be drawn).
  virtual std::optional<Visibility> testAwayFrom(const PixelRect& rect, float threshold,
                                                 float hidden, GridTestCounts& counts,
                                                 const std::vector<PixelRect>& undrawn) {
    (void)rect;
    (void)threshold;
    (void)hidden;
    (void)counts;
    (void)undrawn;
    return std::nullopt;
  }

  // Batched tests, for methods that take a lookahead: plan() answers at once what needs
  // no read, else (if `read`) adds the test to the batch; submitBatch(), the source's
  // collect(), applyBatch(), then resolve() for each planned test in order, and
  // clearBatch().
  virtual std::optional<Visibility> plan(const PixelRect& rect, float threshold, float hidden,
                                         GridTestCounts& counts, bool read);
  // Would the planned batch's reads cover pixels that `undrawn` may cover?
  virtual bool batchReadsUnder(const std::vector<PixelRect>& undrawn) {
    (void)undrawn;
    return true;
  }
  virtual void submitBatch() {}
  virtual void applyBatch() {}
  virtual Visibility resolve(std::size_t index);
  virtual void clearBatch() {}

  // Something is drawn over `rect` (clipped to the viewport): bookkeeping at once.
  virtual void noteDrawn(const PixelRect& rect) = 0;
  // A convex quad whose coverage the CPU knows (coverage.hpp), drawn or hidden by what
  // the frame draws (OcclusionGrid::recordCovered()): tiles it covers entirely may be
  // recorded hidden behind its far key without a read. Returns the tiles recorded.
  virtual std::uint64_t recordCovered(const DrawnQuad& quad, const CoverageRule& rule) {
    (void)quad;
    (void)rule;
    return 0;
  }
  // Testers that read what was drawn right after the draw (busy grid, pyramid): the
  // culler calls afterDraw() once it is drawn, before any test.
  virtual bool readsAfterDraw() const { return false; }
  virtual void afterDraw(const PixelRect& rect) { (void)rect; }
  // The depth buffer was cleared mid-frame to `key`.
  virtual void noteCleared(float key) = 0;
  // Brings every outdated record up to date in one batch (temporal coherence).
  virtual void refreshOutdated(GridTestCounts& counts) { (void)counts; }
  // The grid as a pre-filter of hardware queries (log+hwq): what the records decide
  // without reading, and a refresh of the outdated records under some rectangles.
  virtual std::optional<Visibility> decide(const PixelRect& rect, float threshold,
                                           GridTestCounts& counts) {
    (void)rect;
    (void)threshold;
    (void)counts;
    return std::nullopt;
  }
  virtual void refreshUnder(const std::vector<PixelRect>& rects, GridTestCounts& counts) {
    (void)rects;
    (void)counts;
  }
  virtual const OcclusionGrid* grid() const { return nullptr; }
};

// When a grid's tiles are brought up to date.
enum class GridRefresh : std::uint8_t {
  Lazy,  // marked outdated by a draw, read when a test needs them (LOG §3)
  Busy,  // read right after each draw (LOG §5)
};

// The lazy occlusion grid (grid.hpp) of `variant`, with desc's tile size and knobs.
std::unique_ptr<BoxTester> makeGridTester(const CullerDesc& desc, GridVariant variant,
                                          GridRefresh refresh);
// A CPU depth pyramid updated from the drawn box's area after each draw (depth_pyramid.hpp).
std::unique_ptr<BoxTester> makePyramidTester();
// One pixel-level count over the box's whole rectangle; `visible_pixels` may show.
std::unique_ptr<BoxTester> makeRectCountTester(std::uint32_t visible_pixels);
// The occluder pre-pass's CPU map (OccluderSource::occludes); reads nothing.
std::unique_ptr<BoxTester> makeOccluderMapTester();
// No occlusion test: view-frustum culling, and the query schedules, whose queries test.
std::unique_ptr<BoxTester> makeNoTester();

}  // namespace logrid::detail
