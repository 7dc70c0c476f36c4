// Base of every depth source that reads pixels: it fetches a rectangle of native depth
// values and lets the shared kernels (logrid/depth_kernels.hpp) answer, so that every
// reader rounds the same way. Subclasses implement fetch().
#pragma once

#include <cstddef>
#include <vector>

#include "logrid/depth_kernels.hpp"
#include "logrid/depth_source.hpp"

namespace logrid::cpu {

class PixelReader : public DepthSource {
 public:
  void summarize(const PixelRect* rects, std::size_t count, AreaDepth* out) override;
  void countAtOrBeyond(const AreaQuery* queries, std::size_t count, std::uint32_t* out) override;
  void readKeys(const PixelRect& rect, float* keys) override;

  // The renderer drew since the last read: the next read waits for it (counted as a flush).
  void noteDraw() override { drawn_since_read_ = true; }

 protected:
  // Makes the native depth values of each rect available: data[i] points at rect i's
  // values, rows bottom-up, strides[i] values apart. The pointers stay valid until the
  // next fetch. A batching reader issues every read before waiting for any.
  virtual void fetch(const PixelRect* rects, std::size_t count, const void** data,
                     std::size_t* strides) = 0;

  DepthEncoding encoding_;

 private:
  void timedFetch(const PixelRect* rects, std::size_t count);
  bool drawn_since_read_ = false;
  std::vector<const void*> data_;
  std::vector<std::size_t> strides_;
  std::vector<PixelRect> rects_;
};

}  // namespace logrid::cpu
