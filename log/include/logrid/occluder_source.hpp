// An occluder pre-pass (method.hpp, OccluderUse; CullSources::occluders): occluders chosen
// for the frame's camera that are no objects of the scene, such as the directional
// discretized occluders of logrid::ddo (ddo/occluder_pass.hpp). The culler begins each
// frame with them:
//   * OccluderUse::Map (ddo): boxes are tested against the occluders' CPU map alone;
//     nothing is drawn and nothing read back;
//   * OccluderUse::Recorded (ddo+log): the source chooses occluder quads whose outlines
//     and key ranges the CPU knows (drawnQuads(), coverage.hpp), and the grid records the
//     cells each covers entirely as hidden behind its farthest key (OcclusionGrid::
//     recordCovered) without a read. Nothing need be drawn: the records, the depth buffer
//     and the order of the traversal stay as log-state's, and a test also counts a tile
//     as hidden where the cells under the box are hidden in front of the box's depth
//     threshold. A source that draws them as well appends what it drew to `drawn`, which
//     the culler announces like anything else drawn out of order.
// Conservative only if every occluder is valid for the viewpoint: wherever GL would store
// a depth of it, geometry of the scene at or in front of that depth covers the pixel (the
// DDO selector's guarantee, ddo/selector.hpp). Why a box culled behind a hidden cell is
// hidden in the picture: at each sample s of the cell, GL would draw the quad (coverage.
// hpp), so scene geometry G covers s at a key d_G <= the quad's far key < the box's
// threshold. G belongs to some node of the culled hierarchy, which is drawn unless it was
// itself culled: by what was drawn in front of it (then that hides s in front of d_G), or
// behind another hidden cell, whose geometry covers s at a key < d_G. The keys at s
// strictly decrease along that chain over finitely many objects, so it ends at geometry
// that is drawn, and it hides the box at s. (Until a depth clear: the grid forgets the
// hidden cells at every clear, OcclusionGrid::fill.)
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
  // `record`, also chooses the quads the culler records (drawnQuads()); a source that
  // draws them into the application's depth buffer (with a depth test that keeps the
  // nearer fragment) appends each one's pixels and farthest key to `drawn`. Returns how
  // many occluders it selected (with `record`: chose), or the error (logrid/error.hpp) if
  // it cannot serve the camera, or fails to draw.
  virtual Result<std::uint64_t> beginFrame(const Camera& camera,
                                           const ProjectionSettings& projection, bool record,
                                           std::vector<DrawnArea>& drawn) = 0;

  // After beginFrame(): does every pixel of `rect` (non-empty, inside the viewport) hold
  // an occluder whose depth key is below `threshold`? Decided on the CPU, without a read.
  virtual bool occludes(const PixelRect& rect, float threshold) const = 0;

  // After beginFrame() with `record`: the valid occluders as convex quads whose pixels the
  // CPU knows (their outlines and key ranges, as GL would draw them), for the culler to
  // record the cells they cover entirely (OcclusionGrid::recordCovered). One the source
  // drew must also lie inside an area appended to `drawn`. None by default.
  virtual const std::vector<DrawnQuad>& drawnQuads() const {
    static const std::vector<DrawnQuad> none;
    return none;
  }
};

}  // namespace logrid
