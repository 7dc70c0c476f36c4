// The grid's window onto the depth buffer.
//
// A depth source answers pixel-level queries over rectangles of the application's
// depth buffer, always in depth keys (types.hpp). logrid's core never touches GL: the
// sources in zread/ read through glReadPixels, pixel-buffer objects or hardware
// occlusion queries, or from a software buffer; a Vulkan or software renderer writes
// its own.
//
// Two kinds of query:
//   summarize()        the nearest key, the farthest key and the number of free
//                      (still cleared) pixels of each rectangle, and
//   readKeys()         every key of a rectangle: both only from sources that read
//                      pixels (traits().reads_pixels == true), and exact.
//   countAtOrBeyond()  the number of pixels whose key is >= a threshold, i.e. the
//                      pixels where geometry at the threshold depth could still show.
//                      Every source answers it; a hardware occlusion query answers it
//                      by drawing a rectangle at the threshold depth.
// Calls take arrays so that a batching source (pixel-buffer objects) can issue every
// read before waiting for any; a synchronous source answers them one by one.
#pragma once

#include <cstddef>
#include <cstdint>

#include "logrid/camera.hpp"
#include "logrid/types.hpp"

namespace logrid {

struct AreaDepth {
  float min_key = 0;              // nearest key in the area
  float max_key = 0;              // farthest key in the area
  std::uint32_t free_pixels = 0;  // pixels still holding the clear value
};

struct AreaQuery {
  PixelRect rect;
  float threshold = 0;  // count the pixels whose key is >= threshold
};

struct DepthSourceTraits {
  const char* name = "";
  bool reads_pixels = true;  // summarize() and readKeys() are supported and exact
  bool batched = false;      // answers many areas per call faster than one at a time
};

// What a source did, accumulated since construction (the culler takes differences).
struct ReadCounters {
  std::uint64_t reads = 0;    // pixel reads issued (one per rectangle)
  std::uint64_t pixels = 0;   // pixels transferred or scanned
  std::uint64_t queries = 0;  // hardware occlusion queries issued
  std::uint64_t flushes = 0;  // times the source had to wait for the renderer
  double seconds = 0;         // wall time spent inside the source
};

class DepthSource {
 public:
  virtual ~DepthSource() = default;

  virtual DepthSourceTraits traits() const = 0;

  // Called at the start of each culled frame, after the application cleared its depth
  // buffer and before it draws anything. Throws logrid::Error if the source cannot
  // serve this camera (size or depth set-up differ from the buffer it reads).
  virtual void beginFrame(const Camera& camera) = 0;
  virtual void endFrame() {}
  // The culler drew something since the last query (a source may count the flush).
  virtual void noteDraw() {}

  // Preconditions: each rect is non-empty and inside the viewport.
  virtual void summarize(const PixelRect* rects, std::size_t count, AreaDepth* out) = 0;
  virtual void countAtOrBeyond(const AreaQuery* queries, std::size_t count, std::uint32_t* out) = 0;
  // Writes rect.area() keys, row by row from the bottom row (glReadPixels order).
  virtual void readKeys(const PixelRect& rect, float* keys) = 0;

  const ReadCounters& counters() const { return counters_; }

 protected:
  ReadCounters counters_;
};

}  // namespace logrid
