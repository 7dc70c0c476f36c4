// The GL state of an occlusion-query pass (BoxQuerySource): set for the pass, whatever
// the application left, and restored exactly when the pass ends (also on an exception).
//
// Local to the query source until the general state guard of zread (GlStateGuard, being
// written on another branch) lands; then its prepareDraw() replaces this file. Set and
// restored: the draw framebuffer, viewport (index 0), depth range, clip control (origin
// lower-left, the camera's depth mode), depth test, function and write mask, colour write
// masks of every draw buffer, stencil test, face culling, polygon mode, rasterizer
// discard, depth clamp, polygon offset (fill), scissor test and box, sample mask, sample
// coverage and alpha to coverage, the clip distances, the depth bounds test where the
// driver has it, the program and the vertex array. Not handled: active conditional
// rendering and unpaused transform feedback (the guard refuses them).
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstdint>

#include "logrid/types.hpp"

namespace logrid::zread::detail {

class QueryPassState {
 public:
  static constexpr int kMaxDrawBuffers = 16;
  static constexpr int kMaxClipDistances = 16;

  // Saves the state listed above, then sets the pass's: draws into `framebuffer` over
  // [0, width) x [0, height) with depth range [0, 1], the depth test on with `depth_func`,
  // every write off, `clip_depth_mode` (GL_NEGATIVE_ONE_TO_ONE or GL_ZERO_TO_ONE), and
  // `program` and `vertex_array` bound. The scissor test is off until scissor() is called.
  QueryPassState(GLuint framebuffer, GLint width, GLint height, GLenum depth_func,
                 GLenum clip_depth_mode, GLuint program, GLuint vertex_array);
  ~QueryPassState();
  QueryPassState(const QueryPassState&) = delete;
  QueryPassState& operator=(const QueryPassState&) = delete;

  // Turns the scissor test on with this box.
  void scissor(const PixelRect& rect);

 private:
  GLint draw_framebuffer_ = 0, program_ = 0, vertex_array_ = 0;
  GLint viewport_[4] = {};
  GLdouble depth_range_[2] = {0, 1};
  GLint clip_origin_ = 0, clip_depth_mode_ = 0;
  GLint depth_func_ = 0, polygon_mode_[2] = {}, scissor_box_[4] = {};
  GLboolean depth_mask_ = GL_TRUE;
  GLboolean color_masks_[kMaxDrawBuffers][4] = {};
  GLint draw_buffers_ = 0, clip_distances_ = 0;
  // Capabilities, saved and restored as enabled or not.
  static constexpr std::array<GLenum, 11> kCaps = {
      GL_DEPTH_TEST,         GL_STENCIL_TEST,
      GL_CULL_FACE,          GL_RASTERIZER_DISCARD,
      GL_DEPTH_CLAMP,        GL_POLYGON_OFFSET_FILL,
      GL_SCISSOR_TEST,       GL_SAMPLE_MASK,
      GL_SAMPLE_COVERAGE,    GL_SAMPLE_ALPHA_TO_COVERAGE,
      GL_SAMPLE_ALPHA_TO_ONE};
  std::array<GLboolean, kCaps.size()> caps_{};
  GLboolean clip_enabled_[kMaxClipDistances] = {};
  bool depth_bounds_ = false;
  GLboolean depth_bounds_enabled_ = GL_FALSE;
};

}  // namespace logrid::zread::detail
