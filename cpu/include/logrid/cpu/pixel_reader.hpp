// Base of every depth source that reads pixels: it fetches rectangles of native depth
// values and lets the shared kernels (logrid/depth_kernels.hpp) answer, so that every
// reader rounds the same way.
//
// A subclass implements fetch() and, if it reads asynchronously, issue():
//   synchronous reader   submit() fetches and answers at once (collect() has nothing
//                        left to do);
//   asynchronous reader  submit() only issues the reads of its rectangles; collect()
//                        fetches every rectangle issued since the last collect() (one
//                        wait) and answers them.
#pragma once

#include <cstddef>
#include <vector>

#include "logrid/depth_kernels.hpp"
#include "logrid/depth_source.hpp"

namespace logrid::cpu {

class PixelReader : public DepthSource {
 public:
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override;
  void collect() override;
  void readKeys(const PixelRect& rect, float* keys) override;

  // The renderer drew since the last read: the next read waits for it (counted as a flush).
  void noteDraw() override { drawn_since_read_ = true; }

 protected:
  // Asynchronous readers: starts reading `count` rectangles (appended to what is already
  // issued since the last fetch). Synchronous readers leave it empty.
  virtual void issue(const PixelRect* rects, std::size_t count) {
    (void)rects;
    (void)count;
  }
  // Makes the native depth values of every rectangle available: data[i] points at rect
  // i's values, rows bottom-up, strides[i] values apart, valid until the next issue() or
  // fetch(). An asynchronous reader receives exactly the rectangles issued since the
  // last fetch, in order, and waits for them here.
  virtual void fetch(const PixelRect* rects, std::size_t count, const void** data,
                     std::size_t* strides) = 0;

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

}  // namespace logrid::cpu
