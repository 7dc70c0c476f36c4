// The directional discretized occluders as the culler's occluder pre-pass
// (logrid/occluder_source.hpp), for the methods ddo and ddo+log (method.hpp). Each frame
// the selector (selector.hpp) walks the octree for the camera and selects the faces
// valid for the viewpoint:
//   * ddo: boxes are tested against the selector's CPU occlusion map; nothing is drawn;
//   * ddo+log: the merged occluder quads are drawn into the application's depth buffer by
//     its drawer (a GL application: gl::OccluderRenderer, depth only) and announced with
//     their pixels and farthest keys.
// The octree holds the static objects it was built from; boxes of anything else (moving
// objects) are tested against the same occluders, which only say where static geometry
// hides everything behind.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "logrid/ddo/selector.hpp"
#include "logrid/occluder_source.hpp"

namespace logrid::ddo {

class OccluderPass final : public OccluderSource {
 public:
  // Draws `occluders` into the application's depth buffer for `camera` (depth only, with
  // the depth test that keeps the nearer fragment).
  using Drawer = std::function<void(const std::vector<Occluder>& occluders, const Camera& camera)>;

  // `octree` must outlive the pass. Without a drawer the pass serves ddo only.
  explicit OccluderPass(const Octree& octree, Drawer drawer = {},
                        const SelectorSettings& settings = {});

  // Selects for `camera`; returns the faces selected into the map, or, with `draw`, the
  // occluders drawn after merging. Throws logrid::Error for an invalid camera, or when
  // asked to draw without a drawer.
  std::uint64_t beginFrame(const Camera& camera, const ProjectionSettings& projection, bool draw,
                           std::vector<DrawnArea>& drawn) override;
  bool occludes(const PixelRect& rect, float threshold) const override;

  // The last frame's selection (occluders(), map()) and what it did.
  const Selector& selector() const { return selector_; }
  const SelectionStats& stats() const { return stats_; }

 private:
  Selector selector_;
  Drawer drawer_;
  SelectionStats stats_;
};

}  // namespace logrid::ddo
