// An off-screen framebuffer: RGBA8 colour, a depth buffer of 16, 24 or 32-bit float,
// and optionally an R32UI object-ID buffer, set up for one depth convention; single- or
// multisampled (every attachment a multisampled texture with the same sample count).
//
// Conventions (docs/DESIGN.md, "Depth conventions and depth keys"):
//   standard  glClipControl(GL_LOWER_LEFT, clip range), cleared to 1, GL_LESS
//   reversed  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), cleared to 0, GL_GREATER
// Rows read back are bottom-up, like glReadPixels.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"

namespace logrid::zread {
class GlStateGuard;
}

namespace logrid::gl {

struct FramebufferDesc {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  DepthSetup depth;
  bool object_ids = false;  // add an R32UI attachment (colour attachment 1)
  // Samples per pixel: 0 (or 1) single-sampled, else 2 to GL_MAX_SAMPLES (the driver may
  // round up; samples() says what it gave). A multisampled framebuffer needs
  // Camera::multisample set for culling (zread/multisample.hpp).
  std::uint32_t samples = 0;
};

// Sets the depth state for a convention on the current context: clip control, depth
// function, clear depth, depth test and depth writes on.
void applyDepthState(const DepthSetup& depth);

// The GL internal format for a depth format (GL_DEPTH_COMPONENT16/24/32F).
std::uint32_t depthInternalFormat(DepthFormat format);

class Framebuffer {
 public:
  // Requires a current context. The result form (logrid/error.hpp): the framebuffer, or
  // ErrorCode::InvalidArgument when a side is 0 or exceeds the driver's limits or the
  // depth set-up holds an unknown enum value, ErrorCode::Unsupported when the sample
  // count exceeds the driver's or the format is not renderable, ErrorCode::Runtime when
  // memory runs out or GL fails, each with the value that failed.
  static Result<std::unique_ptr<Framebuffer>> create(const FramebufferDesc& desc);
  // The throwing form: throws logrid::Error where create() fails.
  explicit Framebuffer(const FramebufferDesc& desc);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  const FramebufferDesc& desc() const { return desc_; }
  std::uint32_t handle() const { return fbo_; }
  std::uint32_t depthTexture() const { return depth_; }
  // Samples per pixel the driver allocated (0: single-sampled).
  std::uint32_t samples() const { return samples_; }

  // Binds for drawing: framebuffer, viewport, draw buffers and the depth state.
  void bind() const;
  // Scissor test off and colour writes on: what a whole-frame clear or pass needs, and
  // what a depth source under GlStatePolicy::ApplicationManaged may leave set (a
  // multisample resolve: the scissor around its last rectangle, colour writes off).
  // Not part of bind(): an application's own scissor between its draws is its own.
  void unmask() const;
  // Clears colour to `rgba`, depth to the convention's clear value, IDs to `kNoObject`.
  void clear(const float rgba[4]) const;
  // The same without touching colour (for an ID pass after a frame, object_id_oracle.hpp).
  void clearDepthAndIds() const;
  // Draw only into the ID attachment (for the ID pass) or only into colour.
  void selectIdPass(bool id_pass) const;

  // Read-backs, rows bottom-up. Depth and IDs of a multisampled framebuffer come per
  // sample: samples() values per pixel, pixel (x, y)'s at ((y * width + x) * samples()).
  // Colour is resolved (averaged) to one value per pixel. In both forms: the values or
  // the error (ErrorCode::Runtime for GL's; readObjectIds() without object_ids:
  // ErrorCode::InvalidArgument).
  Result<std::vector<std::uint8_t>> tryReadColor() const;       // width * height * 4, RGBA
  Result<std::vector<float>> tryReadDepth() const;              // window depth as float
  Result<std::vector<std::uint32_t>> tryReadObjectIds() const;  // requires object_ids
  std::vector<std::uint8_t> readColor() const;
  std::vector<float> readDepth() const;
  std::vector<std::uint32_t> readObjectIds() const;

  static constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;

 private:
  struct Unmade {};
  Framebuffer(Unmade, const FramebufferDesc& desc);  // no GL objects: make() makes them
  Status make();
  void release();
  Status readSamples(int kind, std::uint32_t texture, std::uint32_t values_per_pixel,
                     void* dst) const;
  struct SampleReader;

  FramebufferDesc desc_;
  std::uint32_t fbo_ = 0;
  std::uint32_t color_ = 0;
  std::uint32_t ids_ = 0;
  std::uint32_t depth_ = 0;
  std::uint32_t samples_ = 0;
  std::unique_ptr<zread::GlStateGuard> guard_;  // read-backs leave the app's state alone
  mutable std::unique_ptr<SampleReader> sample_reader_;
};

#if LOGRID_HAS_EXCEPTIONS
inline Framebuffer::Framebuffer(const FramebufferDesc& desc) : Framebuffer(Unmade{}, desc) {
  logrid::orThrow(make());
}
inline std::vector<std::uint8_t> Framebuffer::readColor() const {
  return logrid::orThrow(tryReadColor());
}
inline std::vector<float> Framebuffer::readDepth() const { return logrid::orThrow(tryReadDepth()); }
inline std::vector<std::uint32_t> Framebuffer::readObjectIds() const {
  return logrid::orThrow(tryReadObjectIds());
}
#endif

}  // namespace logrid::gl
