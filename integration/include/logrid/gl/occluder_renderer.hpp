// Draws DDO occluders (logrid/ddo/selector.hpp) into the depth buffer of a framebuffer
// before a culler runs: depth only. The quads come in normalized device coordinates with
// w = 1, their depth already pushed back by the selector for the camera's depth setup, so
// the draw uses no matrix: the GL pipeline only clips, maps to the viewport and
// rasterises them.
//
// Whatever GL state the application left, the occluders land as the selector means them
// (zread::GlStateGuard's prepareDraw: no face culling, filled polygons, no stencil,
// scissor or polygon offset, viewport and depth range over the whole framebuffer, depth
// test on with the convention's function (GL_LESS, reversed GL_GREATER) and depth writes
// on, colour writes off; and the camera's clip control, lower-left origin), and the
// application finds its state as it left it, bindings included. A conservative culler
// depends on it: occluders drawn nowhere would only cost culling, but occluders drawn
// with a hostile offset, range or origin would hide what is visible.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/ddo/selector.hpp"
#include "logrid/error.hpp"

namespace logrid::zread {
class GlStateGuard;
}

namespace logrid::gl {

class OccluderRenderer {
 public:
  // Requires a current GL 4.5 context. The result form (logrid/error.hpp): the renderer,
  // or ErrorCode::Runtime for a GL error.
  static Result<std::unique_ptr<OccluderRenderer>> create();
  // The throwing form: throws logrid::Error where create() fails.
  OccluderRenderer();
  ~OccluderRenderer();
  OccluderRenderer(const OccluderRenderer&) = delete;
  OccluderRenderer& operator=(const OccluderRenderer&) = delete;

  // Draws the quads (two triangles each, one draw call) into the depth attachment of
  // `framebuffer` (0: the default framebuffer), which is camera.width x camera.height,
  // for `camera`, the camera the occluders were selected for. In both forms: fails for
  // what zread::GlStateGuard refuses (conditional rendering, unpaused transform feedback,
  // a pending GL error) and for a GL error of the draw. tryDraw() is what a
  // ddo::OccluderPass::Drawer returns.
  Status tryDraw(const std::vector<ddo::Occluder>& occluders, const Camera& camera,
                 std::uint32_t framebuffer);
  void draw(const std::vector<ddo::Occluder>& occluders, const Camera& camera,
            std::uint32_t framebuffer);

 private:
  struct Empty {};
  explicit OccluderRenderer(Empty);  // no GL objects: make() makes them
  Status make();

  struct Program;
  std::unique_ptr<Program> program_;
  std::unique_ptr<zread::GlStateGuard> guard_;
  std::uint32_t vao_ = 0;
  std::uint32_t buffer_ = 0;
  std::size_t capacity_ = 0;  // floats the buffer holds
  std::vector<float> vertices_;
};

#if LOGRID_HAS_EXCEPTIONS
inline OccluderRenderer::OccluderRenderer() : OccluderRenderer(Empty{}) { logrid::orThrow(make()); }
inline void OccluderRenderer::draw(const std::vector<ddo::Occluder>& occluders,
                                   const Camera& camera, std::uint32_t framebuffer) {
  logrid::orThrow(tryDraw(occluders, camera, framebuffer));
}
#endif

}  // namespace logrid::gl
