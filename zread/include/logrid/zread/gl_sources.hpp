// Depth sources that read an OpenGL framebuffer's depth buffer. Each needs a current
// GL 4.5 context and the framebuffer the application draws into (0: the default one).
//
//   ReadPixelsSource  glReadPixels, synchronous: answers inside submit(), one read per
//                     rectangle. Reads the native type (32F as float, D24 as unsigned
//                     int, D16 as unsigned short), the fast path everywhere. The
//                     simple default.
//   PboSource         a ring of persistently mapped pixel-buffer objects with fences,
//                     asynchronous: submit() issues every read of the batch into a
//                     buffer and fences it, collect() waits for the fences and answers
//                     from the mapped memory. The GPU path (the "parallel pixel-level
//                     queries" LOG §6 leaves as future work); on Mesa llvmpipe a read
//                     into a PBO blocks like a direct read (docs/PLATFORM.md).
//   QuerySource       hardware occlusion queries, asynchronous: counts the pixels at or
//                     beyond a depth by drawing the rectangle (scissored) at that depth
//                     with GL_SAMPLES_PASSED and no writes; submit() issues the queries,
//                     collect() reads their results. Reads no depth at all, so it
//                     answers Count requests only. The depth test compares in the
//                     buffer's format, so for D16 and D24 a count may include pixels up
//                     to one quantisation step in front of the threshold (never fewer
//                     than those at or beyond it): conservative.
// The compute-shader tile reduction is in reduction_source.hpp.
//
// beginFrame() checks the framebuffer's depth attachment against Camera::depth.format
// and returns an error if they differ, or if it is multisampled and Camera::multisample
// is false (or if the source could not be made: a shader the driver does not compile). The pixel
// readers read multisampled depth through MultisampleResolver (multisample.hpp): the farthest
// sample of each pixel, as 32-bit float; the query source counts samples.
//
// Every source sets the GL state its draws and reads depend on and restores the
// application's exactly (GlStateGuard, gl_state.hpp); it refuses conditional rendering,
// unpaused transform feedback and a GL error the application left pending, and reports a
// GL error of its own calls naming the call: the requests it spoils are answered
// "visible" and the error is reported by endAccess() (DepthSource, "Errors"). The query source also
// refuses while the application has a GL_SAMPLES_PASSED query active. The culler opens
// one access window per Culler::nextBatch() on each source (beginAccess, endAccess): the
// state is saved and restored, and errors checked, once per batch, not once per read.
//
// Constructed with GlStatePolicy::ApplicationManaged (gl_state.hpp), a source queries
// nothing and leaves what its passes set as they set it; per source (the items each
// GlStateGuard call lists in gl_state.hpp):
//   ReadPixelsSource, PboSource  prepareRead; for a multisampled buffer also the
//                                resolve's prepareDraw, program, vertex array and
//                                bindTexture (multisample.hpp).
//   QuerySource                  prepareDraw, its program and vertex array.
//   ReductionSource              prepareProgram, bindTexture, two bindStorageBuffer
//                                points; for a multisampled buffer also the resolve's.
//   BoxQuerySource               prepareDraw, clipControl, its program and vertex array.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/depth_source.hpp"
#include "logrid/pixel_source.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/multisample.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {

class ReadPixelsSource : public PixelSource {
 public:
  explicit ReadPixelsSource(std::uint32_t framebuffer,
                            GlStatePolicy state = GlStatePolicy::Restore);
  DepthSourceTraits traits() const override { return {"readpixels", true, false}; }
  Status beginFrame(const Camera& camera) override;
  void beginAccess() override { guard_.beginAccess(); }
  Status endAccess() override { return guard_.endAccess(); }

 protected:
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  std::uint32_t framebuffer_;
  std::uint32_t type_ = 0;  // GL type of the native read
  DepthAttachment attachment_;
  GlStateGuard guard_;
  std::unique_ptr<MultisampleResolver> resolver_;
  std::vector<unsigned char> scratch_;
};

class PboSource : public PixelSource {
 public:
  explicit PboSource(std::uint32_t framebuffer, GlStatePolicy state = GlStatePolicy::Restore);
  ~PboSource() override;
  PboSource(const PboSource&) = delete;
  PboSource& operator=(const PboSource&) = delete;
  DepthSourceTraits traits() const override { return {"pbo", true, true}; }
  Status beginFrame(const Camera& camera) override;
  Status endFrame() override;
  void beginAccess() override { guard_.beginAccess(); }
  Status endAccess() override { return guard_.endAccess(); }

  // Buffers in the ring (grows when more batches are in flight than it holds).
  std::size_t ringSize() const { return slots_.size(); }

 protected:
  void issue(const PixelRect* rects, std::size_t count) override;
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  struct Slot {
    std::uint32_t buffer = 0;
    std::size_t capacity = 0;
    const unsigned char* mapped = nullptr;
    void* fence = nullptr;  // GLsync of the reads issued into it, until fetched
  };
  Slot* freeSlot(std::size_t bytes);  // nullptr (and fail()) if it cannot map one
  void release(Slot& slot);

  std::uint32_t framebuffer_;
  std::uint32_t type_ = 0;
  DepthAttachment attachment_;
  GlStateGuard guard_;
  std::unique_ptr<MultisampleResolver> resolver_;
  std::vector<Slot> slots_;
  std::size_t next_slot_ = 0;
  // Per rectangle issued since the last fetch: where its values land (kFailed: nowhere).
  static constexpr std::size_t kFailed = ~std::size_t{0};
  struct Issued {
    std::size_t slot;
    std::size_t offset;
  };
  std::vector<Issued> issued_;
};

class QuerySource : public DepthSource {
 public:
  explicit QuerySource(std::uint32_t framebuffer, GlStatePolicy state = GlStatePolicy::Restore);
  ~QuerySource() override;
  QuerySource(const QuerySource&) = delete;
  QuerySource& operator=(const QuerySource&) = delete;

  DepthSourceTraits traits() const override { return {"query", false, true}; }
  Status beginFrame(const Camera& camera) override;
  void noteDraw() override { drawn_since_query_ = true; }
  void beginAccess() override { guard_.beginAccess(); }
  Status endAccess() override { return guard_.endAccess(); }

  // Count requests only: a Summary request fails (Unsupported): this source never reads
  // depth values (and is no KeyReader).
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override;
  void collect() override;

 private:
  void answerConservatively(const AreaRequest* requests, std::size_t count, AreaAnswer* answers);

  std::uint32_t framebuffer_;
  DepthSetup depth_;
  std::int32_t width_ = 0, height_ = 0;
  GlStateGuard guard_;
  Status unusable_;  // its program could not be made: every frame fails with this
  std::unique_ptr<Program> program_;
  std::int32_t depth_uniform_ = -1;
  std::uint32_t vao_ = 0;
  std::vector<std::uint32_t> queries_;  // query objects, reused frame to frame
  struct Pending {
    std::uint32_t query;  // index into queries_
    AreaAnswer* answer;
  };
  std::vector<Pending> pending_;
  bool drawn_since_query_ = false;
};

}  // namespace logrid::zread
