// What one culled frame did. Every method fills the same fields, so methods compare
// side by side (docs/DESIGN.md, "Statistics").
#pragma once

#include <cstdint>

#include "logrid/grid_settings.hpp"
#include "logrid/method.hpp"

namespace logrid {

// The setting a frame was culled with (FrameStats::setting). For `auto`, its choice.
struct FrameSetting {
  Method method = Method::LogState;  // auto: the grid method it ran (log-state, log-zfar)
  std::uint32_t lookahead = 1;       // K the traversal batched with
  bool temporal_coherence = false;
  bool probe = false;  // auto: a frame that tried a neighbouring setting (docs/AUTO.md)
  // The approximate knobs the frame ran with: CullerDesc::approximation, or what the
  // frame-time budget chose (CullerDesc::budget_ms).
  GridApproximation approximation;
};

// What the grid's tests examined and read (added to, never reset, by the grid's test(),
// decide() and plan()); FrameStats::tiles_tested and tiles_read are a frame's.
struct GridTestCounts {
  std::uint64_t tiles_tested = 0;  // tiles whose record or pixels decided something
  std::uint64_t tiles_read = 0;    // tiles (or tile intersections) read from the source
};

struct FrameStats {
  // Traversal.
  std::uint64_t nodes_visited = 0;      // nodes taken from the test-list
  std::uint64_t boxes_tested = 0;       // occlusion tests run (grid, pyramid or query)
  std::uint64_t boxes_occluded = 0;     // tests that answered occluded (subtree culled)
  std::uint64_t boxes_view_culled = 0;  // outside the frustum or covering no pixel centre
  std::uint64_t boxes_near = 0;         // crossing the near plane: visible without a test
  std::uint64_t invalid_boxes = 0;      // NaN, infinite or inverted: visible and counted
  std::uint64_t nodes_opened = 0;       // inner nodes the records could not decide, opened
                                        // (children tested) instead of read (lookahead > 1)
  std::uint64_t order_fallbacks = 0;    // occlusion-state tests the two-list order could
                                        // not vouch for, done by depth instead
  std::uint64_t colliding_waits = 0;    // boxes kept out of a batch because their rectangle
                                        // overlaps one in it (CullerDesc::detect_colliding)
  std::uint64_t boxes_untested = 0;     // auto: drawn (or opened) without a test, which
                                        // was not expected to pay (docs/AUTO.md)
  std::uint64_t tiles_tested = 0;       // tiles (HZB: pyramid cells) examined by tests
  std::uint64_t tiles_read = 0;         // tiles whose pixels a test or refresh read

  // Depth source (differences of its counters over the frame).
  std::uint64_t reads = 0;          // pixel reads issued
  std::uint64_t pixels_read = 0;    // pixels read from the depth buffer
  std::uint64_t bytes_read = 0;     // bytes that crossed from the renderer
  std::uint64_t batches = 0;        // batches of requests submitted to the source
  std::uint64_t queries = 0;        // hardware occlusion queries issued (by a source or a schedule)
  std::uint64_t flushes = 0;        // times a read or query made the renderer start or finish work
  std::uint64_t state_queries = 0;  // renderer-state queries of the sources (a GL source's
                                    // glGet* and glGetError, keeping the application's state)

  // Query schedules (hwq, chc, stat, nohc, log+hwq; differences of OcclusionQueries'
  // counters, and the schedules' own counts).
  std::uint64_t query_waits = 0;      // query answers waited for (not there when asked)
  std::uint64_t query_polls = 0;      // availability polls
  std::uint64_t query_boxes = 0;      // boxes drawn by queries (a multi-query draws several)
  std::uint64_t multi_queries = 0;    // chc: queries over more than one node
  std::uint64_t records_decided = 0;  // log+hwq: tests the grid's records answered without a query
  double read_seconds = 0;            // wall time inside the depth source

  // Drawing.
  std::uint64_t leaves_drawn = 0;     // nodes whose objects were drawn
  std::uint64_t objects_drawn = 0;    // draw callbacks made
  std::uint64_t coherent_leaves = 0;  // nodes with objects drawn first from last frame's set
  std::uint64_t visible_leaves = 0;   // nodes with objects found visible (recorded where
                                      // the culler keeps its visible set: temporal
                                      // coherence, auto)
  std::uint64_t visible_kept = 0;     // of those, the ones last frame found visible too
                                      // (0 on a first frame or a changed hierarchy)
  std::uint64_t draw_batches = 0;     // non-empty batches handed out (Culler::nextBatch)
  std::uint64_t occluders = 0;        // selected by the occluder pre-pass (ddo: faces in
                                      // its map; ddo+log: quads recorded)
  std::uint64_t occluder_tiles = 0;   // ddo+log: grid tiles the occluders' known coverage
                                      // hid as a whole, without a read or a draw
  std::uint64_t triangles_drawn = 0;  // of the objects drawn (Hierarchy::objectTriangles;
                                      // 0 where the hierarchy does not know them)
  double seconds = 0;                 // wall time of the whole cullFrame(), draws included

  // The exact setting the frame ran with: the method's, or the one `auto` chose.
  FrameSetting setting;

  double tilesPerBox() const {
    return boxes_tested ? double(tiles_tested) / double(boxes_tested) : 0.0;
  }
};

}  // namespace logrid
