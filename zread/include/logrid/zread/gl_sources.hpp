// Depth sources that read an OpenGL framebuffer's depth buffer. Each needs a current
// GL 4.5 context and the framebuffer the application draws into (0: the default one).
//
//   ReadPixelsSource  glReadPixels, synchronous: one read per tile, the test stops at
//                     the first visible tile. Reads the native type (32F as float, D24
//                     as unsigned int, D16 as unsigned short), the fast path everywhere.
//   PboSource         pixel-buffer objects: every tile a test needs is read into one
//                     persistently mapped buffer, then one fence waits for all of them
//                     (the "parallel pixel-level queries" LOG §6 leaves as future work).
//                     Worth it on GPUs; on Mesa llvmpipe a read into a PBO blocks like a
//                     direct read and costs more (PLATFORM.md §2b).
//   QuerySource       hardware occlusion queries: counts the pixels at or beyond a depth
//                     by drawing the rectangle (scissored) at that depth with
//                     GL_SAMPLES_PASSED and no writes. Reads no depth at all. The depth
//                     test compares in the buffer's format, so for D16 and D24 the count
//                     may include pixels up to one quantisation step in front of the
//                     threshold (never fewer than those at or beyond it): conservative.
//
// beginFrame() checks the framebuffer's depth attachment against Camera::depth.format
// and throws logrid::Error if they differ, or if it is multisampled and
// Camera::multisample is false. Multisampled depth is read through MultisampleResolver
// (multisample.hpp): the farthest sample of each pixel.
//
// Every source sets the GL state its draws and reads depend on and restores the
// application's exactly (GlStateGuard, gl_state.hpp); it refuses conditional rendering
// and unpaused transform feedback, and reports a GL error of its own calls as a
// logrid::Error naming the call.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/cpu/pixel_reader.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/multisample.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {

class ReadPixelsSource : public cpu::PixelReader {
 public:
  explicit ReadPixelsSource(std::uint32_t framebuffer);
  DepthSourceTraits traits() const override { return {"readpixels", true, false}; }
  void beginFrame(const Camera& camera) override;

 protected:
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  std::uint32_t framebuffer_;
  std::uint32_t type_ = 0;  // GL type of the native read
  DepthSetup depth_;
  DepthAttachment attachment_;
  GlStateGuard guard_;
  std::unique_ptr<MultisampleResolver> resolver_;
  std::vector<unsigned char> scratch_;
};

class PboSource : public cpu::PixelReader {
 public:
  explicit PboSource(std::uint32_t framebuffer);
  ~PboSource() override;
  PboSource(const PboSource&) = delete;
  PboSource& operator=(const PboSource&) = delete;
  DepthSourceTraits traits() const override { return {"pbo", true, true}; }
  void beginFrame(const Camera& camera) override;

 protected:
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  void reserve(std::size_t bytes);
  std::uint32_t framebuffer_;
  std::uint32_t type_ = 0;
  DepthSetup depth_;
  DepthAttachment attachment_;
  GlStateGuard guard_;
  std::unique_ptr<MultisampleResolver> resolver_;
  std::uint32_t buffer_ = 0;
  std::size_t capacity_ = 0;
  const unsigned char* mapped_ = nullptr;
};

class QuerySource : public DepthSource {
 public:
  explicit QuerySource(std::uint32_t framebuffer);
  ~QuerySource() override;
  QuerySource(const QuerySource&) = delete;
  QuerySource& operator=(const QuerySource&) = delete;

  DepthSourceTraits traits() const override { return {"query", false, true}; }
  void beginFrame(const Camera& camera) override;
  void noteDraw() override { drawn_since_query_ = true; }

  // Not supported: throws logrid::Error (this source never reads pixels).
  void summarize(const PixelRect* rects, std::size_t count, AreaDepth* out) override;
  void readKeys(const PixelRect& rect, float* keys) override;
  void countAtOrBeyond(const AreaQuery* queries, std::size_t count, std::uint32_t* out) override;

 private:
  std::uint32_t framebuffer_;
  DepthSetup depth_;
  std::int32_t width_ = 0, height_ = 0;
  GlStateGuard guard_;
  std::unique_ptr<Program> program_;
  std::int32_t depth_uniform_ = -1;
  std::uint32_t vao_ = 0;
  std::vector<std::uint32_t> queries_;
  bool drawn_since_query_ = false;
};

}  // namespace logrid::zread
