// Hardware occlusion queries as logrid's query schedules see them (method.hpp: hwq, chc,
// stat, nohc and log+hwq). The schedules are GL-free logic in log/; they reach the
// renderer only through this interface. zread::BoxQuerySource implements it over an
// OpenGL framebuffer; a Vulkan, Direct3D or software renderer writes its own, and the
// unit tests drive the schedules with a fake one.
//
// A query counts the samples that pass the depth test when something is drawn against
// the application's depth buffer with depth and colour writes off, the test keeping the
// nearer-or-equal fragment (GL_LEQUAL standard, GL_GEQUAL reversed), as the buffer is when
// the query is issued: the renderer executes commands in order, so what is drawn after
// the issue does not count. Within a frame keys only shrink (culler.hpp), so a count of 0
// stays true however much is drawn before its result is read; a depth clear breaks that,
// and the culler discards the answers of queries issued before one.
//
// Two kinds of query:
//   issueBoxes  the faces of one or more world-space boxes, each given as a QueryBox from
//               Projector::queryBox(): widened and moved nearer so that a box with any
//               sample of its geometry visible shows at least one sample (projection.hpp,
//               "Query boxes"). Draw every face (no face culling). Several boxes in one
//               query are CHC++'s multi-queries: the count is their sum.
//   issueRects  pixel rectangles, each at one depth key (RectQuery): counts the pixels of
//               each rectangle whose stored key is >= its threshold (as DepthSource's
//               Count request does), summed.
// Counts may exceed the exact ones (a GL_ANY_SAMPLES_PASSED_CONSERVATIVE implementation
// answers 0 or 1, and may answer 1 where nothing passes); they must never be 0 where a
// sample passes.
//
// Asking and waiting are separate: issue*() returns a handle at once; ready() tells
// without waiting whether result() would wait; result() waits if it must, returns the
// count and releases the handle. Every handle issued in a frame is read by its end.
#pragma once

#include <cstddef>
#include <cstdint>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/projection.hpp"
#include "logrid/types.hpp"

namespace logrid {

using QueryHandle = std::uint32_t;

// A rectangle at a depth key (non-empty, inside the viewport).
struct RectQuery {
  PixelRect rect;
  float threshold = 0;
};

// What a query source did, accumulated since construction (the culler takes differences).
struct QueryCounters {
  std::uint64_t queries = 0;  // queries issued (box and rectangle)
  std::uint64_t boxes = 0;    // boxes and rectangles drawn by queries (a multi-query draws several)
  std::uint64_t polls = 0;    // ready() calls
  std::uint64_t waits = 0;    // result() calls whose answer was not there yet
  std::uint64_t flushes = 0;  // polls and results that made the renderer start or finish
                              // work drawn since the last one (each splits llvmpipe's frame)
  std::uint64_t state_queries = 0;  // queries of the renderer's state (ReadCounters')
  double seconds = 0;               // wall time inside the source
};

class OcclusionQueries {
 public:
  virtual ~OcclusionQueries() = default;

  virtual const char* queryName() const = 0;
  // Called at the start of each culled frame with the culler's camera, after the
  // application cleared its depth buffer. An error if the source cannot serve this camera
  // (a size or depth set-up that differs from its buffer's).
  virtual Status beginQueryFrame(const Camera& camera) = 0;
  // Called at the end of each culled frame; every handle has been read by then.
  virtual Status endQueryFrame() { return {}; }
  // Something was drawn since the last query call (counts flushes; nothing else).
  virtual void noteDraw() {}
  // Bracket each Culler::nextBatch()'s queries, as DepthSource::beginAccess() and
  // endAccess() do its reads; endAccess() returns the window's first error (by default
  // takeError()).
  virtual void beginAccess() {}
  virtual Status endAccess() { return takeError(); }

  // A call below that fails (a renderer error, a handle that is not in flight) answers
  // "visible" (ready() true, result() the largest count) and keeps its error (fail())
  // until takeError(), as a depth source's requests do (depth_source.hpp).

  // Issues one query over `count` >= 1 boxes (see above).
  virtual QueryHandle issueBoxes(const QueryBox* boxes, std::size_t count) = 0;
  // Issues one query over `count` >= 1 rectangles (see above).
  virtual QueryHandle issueRects(const RectQuery* rects, std::size_t count) = 0;
  // Does result(handle) return without waiting? May make the renderer start pending work.
  virtual bool ready(QueryHandle handle) = 0;
  // The count, waiting for it if needed. Releases the handle.
  virtual std::uint32_t result(QueryHandle handle) = 0;

  const QueryCounters& queryCounters() const { return query_counters_; }
  // The first error of a call since the last takeError(), and clears it (ok if none).
  Status takeError() { return failure_.take(); }

 protected:
  void fail(Status error) { failure_.note(std::move(error)); }

  QueryCounters query_counters_;
  FirstError failure_;
};

}  // namespace logrid
