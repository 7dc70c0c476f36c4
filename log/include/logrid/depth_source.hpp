// The grid's window onto the depth buffer.
//
// A depth source answers requests about rectangles of the application's depth buffer,
// always in depth keys (types.hpp). logrid's core never touches GL: the sources in
// zread/ read through glReadPixels, rings of pixel-buffer objects, a compute-shader
// reduction or hardware occlusion queries; those in cpu/ read a buffer in memory; a
// Vulkan or software renderer writes its own, most simply over logrid::PixelSource
// (pixel_source.hpp), which needs only the depth values of a rectangle.
//
// Asking and waiting are separate (docs/DESIGN.md, "Depth sources: asking and waiting apart"):
//   submit()   takes a batch of requests, from as many boxes as the caller gathered,
//              and the array their answers go to;
//   collect()  waits until every answer submitted since the last collect() is written.
// A synchronous source answers inside submit() and its collect() returns at once. An
// asynchronous source (traits().asynchronous) only issues the reads in submit(), so
// that the renderer is waited for once per batch rather than once per rectangle.
//
// Two kinds of request:
//   Summary  the nearest key, the farthest key and the number of free (still cleared)
//            pixels of the rectangle. Only sources that see depth values answer it
//            (traits().reads_depth); their summaries are exact.
//   Count    the number of pixels whose key is >= a threshold, i.e. the pixels where
//            geometry at the threshold depth could still show. Every source answers
//            it; a hardware occlusion query answers it by drawing the rectangle at the
//            threshold depth. A count may exceed the exact one (a query source counts
//            pixels up to one quantisation step in front of the threshold), never fall
//            short of it.
// Errors (error.hpp): beginFrame(), endFrame() and endAccess() return a Status. A request
// that fails (a renderer error, a buffer that cannot be mapped) is answered as if nothing
// were drawn over its pixels — a Summary with min_key -inf, max_key +inf and every pixel
// free, a Count of every pixel: never "hidden" — and its error is kept (fail()) until
// takeError(); endAccess() takes it by default, so that the culler reports it at the end
// of the Culler::nextBatch() that made the request, and abandons the frame.
// Answers describe the buffer as it was when submit() was called. Within a frame the
// application draws only with a depth test that keeps the nearer fragment, so keys only
// shrink: a farthest key and a count stay upper bounds however much is drawn between
// submit() and collect(), and a nearest key or a free-pixel count may not.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/types.hpp"

namespace logrid {

// What a Summary request answers.
struct AreaDepth {
  float min_key = 0;              // nearest key in the area
  float max_key = 0;              // farthest key in the area
  std::uint32_t free_pixels = 0;  // pixels still holding the clear value
};

enum class AreaAsk : std::uint8_t {
  Summary,  // AreaAnswer::depth (sources with traits().reads_depth only)
  Count,    // AreaAnswer::count: pixels whose key is >= AreaRequest::threshold
};

struct AreaRequest {
  PixelRect rect;  // non-empty, inside the viewport
  AreaAsk ask = AreaAsk::Summary;
  float threshold = 0;  // Count only
};

struct AreaAnswer {
  AreaDepth depth;          // Summary
  std::uint32_t count = 0;  // Count
};

struct DepthSourceTraits {
  const char* name = "";
  bool reads_depth = true;    // answers Summary requests, exactly
  bool asynchronous = false;  // submit() returns before the answers exist
};

// What a source did, accumulated since construction (the culler takes differences).
struct ReadCounters {
  std::uint64_t reads = 0;          // rectangles read or counted (one per request)
  std::uint64_t pixels = 0;         // pixels transferred or scanned
  std::uint64_t bytes = 0;          // bytes that crossed from the renderer to the caller
  std::uint64_t queries = 0;        // hardware occlusion queries issued
  std::uint64_t batches = 0;        // submit() calls that asked for anything
  std::uint64_t flushes = 0;        // times the source had to wait for the renderer
  std::uint64_t state_queries = 0;  // queries of the renderer's state (a GL source's
                                    // glGet* and glGetError, to keep the application's)
  double seconds = 0;               // wall time spent inside the source
};

class DepthSource {
 public:
  virtual ~DepthSource() = default;

  virtual DepthSourceTraits traits() const = 0;

  // Called at the start of each culled frame, after the application cleared its depth
  // buffer and before it draws anything. An error if the source cannot serve this camera
  // (size or depth set-up differ from the buffer it reads).
  virtual Status beginFrame(const Camera& camera) = 0;
  // Called at the end of each culled frame; nothing is pending by then.
  virtual Status endFrame() { return {}; }
  // The culler (or the application, through Culler::noteDrawn) drew something since the
  // last request: the next read waits for it.
  virtual void noteDraw() {}

  // The culler brackets the requests of each Culler::nextBatch() with these: in between,
  // nothing but the culler's sources uses the renderer. A GL source saves the
  // application's state once at its first request and restores it in endAccess() instead
  // of around each request (zread/gl_state.hpp, "Access windows"). endAccess() returns
  // the first error of the window's requests (by default takeError()); it is called also
  // when an exception (the application's own) leaves nextBatch(), its Status dropped.
  virtual void beginAccess() {}
  virtual Status endAccess() { return takeError(); }

  // Asks `count` requests. answers[i] answers requests[i]; it is written no later than
  // the next collect() and must stay valid until then. Preconditions: every rect is
  // non-empty and inside the viewport; Summary only where traits().reads_depth.
  virtual void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) = 0;
  // Waits until every answer submitted since the last collect() is written.
  virtual void collect() {}

  // Synchronous conveniences over submit() + collect(), one answer per rectangle.
  void summarize(const PixelRect* rects, std::size_t count, AreaDepth* out);
  void countAtOrBeyond(const PixelRect* rects, std::size_t count, float threshold,
                       std::uint32_t* out);

  const ReadCounters& counters() const { return counters_; }
  // The first error of a request since the last takeError(), and clears it (ok if none).
  Status takeError() { return failure_.take(); }

 protected:
  // Keeps the first error of a request for takeError(); the request is answered as if
  // nothing were drawn over it (conservativeAnswer()).
  void fail(Status error) { failure_.note(std::move(error)); }
  static AreaAnswer conservativeAnswer(const AreaRequest& request);

  ReadCounters counters_;
  FirstError failure_;

 private:
  std::vector<AreaRequest> scratch_requests_;
  std::vector<AreaAnswer> scratch_answers_;
};

// What only the HZB baseline needs besides a DepthSource: the keys of a whole area, to
// build its pyramid from (depth_pyramid.hpp). A source for the lazy grid does without;
// logrid::PixelSource (pixel_source.hpp) is both.
class KeyReader {
 public:
  virtual ~KeyReader() = default;
  // Writes rect.area() keys, row by row from the bottom row (glReadPixels order), at
  // once. Preconditions: rect non-empty and inside the viewport; nothing submitted and
  // not yet collected.
  virtual void readKeys(const PixelRect& rect, float* keys) = 0;
};

}  // namespace logrid
