// A depth source that reduces the depth buffer on the GPU: a compute shader (GL 4.3+)
// reads each requested rectangle of the depth texture and writes its nearest and
// farthest depth, its free-pixel count and its count at or beyond the threshold into a
// buffer, so a refresh moves 16 bytes per rectangle instead of its depth values.
// Asynchronous: submit() uploads the batch's rectangles, dispatches and fences;
// collect() waits for the fences and reads the answers from persistently mapped memory.
//
// Two kernels:
//   PerRequest    one invocation per rectangle, a serial loop over its pixels: the fast
//                 one on llvmpipe, where barriers are expensive (docs/PLATFORM.md);
//   PerWorkgroup  one 16x16 workgroup per rectangle with a shared-memory reduction: the
//                 one for GPUs.
// Kernel::Auto picks PerRequest on software renderers and PerWorkgroup elsewhere.
//
// Needs the framebuffer's depth attachment to be a 2D depth texture (a renderbuffer
// cannot be read by a shader) or multisampled: beginFrame() returns an error (Unsupported)
// otherwise, as it does where the context has no compute shaders (below OpenGL 4.3). A multisampled
// buffer (Camera::multisample set) is reduced from its resolve, the farthest sample of each pixel
// (multisample.hpp). The application's texture and sampler state do not matter: the dispatch binds
// its own sampler and sets the texture's swizzle, depth-stencil mode and base level for its
// duration (GlStateGuard). D16 and D24 values reach the shader as normalised floats; their answers
// are widened by one float step (nearest key down, farthest up, counts at a threshold one step
// nearer) so that the conversion's rounding never makes them less conservative than
// the CPU kernels' exact ones. D32F answers are exact.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/depth_source.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/multisample.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {

class ReductionSource : public DepthSource, public KeyReader {
 public:
  enum class Kernel : std::uint8_t { Auto, PerRequest, PerWorkgroup };

  explicit ReductionSource(std::uint32_t framebuffer, Kernel kernel = Kernel::Auto,
                           GlStatePolicy state = GlStatePolicy::Restore);
  ~ReductionSource() override;
  ReductionSource(const ReductionSource&) = delete;
  ReductionSource& operator=(const ReductionSource&) = delete;

  DepthSourceTraits traits() const override { return {"reduce", true, true}; }
  Status beginFrame(const Camera& camera) override;
  Status endFrame() override;
  void noteDraw() override { drawn_since_read_ = true; }
  void beginAccess() override { guard_.beginAccess(); }
  Status endAccess() override { return guard_.endAccess(); }

  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override;
  void collect() override;
  // Reads the rectangle with glReadPixels (a debugging aid, not the fast path).
  void readKeys(const PixelRect& rect, float* keys) override;

  Kernel kernel() const { return kernel_; }

 private:
  struct Slot {
    std::uint32_t requests = 0;  // SSBO of the batch's rectangles
    std::uint32_t answers = 0;   // SSBO of its answers, persistently mapped
    std::size_t capacity = 0;    // rectangles either buffer holds
    const unsigned char* mapped = nullptr;
    void* fence = nullptr;  // GLsync, until collected
    std::vector<AreaAnswer*> out;
    std::vector<AreaRequest> asked;
  };
  Slot* freeSlot(std::size_t count);  // nullptr (and fail()) if it cannot map one
  void release(Slot& slot);
  // False (the error noted) if the dispatch failed: nothing is in flight then.
  bool dispatch(Slot& slot, const AreaRequest* requests, std::size_t count);

  std::uint32_t framebuffer_;
  Kernel kernel_;
  Status unusable_;  // no compute shaders, or a kernel the driver does not compile
  std::unique_ptr<Program> program_;
  DepthAttachment attachment_;
  GlStateGuard guard_;
  std::unique_ptr<MultisampleResolver> resolver_;
  std::vector<PixelRect> rects_;
  std::uint32_t texture_ = 0;  // the depth attachment, found in beginFrame()
  std::int32_t texture_level_ = 0;
  DepthSetup depth_;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
  std::vector<Slot> slots_;
  std::vector<unsigned char> upload_;
  bool drawn_since_read_ = false;
};

}  // namespace logrid::zread
