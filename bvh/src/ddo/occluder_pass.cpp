#include "logrid/ddo/occluder_pass.hpp"

#include "logrid/error.hpp"

namespace logrid::ddo {

OccluderPass::OccluderPass(const Octree& octree, Drawer drawer, const SelectorSettings& settings)
    : selector_(octree, settings), drawer_(std::move(drawer)) {}

std::uint64_t OccluderPass::beginFrame(const Camera& camera, const ProjectionSettings& projection,
                                       bool draw, std::vector<DrawnArea>& drawn) {
  if (draw && !drawer_) {
    throw Error(ErrorCode::InvalidArgument,
                "ddo::OccluderPass: asked to draw its occluders (ddo+log) but made without a "
                "drawer; pass one, e.g. gl::OccluderRenderer's draw into the frame's framebuffer");
  }
  selector_.select(camera, {}, stats_, projection);
  if (!draw) return stats_.faces_selected;
  drawer_(selector_.occluders(), camera);
  for (const Occluder& o : selector_.occluders()) drawn.push_back({o.rect, o.far_key});
  return selector_.occluders().size();
}

bool OccluderPass::occludes(const PixelRect& rect, float threshold) const {
  return selector_.map().occludes(rect, threshold);
}

}  // namespace logrid::ddo
