// Each method's occlusion test, one class per method (the culler's only switch on the
// method is makeTester()). Internal to logrid::core.
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

  // A new frame whose depth buffer is cleared to `clear_key`.
  virtual void beginFrame(const Camera& camera, float clear_key) = 0;
  // Is any pixel of `rect` at or beyond `threshold`? Tested on its own.
  virtual Visibility test(const PixelRect& rect, float threshold, DepthSource& source,
                          GridTestCounts& counts) = 0;

  // Batched tests, for methods with MethodInfo::lookahead: plan() answers at once what
  // needs no read, else (if `read`) adds the test to the batch; submitBatch(), the
  // source's collect(), applyBatch(), then resolve() for each planned test in order, and
  // clearBatch().
  virtual std::optional<Visibility> plan(const PixelRect& rect, float threshold,
                                         const DepthSourceTraits& source, GridTestCounts& counts,
                                         bool read);
  virtual void submitBatch(DepthSource& source);
  virtual void applyBatch() {}
  virtual Visibility resolve(std::size_t index, GridTestCounts& counts);
  virtual void clearBatch() {}

  // Something was drawn over `rect` (clipped to the viewport).
  virtual void noteDrawn(const PixelRect& rect, DepthSource& source) = 0;
  // The depth buffer was cleared mid-frame to `key`.
  virtual void noteCleared(float key) = 0;
  // Brings every outdated record up to date in one batch (temporal coherence).
  virtual void refreshOutdated(DepthSource& source, GridTestCounts& counts) {
    (void)source;
    (void)counts;
  }
  // The grid as a pre-filter of hardware queries (log+hwq): what the records decide
  // without reading, and a refresh of the outdated records under some rectangles.
  virtual std::optional<Visibility> decide(const PixelRect& rect, float threshold,
                                           GridTestCounts& counts) {
    (void)rect;
    (void)threshold;
    (void)counts;
    return std::nullopt;
  }
  virtual void refreshUnder(const std::vector<PixelRect>& rects, DepthSource& source,
                            GridTestCounts& counts) {
    (void)rects;
    (void)source;
    (void)counts;
  }
  virtual const OcclusionGrid* grid() const { return nullptr; }
};

std::unique_ptr<BoxTester> makeTester(const CullerDesc& desc);

}  // namespace logrid::detail
