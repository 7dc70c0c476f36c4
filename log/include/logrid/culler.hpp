// The culler: walks a Hierarchy front to back for one camera, tests each box with the
// method CullerDesc::method names (method.hpp), and hands the objects of every potentially
// visible node to the application to draw, in batches.
//
// Typical use, once per frame, in either form:
//
//   glClear(GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT);      // the frame starts cleared
//   // pull: the application draws each batch as it likes (one multi-draw, a command list)
//   culler.beginFrame(camera, hierarchy, {&depth_source});
//   for (logrid::DrawBatch b = culler.nextBatch(); !b.empty(); b = culler.nextBatch())
//     drawObjects(b.begin(), b.end());                        // with the depth test
//   logrid::FrameStats stats = culler.endFrame();
//   // callback: the same loop inside one call
//   logrid::FrameStats stats = culler.cullFrame(camera, hierarchy, depth_source,
//       [&](logrid::ObjectId id) { drawObject(id); });
//
// A batch holds what can be drawn before the next depth read or query needs it drawn:
// the reads happen inside nextBatch(), so an application that records its draws (command
// lists, a render graph, several threads) submits each batch before asking for the next.
// A read that none of the batch's objects can reach (their boxes' rectangles on screen)
// does not need it drawn: the test reads at once what it would read after the draw, and
// the batch may grow. A test that must also read where the batch draws reads the rest
// first, and a box shown there joins the batch. Queries always wait for it.
//
// What a method reads, queries or draws first comes in one CullSources (its MethodInfo::
// needs says which it must be given): a DepthSource for the methods that read the depth
// buffer, OcclusionQueries for the hardware-query methods (a GL application passes a
// zread::BoxQuerySource), an OccluderSource for the occluder pre-pass of ddo and ddo+log.
//
//   stats = culler.cullFrame(camera, hierarchy, {&depth, &queries}, draw);   // log+hwq
//
// Contract for the frame: the depth buffer is cleared before it begins (or what was drawn
// into it before is announced in `drawn_before`), and everything drawn during it is what
// the batches hand out, drawn with a depth test that keeps the nearer fragment
// (GL_LESS/LEQUAL standard, GL_GREATER/GEQUAL reversed) and depth writes on. Anything
// else drawn during the frame is announced with noteDrawn(), and a depth clear with
// noteDepthCleared() (from the callback, or between batches).
//
// Traversals (MethodInfo::traversal; LOG §3, §4):
//   * two-list, for methods with occlusion-state semantics (MethodInfo::semantics):
//     a test-list ordered by nearest key and a draw-list ordered by farthest key; a
//     visible node's objects are drawn only once they lie in front of every box still to
//     be tested, so that "every pixel holds something" means "hidden". A box for which
//     the order cannot vouch (something of unknown or greater depth was drawn over the
//     box's pixel rectangle: drawn_before, noteDrawn, temporal coherence, occluders drawn
//     first; or anywhere: a mid-frame clear to a nearer value) is tested by depth instead,
//     as the zfar variant tests every box (FrameStats::order_fallbacks). Areas drawn out
//     of order are judged by their rectangles, up to 256 a frame; beyond that, for every
//     box.
//   * approximate front to back: the test-list only; visible objects are drawn at once.
//   * a hardware-query schedule (hwq, chc, stat, nohc, log+hwq): each walks the hierarchy
//     in its own order (log/src/query_*.cpp, settings in CullerDesc::queries) and draws
//     what it finds visible at once; it keeps what it learns about each node across
//     frames and forgets it when the hierarchy object or its revision() changes.
// View-frustum culling is hierarchical: an outside node's children are never visited.
//
// Lookahead (CullerDesc::lookahead = K, MethodTakes::lookahead): with K = 1 each box is
// tested on its own, in the paper's order (the grid reads one tile at a time and stops at
// the first visible one). With K > 1 the boxes whose tiles the records cannot decide are
// set aside, up to K of them, while the traversal goes on with what the records decide
// and draws what is known visible; then one batch reads every tile they need
// (DepthSource::submit, one collect) and they are decided. The renderer is then waited
// for once per batch, not once per tile. Every K is exact; K = 1 gives the answers and
// reads of the paper's order. CullerDesc::detect_colliding keeps boxes that overlap on
// screen out of one batch.
//
// Temporal coherence (CullerDesc::temporal_coherence, MethodTakes::temporal_coherence):
// the nodes with objects found visible last frame are drawn first, without tests, the
// grid's outdated tiles are refreshed in one batch, and then the hierarchy is traversed as
// usual; a node drawn first is not drawn again. Conservative by construction: whatever
// was not drawn first is tested against this frame's depth. The culler remembers nodes by NodeId,
// and forgets them when the hierarchy object or its revision() changes.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/costs.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/error.hpp"
#include "logrid/grid_settings.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/method.hpp"
#include "logrid/occluder_source.hpp"
#include "logrid/occlusion_queries.hpp"
#include "logrid/projection.hpp"
#include "logrid/query_schedule.hpp"
#include "logrid/stats.hpp"

namespace logrid {

// CullerDesc::lookahead value: gather every box the traversal reaches before it must wait.
inline constexpr std::uint32_t kUnlimitedLookahead = std::numeric_limits<std::uint32_t>::max();

// What the culler times its frames by, for what it learns from them: the online cost
// estimate (Culler::costEstimate), auto's choices and a frame-time budget.
enum class FrameClock {
  CulledPass,     // beginFrame() to endFrame(), FrameStats::seconds
  ReportedFrame,  // the whole frame, as the application reports it (Culler::reportFrameTime)
};

struct CullerDesc {
  Method method = Method::LogState;
  std::uint32_t tile_size = 32;  // pixels per tile side (LOG §5 uses 32)
  ProjectionSettings projection;

  // Speed for accuracy (grid.hpp, GridApproximation). Off by default. What each knob
  // gives up, measured on the forest and the city, is in docs/TRADEOFF.md:
  //   visible_pixels      boxes showing at most N pixels are culled: objects whose
  //                       visible part is that small vanish (log-*, bog, pq; with the
  //                       query reader the count comes from GL_SAMPLES_PASSED);
  //   full_free_fraction  tiles with at most this fraction of free pixels count as full:
  //                       objects seen only through such gaps vanish (log-state, bog);
  //   row_stride          reads sample every k-th row: objects seen only through rows
  //                       that were skipped vanish (log-*, bog).
  // Knobs combine: with visible_pixels and full_free_fraction together, tiles counted
  // as full contribute no pixels to the visible-pixel count. Which method takes which
  // knob is in its MethodInfo::takes.
  GridApproximation approximation;

  // Boxes whose undecided tiles are read in one batch: 1 (the paper's order, one box at
  // a time) up to kUnlimitedLookahead. Methods that do not take it (MethodTakes), and
  // counting tests (approximation.visible_pixels with a grid), test one box at a time.
  std::uint32_t lookahead = 1;
  // Draw last frame's visible nodes with objects first, then refresh the grid in one batch (methods
  // that take it, MethodTakes).
  bool temporal_coherence = false;
  // Detection of colliding queries (ternary-tree paper, §3.5): with lookahead > 1, a box
  // whose pixel rectangle overlaps that of a box already set aside for the batch is not
  // added to it; the batch is resolved first (and its visible nodes drawn or queued), so
  // that what the nearer box holds can hide the farther one, which is then tested
  // again. Fewer boxes found visible for more, smaller batches. Exact either way.
  bool detect_colliding = false;

  // The hardware-query methods' settings (query_schedule.hpp); nohc needs measured
  // hardware parameters (zread::calibrateQueries).
  QueryScheduleDesc queries = {};

  // A frame-time budget in milliseconds (what it times: frame_clock), 0: none, the culler
  // stays as exact as `approximation` says. With a budget the culler sets the approximate
  // knobs itself, frame by frame: when its frames run over the budget it moves along the
  // measured Pareto front of the knobs the method takes at its setting (without temporal
  // coherence the full-tile free fraction 0.01 to 0.25, then visible pixels 256; with it
  // visible pixels 16 to 256: docs/TRADEOFF.md), and back to exact when there is time,
  // with hysteresis (docs/BUDGET.md). FrameStats::setting records what each frame ran.
  // Needs a grid method that takes those knobs (log-state, log-zfar, bog, ddo+log) and
  // `approximation` left exact.
  double budget_ms = 0;
  // The culled pass by default: its time misses what the renderer does after endFrame()
  // (on a deferred renderer such as llvmpipe, much of the drawing, done at the finish).
  // An application that presents the frame knows its whole time (clear, the culled pass,
  // its other drawing, the finish or swap), which is what its user sees: with
  // ReportedFrame the culler learns from the times it passes to reportFrameTime() instead.
  FrameClock frame_clock = FrameClock::CulledPass;

  // The cost model's starting point (costs.hpp): measured on this machine for the depth
  // source used (loadCullerCosts on a file of `logrid calibrate --costs`), or the
  // defaults. Every culler refines it online (Culler::costEstimate); `auto` chooses with it.
  CullerCosts costs = {};
};

// Returns an empty string if the descriptor is usable, else a message naming the field.
std::string validateCullerDesc(const CullerDesc& desc);

// The hardware-query schedule a culler with `desc` runs: the method's own (hwq, chc, stat,
// nohc), CullerDesc::queries.schedule for log+hwq, nothing for the other methods.
std::optional<QuerySchedule> querySchedule(const CullerDesc& desc);

using DrawCallback = std::function<void(ObjectId)>;

// What a method reads, queries and draws first (MethodInfo::needs says which it needs;
// the others may be null and are not used).
struct CullSources {
  DepthSource* depth = nullptr;         // the application's depth buffer
  OcclusionQueries* queries = nullptr;  // hardware occlusion queries
  OccluderSource* occluders = nullptr;  // the occluder pre-pass (ddo, ddo+log)
};

// Optional hooks for overlays and debugging; called synchronously during cullFrame().
class CullObserver {
 public:
  virtual ~CullObserver() = default;
  virtual void onTested(NodeId, const BoxProjection&, Visibility) {}
  virtual void onDrawn(NodeId, const BoxProjection&) {}
};

class OcclusionGrid;  // grid.hpp: the grid's internals, for overlays (Culler::grid())

namespace detail {
struct MethodDef;
class AutoPolicy;
class BudgetController;
class BoxTester;
class Schedule;
class GridPrefilter;
class QueryFrame;
}  // namespace detail

// The objects of one batch of the pull form (Culler::nextBatch), in the order the
// traversal handed them out. Valid until the next nextBatch() or endFrame().
class DrawBatch {
 public:
  DrawBatch() = default;
  DrawBatch(const ObjectId* first, std::size_t count) : first_(first), count_(count) {}
  const ObjectId* begin() const { return first_; }
  const ObjectId* end() const { return first_ + count_; }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  ObjectId operator[](std::size_t i) const { return first_[i]; }

 private:
  const ObjectId* first_ = nullptr;
  std::size_t count_ = 0;
};

class Culler {
 public:
  // Every call that can fail comes in two forms (error.hpp): the result form (create(),
  // tryX()) returns a Status or a Result; the throwing form (the constructor, X())
  // throws logrid::Error with the same code and message, where exceptions are enabled.
  //
  // The culler for `desc`, or validateCullerDesc()'s problem (InvalidArgument).
  static Result<Culler> create(const CullerDesc& desc = {});
  explicit Culler(const CullerDesc& desc = {});
  ~Culler();
  Culler(Culler&&) noexcept;
  Culler& operator=(Culler&&) noexcept;

  const CullerDesc& desc() const { return desc_; }

  // ---- The pull form: the application draws each batch however it likes. ----
  //
  //   culler.beginFrame(camera, hierarchy, sources);
  //   for (logrid::DrawBatch batch = culler.nextBatch(); !batch.empty();
  //        batch = culler.nextBatch())
  //     for (logrid::ObjectId id : batch) drawObject(id);   // or one multi-draw, or threads
  //   logrid::FrameStats stats = culler.endFrame();
  //
  // beginFrame() starts a frame (the same contract as cullFrame's, below). nextBatch()
  // runs the traversal until it has objects to draw and a depth read or query needs them
  // drawn first, or until the frame is done, and returns those objects (empty: done).
  // Asking for the next batch says the last one is drawn: every object of it, with the
  // depth test that keeps the nearer fragment and depth writes on, by any number of draw
  // calls, in any order, from any thread the application synchronises before asking. The
  // depth reads and queries of the frame happen inside nextBatch(), never between.
  // Between batches the application may announce what else it drew (noteDrawn()) and a
  // depth clear (noteDepthCleared()). `hierarchy` and the sources must live until
  // endFrame(). They fail as cullFrame() does; an error ends the frame (nothing of it is
  // left to draw, and the next beginFrame() starts afresh).
  Status tryBeginFrame(const Camera& camera, const Hierarchy& hierarchy, const CullSources& sources,
                       const std::vector<DrawnArea>& drawn_before = {});
  Result<DrawBatch> tryNextBatch();
  // Ends the frame once nextBatch() returned an empty batch, and returns what it did
  // (FrameStats::seconds: from beginFrame() to here, the application's drawing included).
  // Fails (and abandons the frame) if the traversal is not done.
  Result<FrameStats> tryEndFrame();
  void beginFrame(const Camera& camera, const Hierarchy& hierarchy, const CullSources& sources,
                  const std::vector<DrawnArea>& drawn_before = {});
  DrawBatch nextBatch();
  FrameStats endFrame();
  // Ends a frame early (the application gave up on it, e.g. after an error of its own):
  // what was not handed out is not drawn, and the next beginFrame() starts afresh. Does
  // nothing outside a frame.
  void abandonFrame();

  // ---- The callback form: one call, a loop over the pull form. ----
  //
  // Culls and draws one frame: `draw` is called for each object of each batch, in order.
  // `drawn_before`: what the application drew into the depth buffer after clearing it
  // and before this call (e.g. occluders drawn first); the grid starts with those tiles
  // outdated. Fails (InvalidArgument) for an invalid camera (validateCamera), a source the
  // method needs but was not given (MethodInfo::needs), a depth source that cannot serve
  // the camera or does not read the depth values the method needs, and with a source's
  // own error (a renderer error: Runtime); boxes with NaN or inverted bounds are drawn
  // and counted in FrameStats::invalid_boxes. An exception thrown by `draw` abandons the
  // frame and leaves cullFrame().
  Result<FrameStats> tryCullFrame(const Camera& camera, const Hierarchy& hierarchy,
                                  const CullSources& sources, const DrawCallback& draw,
                                  const std::vector<DrawnArea>& drawn_before = {});
  FrameStats cullFrame(const Camera& camera, const Hierarchy& hierarchy, const CullSources& sources,
                       const DrawCallback& draw, const std::vector<DrawnArea>& drawn_before = {});
  // The same for the methods that need a depth source and nothing else.
  FrameStats cullFrame(const Camera& camera, const Hierarchy& hierarchy, DepthSource& depth,
                       const DrawCallback& draw, const std::vector<DrawnArea>& drawn_before = {});

  // During a frame (from the draw callback, or between batches of the pull form; outside
  // a frame they fail with InvalidArgument): the application drew something more than the
  // culler's objects, over `area` (e.g. a decal or a particle beside them), or over the
  // pixels of a world-space box.
  Status tryNoteDrawn(const DrawnArea& area);
  Status tryNoteDrawn(const Aabb& box);
  void noteDrawn(const DrawnArea& area);
  void noteDrawn(const Aabb& box);
  // ... or it cleared the depth buffer: to the convention's clear value, or to another
  // window depth (as glClearDepth takes it; outside [0, 1] fails). A clear in the middle
  // of a batch is safe: what the batch holds counts as drawn after it.
  Status tryNoteDepthCleared();
  Status tryNoteDepthCleared(float window_depth);
  void noteDepthCleared();
  void noteDepthCleared(float window_depth);

  // The projection of a world-space box for this frame's camera (during a frame; outside
  // one it fails with InvalidArgument).
  Result<BoxProjection> tryProject(const Aabb& box) const;
  BoxProjection project(const Aabb& box) const;

  // The grid of the last frame (nullptr for methods without one), for overlays.
  const OcclusionGrid* grid() const;
  void setObserver(CullObserver* observer) { observer_ = observer; }
  // Forget the nodes remembered for temporal coherence, and what the query methods
  // remember of each node.
  void forgetCoherence();

  // The whole time of the frame that ended last, as the application measured it, for
  // CullerDesc::frame_clock = ReportedFrame (ignored with CulledPass); call it once after
  // endFrame() and before the next beginFrame(). A frame not reported by then is taken
  // at its culled pass's time. Fails (InvalidArgument) for a time that is negative or not
  // finite, and with ReportedFrame for a frame reported twice or none ended.
  Status tryReportFrameTime(double seconds);
  void reportFrameTime(double seconds);

  // The online cost estimate (costs.hpp), from CullerDesc::costs and every frame ended.
  const CostEstimate& costEstimate() const { return estimate_; }

 private:
  struct Entry {
    float order;  // test-list: nearest key - margin; draw-list: farthest key + margin
    NodeId node;
    BoxProjection projection;
    bool by_state = false;  // pending: planned with the occlusion-state threshold
  };
  // Where the frame's traversal stands between two batches.
  enum class Phase : std::uint8_t { Coherent, CoherentRefresh, Traverse, Schedule, Done };
  struct Checked {};  // the desc was validated
  Culler(Checked, const CullerDesc& desc);
  // beginFrame's steps up to the sources' frames: the method's checks, the projector, the
  // tester.
  Status prepare(const Camera& camera, const CullSources& sources);
  // Abandons the frame, and returns the error that ended it.
  Status failFrame(Status status);
  // beginFrame's further steps: the depth source's and the queries' frames begun (their
  // counters taken), the last frame's lists and counts cleared, the occluder pre-pass,
  // and for Traversal::Schedule the schedule's frame wired and begun.
  Status beginSourceFrames(const Camera& camera);
  void clearFrameState();
  Status beginOccluders(const Camera& camera);
  void beginSchedule(const Hierarchy& hierarchy);
  // Runs the frame until the batch must be drawn before going on, or the frame is done.
  void advance();
  // The approximate knobs this frame runs with: the budget's rung, or CullerDesc's.
  const GridApproximation& frameApproximation() const;
  // What the culler learns from a frame (cost estimate, auto, budget), with its time.
  void learnFrom(const FrameStats& frame);
  // Two-list or approximate front to back, with lookahead: true when done, false when
  // the batch must be drawn first.
  bool traverse();
  // traverse()'s steps, each one turn of its loop. testHeld: the box held for its test
  // (lookahead 1) tested, unless the test may read what the undrawn batch covers (false).
  // drawFrontmost: the frontmost visible node drawn if two-list order allows (true).
  // visitNext: the test-list's frontmost node decided without a test, held for its test,
  // planned from the records (planTest, lookahead > 1), or put back to wait for
  // colliding boxes (waitsForColliding). untestedByCost: auto found a test not worth its
  // cost (true: visible, untested). Inline, defined in culler.cpp only: the per-node path
  // stays one function, as fast as before it was split.
  inline bool testHeld();
  inline bool drawFrontmost();
  inline void visitNext();
  inline bool untestedByCost(const Entry& entry);
  inline bool waitsForColliding(const Entry& entry);
  inline void planTest(const Entry& entry);
  // Work that waits for the batch to be drawn (busy refreshes); false if it still waits.
  bool afterBatchDrawn();
  // Projects the children of `node` and puts those in view on the test-list.
  void pushChildren(NodeId node);
  void pushTest(NodeId node, const BoxProjection& projection);
  // Decides what needs no occlusion test (view culled, invalid, crossing the near
  // plane, no occlusion test for this method); nothing if the box must be tested.
  bool forced(const Entry& entry, Visibility& result);
  bool collidesWithPending(const PixelRect& rect) const;
  // Does everything drawn so far lie in front of the box (occlusion-state semantics)?
  bool orderVouches(const Entry& entry) const;
  // The box's test threshold: the clear key where the order vouches (`by_state`), else
  // its nearest key minus its margin.
  float thresholdFor(const Entry& entry, bool& by_state) const;
  void countFallback(bool by_state);  // FrameStats::order_fallbacks
  // A test's answer: counted, and an occluded box remembered while the batch is undrawn.
  // `evidence`: the answer came from a read, or is occluded from the records (what auto
  // learns P(occluded) from).
  void decided(const Entry& entry, Visibility v, bool evidence);
  void finish(const Entry& entry, Visibility v);
  void resolvePending();
  // The node's objects into this batch, counted as drawn (objects, triangles, leaves).
  void batchObjects(NodeId node);
  void drawEntry(const Entry& entry);
  void drawCoherent();
  // How many of this frame's visible nodes with objects last frame found visible too.
  std::uint64_t countKept();
  // `ordered`: drawn in two-list order (in front of every box still to be tested, up to
  // rounding); else remembered in unordered_. `batched`: drawn with the batch the culler
  // hands out next, so its sources learn of the draw then (handOutBatch()); else drawn.
  void noteDrawnWith(const DrawnArea& area, bool ordered, bool batched = false);
  // The batch is handed out to be drawn: the sources' next read or query waits for it.
  void handOutBatch();
  // An error (InvalidArgument, naming `who`) unless called during a frame.
  Status requireFrame(const char* who) const;

  // For `auto`: this frame's setting chosen, with the method (log-state or log-zfar)
  // and tester it runs.
  void chooseSetting(const Hierarchy& hierarchy);

  CullerDesc desc_;
  const detail::MethodDef* method_;  // what the frame runs (auto: the method it chose)
  std::unique_ptr<detail::BoxTester> tester_;
  std::unique_ptr<detail::AutoPolicy> auto_;          // `auto` only
  std::unique_ptr<detail::BudgetController> budget_;  // CullerDesc::budget_ms > 0 only
  // FrameClock::ReportedFrame: the frame that ended, until its time is reported.
  std::optional<FrameStats> unreported_;
  std::unique_ptr<detail::BoxTester> other_tester_;  // auto: the other grid variant's
  CostEstimate estimate_;
  std::unique_ptr<Projector> projector_;
  CullObserver* observer_ = nullptr;

  // This frame's (from beginFrame() to endFrame()).
  bool in_frame_ = false;
  Phase phase_ = Phase::Done;
  const Hierarchy* hierarchy_ = nullptr;
  CullSources sources_;
  std::chrono::steady_clock::time_point start_;
  ReadCounters depth_before_;
  QueryCounters queries_before_;
  bool coherence_ = false;
  bool record_visible_ = false;  // the visible nodes with objects are kept for the next frame
  FrameSetting setting_;         // this frame's
  FrameStats stats_;
  GridTestCounts grid_counts_;
  std::vector<ObjectId> batch_;  // handed out by the last nextBatch()
  struct BatchArea {
    DrawnArea area;
    bool ordered;
  };
  std::vector<BatchArea> batch_areas_;  // the batch's nodes, noted again after a clear
  // Where the batch may draw, clipped to the viewport: a test or a batch of reads that
  // reads none of it need not wait for the batch to be drawn.
  std::vector<PixelRect> batch_rects_;
  std::vector<PixelRect> after_draw_;  // drawn; the tester reads them once drawn (busy)
  float drawn_back_ = 0;  // farthest key + margin of what was drawn in order so far this
                          // frame (and of unordered areas beyond kMaxUnorderedAreas)
  std::vector<DrawnArea> unordered_;       // drawn out of order this frame (clipped rects)
  std::vector<DrawnArea> occluder_areas_;  // this frame's occluders drawn first
  std::uint32_t lookahead_ = 1;            // this frame's
  std::vector<Entry> test_list_;
  std::vector<Entry> draw_list_;
  // pushChildren()'s scratch: a node's children, their boxes and projections.
  std::vector<NodeId> child_ids_;
  std::vector<Aabb> child_boxes_;
  std::vector<BoxProjection> child_projections_;
  std::vector<Entry> pending_;         // set aside for the next batch, in test-list order
  std::vector<Entry> deferred_;        // visible by the records behind pending_: test again
  std::optional<Entry> testing_;       // taken off the test-list, its test may need the batch
  std::vector<Entry> culled_undrawn_;  // found occluded while the batch waits to be drawn
  bool resolve_due_ = false;           // pending_ is to be read and resolved
  // Temporal coherence: last frame's visible nodes with objects, for which hierarchy.
  std::vector<NodeId> coherent_;
  std::vector<NodeId> visible_drawn_;  // this frame's
  std::vector<NodeId> drawn_first_;    // sorted: nodes drawn from coherent_
  std::vector<NodeId> kept_scratch_;   // countKept()'s sorted copy of coherent_
  const Hierarchy* coherent_hierarchy_ = nullptr;
  std::uint64_t coherent_revision_ = 0;
  // Query methods: the schedule and its frame count, for which hierarchy; mid-frame
  // depth clears (answers issued before one no longer hold).
  std::unique_ptr<detail::Schedule> schedule_;
  std::unique_ptr<detail::GridPrefilter> prefilter_;  // log+hwq, this frame's
  std::unique_ptr<detail::QueryFrame> query_frame_;   // this frame's
  std::uint32_t schedule_frame_ = 0;
  const Hierarchy* schedule_hierarchy_ = nullptr;
  std::uint64_t schedule_revision_ = 0;
  std::uint64_t clear_epoch_ = 0;
};

inline Result<FrameStats> Culler::tryCullFrame(const Camera& camera, const Hierarchy& hierarchy,
                                               const CullSources& sources, const DrawCallback& draw,
                                               const std::vector<DrawnArea>& drawn_before) {
  if (Status begun = tryBeginFrame(camera, hierarchy, sources, drawn_before); !begun) return begun;
  // Abandons the frame if `draw` throws (after endFrame() it does nothing).
  struct Abandon {
    Culler& culler;
    ~Abandon() { culler.abandonFrame(); }
  } abandon{*this};
  for (;;) {
    Result<DrawBatch> batch = tryNextBatch();
    if (!batch) return batch.status();
    if (batch->empty()) return tryEndFrame();
    for (ObjectId id : *batch) draw(id);
  }
}

#if LOGRID_HAS_EXCEPTIONS
inline Culler::Culler(const CullerDesc& desc) : Culler(orThrow(create(desc))) {}
inline void Culler::beginFrame(const Camera& camera, const Hierarchy& hierarchy,
                               const CullSources& sources,
                               const std::vector<DrawnArea>& drawn_before) {
  orThrow(tryBeginFrame(camera, hierarchy, sources, drawn_before));
}
inline DrawBatch Culler::nextBatch() { return orThrow(tryNextBatch()); }
inline FrameStats Culler::endFrame() { return orThrow(tryEndFrame()); }
inline FrameStats Culler::cullFrame(const Camera& camera, const Hierarchy& hierarchy,
                                    const CullSources& sources, const DrawCallback& draw,
                                    const std::vector<DrawnArea>& drawn_before) {
  return orThrow(tryCullFrame(camera, hierarchy, sources, draw, drawn_before));
}
inline FrameStats Culler::cullFrame(const Camera& camera, const Hierarchy& hierarchy,
                                    DepthSource& depth, const DrawCallback& draw,
                                    const std::vector<DrawnArea>& drawn_before) {
  return cullFrame(camera, hierarchy, CullSources{&depth}, draw, drawn_before);
}
inline void Culler::noteDrawn(const DrawnArea& area) { orThrow(tryNoteDrawn(area)); }
inline void Culler::noteDrawn(const Aabb& box) { orThrow(tryNoteDrawn(box)); }
inline void Culler::noteDepthCleared() { orThrow(tryNoteDepthCleared()); }
inline void Culler::noteDepthCleared(float window_depth) {
  orThrow(tryNoteDepthCleared(window_depth));
}
inline void Culler::reportFrameTime(double seconds) { orThrow(tryReportFrameTime(seconds)); }
inline BoxProjection Culler::project(const Aabb& box) const { return orThrow(tryProject(box)); }
#endif

}  // namespace logrid
