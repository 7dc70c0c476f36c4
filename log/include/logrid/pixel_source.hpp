// A base for depth sources of one's own: a Vulkan or Direct3D renderer's read-back, a CPU
// rasteriser's buffer, a depth buffer in a file. The subclass only says where the depth
// values of a rectangle are; the base answers every request from them with the kernels
// every logrid source shares (depth_kernels.hpp: min keys rounded down, max keys up,
// counts towards "not occluded"), and keeps the counters (DepthSource::counters()).
//
// A subclass implements:
//   traits()      its name; reads_depth true (it reads values); asynchronous if it
//                 implements issue() and waits in fetch();
//   beginFrame()  checks that its buffer matches the camera (size, depth set-up; an
//                 error naming the value if not) and sets encoding_: the native type of
//                 its values and the depth convention;
//   fetch()       makes the native values of each rectangle available (below), or, where
//                 it cannot, says why with fail() and leaves the rectangle's data null;
//   issue()       optional: starts reading rectangles that fetch() will wait for.
// A synchronous subclass answers inside submit(); an asynchronous one issues in submit()
// and fetches every rectangle issued since the last collect() in collect(), so that the
// renderer is waited for once per batch.
//
// samples/example/vulkan_style_source.hpp is a complete one over a mapped read-back
// buffer, cpu/software_depth.hpp one over a float array; both without GL.
#pragma once

#include <cstddef>
#include <vector>

#include "logrid/depth_kernels.hpp"
#include "logrid/depth_source.hpp"

namespace logrid {

class PixelSource : public DepthSource, public KeyReader {
 public:
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override;
  void collect() override;
  // Reads at once (a KeyReader, for the HZB baseline); collect() pending requests first.
  void readKeys(const PixelRect& rect, float* keys) override;

  // The renderer drew since the last read: the next read waits for it (counted as a flush).
  void noteDraw() override { drawn_since_read_ = true; }

 protected:
  // Asynchronous sources: starts reading `count` rectangles (appended to what is already
  // issued since the last fetch). Synchronous sources leave it empty.
  virtual void issue(const PixelRect* rects, std::size_t count) {
    (void)rects;
    (void)count;
  }
  // Makes the native depth values of every rectangle available: data[i] points at rect
  // i's values, rows bottom-up, strides[i] values apart, valid until the next issue() or
  // fetch(). An asynchronous source receives exactly the rectangles issued since the
  // last fetch, in order, and waits for them here. A rectangle whose values cannot be
  // had (a renderer error) gets null data and fail() says why: it is answered as if
  // nothing were drawn over it.
  virtual void fetch(const PixelRect* rects, std::size_t count, const void** data,
                     std::size_t* strides) = 0;

  // How the fetched values store depth; set in beginFrame().
  DepthEncoding encoding_;

 private:
  void answerPending();
  bool drawn_since_read_ = false;
  std::vector<AreaRequest> pending_;
  std::vector<AreaAnswer*> pending_answers_;
  std::vector<PixelRect> rects_;
  std::vector<const void*> data_;
  std::vector<std::size_t> strides_;
};

}  // namespace logrid
