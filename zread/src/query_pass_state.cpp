#include "query_pass_state.hpp"

#include <algorithm>

namespace logrid::zread::detail {

namespace {

bool hasDepthBounds() {
  static const bool has = epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
  return has;
}

// A name the application deleted while it was bound ceased to exist when the pass bound
// its own: restore only names that still exist (0 otherwise, as if it had unbound it).
GLuint existing(GLint name, GLboolean (*is)(GLuint)) {
  return name != 0 && is(GLuint(name)) ? GLuint(name) : 0;
}

}  // namespace

QueryPassState::QueryPassState(GLuint framebuffer, GLint width, GLint height, GLenum depth_func,
                               GLenum clip_depth_mode, GLuint program, GLuint vertex_array) {
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
  glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
  glGetIntegerv(GL_VIEWPORT, viewport_);
  glGetDoublev(GL_DEPTH_RANGE, depth_range_);
  glGetIntegerv(GL_CLIP_ORIGIN, &clip_origin_);
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth_mode_);
  glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
  glGetIntegerv(GL_POLYGON_MODE, polygon_mode_);
  glGetIntegerv(GL_SCISSOR_BOX, scissor_box_);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &draw_buffers_);
  draw_buffers_ = std::clamp(draw_buffers_, 1, kMaxDrawBuffers);
  for (GLint i = 0; i < draw_buffers_; ++i) {
    glGetBooleani_v(GL_COLOR_WRITEMASK, GLuint(i), color_masks_[i]);
  }
  for (std::size_t i = 0; i < kCaps.size(); ++i) caps_[i] = glIsEnabled(kCaps[i]);
  glGetIntegerv(GL_MAX_CLIP_DISTANCES, &clip_distances_);
  clip_distances_ = std::clamp(clip_distances_, 0, kMaxClipDistances);
  for (GLint i = 0; i < clip_distances_; ++i) {
    clip_enabled_[i] = glIsEnabled(GLenum(GL_CLIP_DISTANCE0 + i));
  }
  depth_bounds_ = hasDepthBounds();
  if (depth_bounds_) depth_bounds_enabled_ = glIsEnabled(GL_DEPTH_BOUNDS_TEST_EXT);

  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glDepthRange(0.0, 1.0);
  glClipControl(GL_LOWER_LEFT, clip_depth_mode);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(depth_func);
  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);  // every draw buffer
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  for (std::size_t i = 1; i < kCaps.size(); ++i) glDisable(kCaps[i]);  // all but the depth test
  for (GLint i = 0; i < clip_distances_; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
  if (depth_bounds_) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
  glUseProgram(program);
  glBindVertexArray(vertex_array);
}

void QueryPassState::scissor(const PixelRect& r) {
  glEnable(GL_SCISSOR_TEST);
  glScissor(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
}

QueryPassState::~QueryPassState() {
  glBindVertexArray(existing(vertex_array_, glIsVertexArray));
  glUseProgram(existing(program_, glIsProgram));
  if (depth_bounds_ && depth_bounds_enabled_) glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
  for (GLint i = 0; i < clip_distances_; ++i) {
    if (clip_enabled_[i]) glEnable(GLenum(GL_CLIP_DISTANCE0 + i));
  }
  for (std::size_t i = 0; i < kCaps.size(); ++i) {
    if (caps_[i]) {
      glEnable(kCaps[i]);
    } else {
      glDisable(kCaps[i]);
    }
  }
  glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygon_mode_[0]));
  for (GLint i = 0; i < draw_buffers_; ++i) {
    const GLboolean* m = color_masks_[i];
    glColorMaski(GLuint(i), m[0], m[1], m[2], m[3]);
  }
  glDepthMask(depth_mask_);
  glDepthFunc(GLenum(depth_func_));
  glScissor(scissor_box_[0], scissor_box_[1], scissor_box_[2], scissor_box_[3]);
  glClipControl(GLenum(clip_origin_), GLenum(clip_depth_mode_));
  glDepthRange(depth_range_[0], depth_range_[1]);
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, existing(draw_framebuffer_, glIsFramebuffer));
}

}  // namespace logrid::zread::detail
