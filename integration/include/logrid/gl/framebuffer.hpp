// An off-screen framebuffer: RGBA8 colour, a depth buffer of 16, 24 or 32-bit float,
// and optionally an R32UI object-ID buffer, set up for one depth convention.
//
// Conventions (DESIGN.md "Depth conventions"):
//   standard  glClipControl(GL_LOWER_LEFT, clip range), cleared to 1, GL_LESS
//   reversed  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), cleared to 0, GL_GREATER
// Rows read back are bottom-up, like glReadPixels.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"

namespace logrid::gl {

struct FramebufferDesc {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  DepthSetup depth;
  bool object_ids = false;  // add an R32UI attachment (colour attachment 1)
};

// Sets the depth state for a convention on the current context: clip control, depth
// function, clear depth, depth test and depth writes on.
void applyDepthState(const DepthSetup& depth);

// The GL internal format for a depth format (GL_DEPTH_COMPONENT16/24/32F).
std::uint32_t depthInternalFormat(DepthFormat format);

class Framebuffer {
 public:
  // Requires a current context. Throws logrid::Error when a side is 0 or exceeds the
  // driver's limits, the depth set-up holds an unknown enum value, the format is not
  // renderable, memory runs out or the framebuffer is incomplete, each with the value
  // that failed.
  explicit Framebuffer(const FramebufferDesc& desc);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  const FramebufferDesc& desc() const { return desc_; }
  std::uint32_t handle() const { return fbo_; }
  std::uint32_t depthTexture() const { return depth_; }

  // Binds for drawing: framebuffer, viewport, draw buffers and the depth state.
  void bind() const;
  // Clears colour to `rgba`, depth to the convention's clear value, IDs to `kNoObject`.
  void clear(const float rgba[4]) const;
  // The same without touching colour (for an ID pass after a frame, object_id_oracle.hpp).
  void clearDepthAndIds() const;
  // Draw only into the ID attachment (for the ID pass) or only into colour.
  void selectIdPass(bool id_pass) const;

  std::vector<std::uint8_t> readColor() const;       // width * height * 4, RGBA
  std::vector<float> readDepth() const;              // window depth as float
  std::vector<std::uint32_t> readObjectIds() const;  // requires object_ids

  static constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;

 private:
  void release();

  FramebufferDesc desc_;
  std::uint32_t fbo_ = 0;
  std::uint32_t color_ = 0;
  std::uint32_t ids_ = 0;
  std::uint32_t depth_ = 0;
};

}  // namespace logrid::gl
