// An occluder pre-pass (method.hpp, OccluderUse; CullSources::occluders): occluders chosen
// for the frame's camera that are no objects of the scene, such as the directional
// discretized occluders of logrid::ddo (ddo/occluder_pass.hpp). The culler begins each
// frame with them:
//   * OccluderUse::Map (ddo): boxes are tested against the occluders' CPU map alone;
//     nothing is drawn and nothing read back;
//   * OccluderUse::Drawn (ddo+log): the occluders are drawn into the application's depth
//     buffer first (depth only), announced to the grid like anything else drawn out of
//     order, and the grid reads them with the scene. The tiles an occluder quad covers
//     entirely (drawnQuads(), coverage.hpp) are recorded full with its farthest key
//     without a read; the tiles it covers partly are outdated like after any draw.
// Conservative only if every occluder is valid for the viewpoint: wherever it stores a
// depth, geometry of the scene at or in front of that depth covers the pixel (the DDO
// selector's guarantee, ddo/selector.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/coverage.hpp"
#include "logrid/error.hpp"
#include "logrid/projection.hpp"
#include "logrid/types.hpp"

namespace logrid {

class OccluderSource {
 public:
  virtual ~OccluderSource() = default;

  // Selects this frame's occluders for `camera` (forgetting the last frame's). With
  // `draw`, also draws them into the application's depth buffer, with a depth test that
  // keeps the nearer fragment, and appends each one's pixels and farthest key to `drawn`.
  // Returns how many occluders it selected, or the error (logrid/error.hpp) if it cannot
  // serve the camera, or cannot draw when asked to.
  virtual Result<std::uint64_t> beginFrame(const Camera& camera,
                                           const ProjectionSettings& projection, bool draw,
                                           std::vector<DrawnArea>& drawn) = 0;

  // After beginFrame(): does every pixel of `rect` (non-empty, inside the viewport) hold
  // an occluder whose depth key is below `threshold`? Decided on the CPU, without a read.
  virtual bool occludes(const PixelRect& rect, float threshold) const = 0;

  // After beginFrame() with `draw`: the convex quads among what it drew whose pixels the
  // CPU knows (their outlines and key ranges), for the culler to record the tiles they
  // cover entirely (OcclusionGrid::recordCovered). Each must also lie inside an area
  // appended to `drawn`. None by default.
  virtual const std::vector<DrawnQuad>& drawnQuads() const {
    static const std::vector<DrawnQuad> none;
    return none;
  }
};

}  // namespace logrid
