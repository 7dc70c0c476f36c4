#include "logrid/culler.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

#include "auto_policy.hpp"
#include "budget.hpp"
#include "logrid/coverage.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"
#include "methods/method_def.hpp"
#include "query_frame.hpp"
#include "query_prefilter.hpp"
#include "testers.hpp"

namespace logrid {

std::string validateCullerDesc(const CullerDesc& desc) {
  if (!parseMethod(toString(desc.method))) {
    return "culler: method " + std::to_string(int(desc.method)) + " is unknown; use " +
           methodNames();
  }
  const detail::MethodDef& def = detail::methodDef(desc.method);
  const MethodInfo& info = def.info;
  const std::string method = info.name;
  const std::string projection = validateProjectionSettings(desc.projection);
  if (!projection.empty()) return "culler: " + projection;
  if (desc.tile_size < 1) {
    std::ostringstream out;
    out << "culler: tile size " << desc.tile_size << " is invalid; use 1 pixel or more";
    return out.str();
  }
  if (desc.lookahead < 1) {
    return "culler: lookahead 0 is invalid; use 1 (one box at a time) or more "
           "(kUnlimitedLookahead: every box the traversal reaches)";
  }
  const GridApproximation& a = desc.approximation;
  if (a.visible_pixels != 0 && !info.takes.visible_pixels) {
    return "culler: method " + method + " takes no visible-pixel threshold";
  }
  if (a.full_free_fraction != 0 && !info.takes.full_fraction) {
    return "culler: method " + method + " takes no full-tile free fraction";
  }
  if (a.row_stride != 1 && !info.takes.row_stride) {
    return "culler: method " + method + " takes no row stride (it has no tiles)";
  }
  if (info.grid) {
    // The grid's own checks, with a viewport that is always valid.
    const std::string problem = validateGridDesc({1, 1, desc.tile_size, *info.grid}, a);
    if (!problem.empty()) return "culler: " + problem;
  }
  if (def.validate) {
    const std::string problem = def.validate(desc, info);
    if (!problem.empty()) return "culler: method " + method + ": " + problem;
  }
  if (!(std::isfinite(desc.budget_ms) && desc.budget_ms >= 0 && desc.budget_ms <= 1e6)) {
    std::ostringstream out;
    out << "culler: budget " << desc.budget_ms
        << " ms is invalid; use 0 (none) or a frame time in (0, 1000000] ms";
    return out.str();
  }
  if (desc.budget_ms > 0 &&
      detail::budgetLadder(info, desc.temporal_coherence && info.takes.temporal_coherence)
          .empty()) {
    return "culler: method " + method +
           " cannot meet a frame-time budget: the budget moves along a grid's full-tile free "
           "fraction or visible pixels, which it does not take; use log-state, log-zfar, bog "
           "or ddo+log, or no budget";
  }
  if (desc.frame_clock != FrameClock::CulledPass && desc.frame_clock != FrameClock::ReportedFrame) {
    return "culler: frame_clock " + std::to_string(int(desc.frame_clock)) +
           " is not a FrameClock; use CulledPass or ReportedFrame";
  }
  if (desc.budget_ms > 0 && !a.exact()) {
    return "culler: with a frame-time budget the culler sets the approximate knobs itself; "
           "leave CullerDesc::approximation exact";
  }
  const std::string costs = validateCullerCosts(desc.costs);
  if (!costs.empty()) return "culler: " + costs;
  return {};
}

Result<Culler> Culler::create(const CullerDesc& desc) {
  std::string problem = validateCullerDesc(desc);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  return Culler(Checked{}, desc);
}

Culler::Culler(Checked, const CullerDesc& desc) : desc_(desc), estimate_(desc.costs) {
  method_ = &detail::methodDef(desc_.method);
  if (desc_.method == Method::Auto) {
    // auto runs log-state or log-zfar, one grid tester each (exact: no approximation).
    auto_ = std::make_unique<detail::AutoPolicy>();
    method_ = &detail::methodDef(auto_->current().method);
    const Method other =
        auto_->current().method == Method::LogState ? Method::LogZfar : Method::LogState;
    other_tester_ = detail::makeGridTester(desc_, *detail::methodDef(other).info.grid,
                                           detail::GridRefresh::Lazy);
  }
  if (desc_.budget_ms > 0) {
    const MethodInfo& info = method_->info;
    budget_ = std::make_unique<detail::BudgetController>(
        desc_.budget_ms * 1e-3,
        detail::budgetLadder(info, desc_.temporal_coherence && info.takes.temporal_coherence));
  }
  tester_ = method_->make_tester(desc_, method_->info);
  if (method_->make_schedule) schedule_ = method_->make_schedule(desc_, method_->info);
}

void Culler::chooseSetting(const Hierarchy& hierarchy) {
  setting_ = auto_->beginFrame(hierarchy);
  if (setting_.method != method_->info.method) {
    method_ = &detail::methodDef(setting_.method);
    std::swap(tester_, other_tester_);
  }
}

Culler::~Culler() = default;
Culler::Culler(Culler&&) noexcept = default;
Culler& Culler::operator=(Culler&&) noexcept = default;

const OcclusionGrid* Culler::grid() const { return tester_->grid(); }

namespace {

// Min-heaps on Entry::order: a function object, so that the heap operations inline it.
struct LaterFirst {
  template <typename E>
  bool operator()(const E& a, const E& b) const {
    return a.order > b.order;
  }
};

constexpr float kNothingDrawn = -std::numeric_limits<float>::infinity();

// Areas drawn out of order that occlusion-state tests check one by one (a few hundred
// occluders or coherent nodes); further ones count for every box.
constexpr std::size_t kMaxUnorderedAreas = 256;

// "culler: method M <what> ...; pass <how>" for a source the method needs.
Status require(bool given, const MethodInfo& info, const char* what, const char* how) {
  if (given) return {};
  return Status(ErrorCode::InvalidArgument, std::string("culler: method ") + info.name + " " +
                                                what + "; pass " + how +
                                                " in the frame's CullSources");
}

// Abandons the culler's frame when an exception leaves the scope it guards.
class AbandonOnThrow {
 public:
  explicit AbandonOnThrow(std::function<void()> abandon)
      : abandon_(std::move(abandon)), exceptions_(std::uncaught_exceptions()) {}
  ~AbandonOnThrow() {
    if (std::uncaught_exceptions() > exceptions_) abandon_();
  }
  AbandonOnThrow(const AbandonOnThrow&) = delete;
  AbandonOnThrow& operator=(const AbandonOnThrow&) = delete;

 private:
  std::function<void()> abandon_;
  int exceptions_;
};

// Brackets one nextBatch()'s requests with the sources' beginAccess() and endAccess().
class SourceAccess {
 public:
  explicit SourceAccess(const CullSources& sources)
      : depth_(sources.depth), queries_(sources.queries) {
    if (depth_) depth_->beginAccess();
    if (queries_) queries_->beginAccess();
  }
  // Ends both windows; the first error of their requests (the queries' first).
  Status end() {
    DepthSource* depth = std::exchange(depth_, nullptr);
    OcclusionQueries* queries = std::exchange(queries_, nullptr);
    Status status = queries ? queries->endAccess() : Status{};
    Status depth_status = depth ? depth->endAccess() : Status{};
    return status ? depth_status : status;
  }
  // An exception left nextBatch() (thrown by an application's hierarchy or source): the
  // windows end, and what they report is dropped for the exception.
  ~SourceAccess() {
    if (queries_) (void)queries_->endAccess();
    if (depth_) (void)depth_->endAccess();
  }
  SourceAccess(const SourceAccess&) = delete;
  SourceAccess& operator=(const SourceAccess&) = delete;

 private:
  DepthSource* depth_;
  OcclusionQueries* queries_;
};

}  // namespace

Status Culler::prepare(const Camera& camera, const CullSources& sources) {
  // The method as the application named it (auto's needs are those of what it runs).
  const MethodInfo& info = methodInfo(desc_.method);
  for (const Status& given : {require(!info.needs.queries || sources.queries, info,
                                      "tests boxes with hardware occlusion queries",
                                      "an OcclusionQueries (e.g. zread::BoxQuerySource)"),
                              require(!info.needs.depth || sources.depth, info,
                                      "reads the depth buffer", "a DepthSource"),
                              require(!info.needs.occluders || sources.occluders, info,
                                      "begins with an occluder pre-pass",
                                      "an OccluderSource (e.g. ddo::OccluderPass)")}) {
    if (!given) return given;
  }
  if (info.needs.depth_values && !sources.depth->traits().reads_depth) {
    return Status(ErrorCode::InvalidArgument,
                  std::string("culler: method ") + info.name +
                      " needs a depth source that reads depth values; '" +
                      sources.depth->traits().name + "' only answers counts");
  }
  Result<Projector> projector = Projector::create(camera, desc_.projection);  // the camera
  if (!projector) return projector.status();
  projector_ = std::make_unique<Projector>(std::move(projector).value());
  // Only what the method uses: a source it does not need is neither begun nor counted.
  sources_ = {info.needs.depth ? sources.depth : nullptr,
              info.needs.queries ? sources.queries : nullptr,
              info.needs.occluders ? sources.occluders : nullptr};
  const GridApproximation& approximation = frameApproximation();
  if (budget_) tester_->setApproximation(approximation);
  if (Status tester = tester_->beginFrame(camera, projector_->clearKey(), sources_); !tester) {
    return tester;
  }
  // Counting tests of the grid are sequential (grid.hpp); so are methods whose tests
  // read nothing worth batching.
  const bool counting_grid = approximation.visible_pixels > 0 && info.grid;
  lookahead_ = info.takes.lookahead && !counting_grid ? desc_.lookahead : 1;
  if (auto_) lookahead_ = setting_.lookahead;
  return {};
}

Status Culler::tryBeginFrame(const Camera& camera, const Hierarchy& hierarchy,
                             const CullSources& sources,
                             const std::vector<DrawnArea>& drawn_before) {
  if (in_frame_) {
    return Status(ErrorCode::InvalidArgument,
                  "Culler::beginFrame: the last frame was not ended; call nextBatch() until it "
                  "returns an empty batch, then endFrame()");
  }
  if (unreported_) {  // not reported: taken at its culled pass's time
    learnFrom(*unreported_);
    unreported_.reset();
  }
  start_ = std::chrono::steady_clock::now();
  if (auto_) chooseSetting(hierarchy);
  const MethodInfo& info = method_->info;
  if (Status prepared = prepare(camera, sources); !prepared) return prepared;
  in_frame_ = true;
  const AbandonOnThrow guard([this] { abandonFrame(); });
  if (Status begun = beginSourceFrames(camera); !begun) return failFrame(begun);
  hierarchy_ = &hierarchy;
  clearFrameState();
  coherence_ = auto_ ? setting_.temporal_coherence
                     : desc_.temporal_coherence && info.takes.temporal_coherence;
  // auto keeps the visible nodes with objects every frame: the next may choose coherence.
  record_visible_ = coherence_ || auto_;
  if (!auto_) setting_ = {desc_.method, lookahead_, coherence_, false, {}};
  setting_.approximation = frameApproximation();
  stats_.setting = setting_;

  for (const DrawnArea& area : drawn_before) noteDrawnWith(area, false);
  if (info.occluders != OccluderUse::None) {
    if (Status occluders = beginOccluders(camera); !occluders) return failFrame(occluders);
  }
  if (schedule_) {
    beginSchedule(hierarchy);
  } else {
    phase_ = coherence_ ? Phase::Coherent : Phase::Traverse;
    const NodeId root = hierarchy.root();
    if (root != kNoNode) pushTest(root, projector_->project(hierarchy.bounds(root)));
  }
  return {};
}

Status Culler::beginSourceFrames(const Camera& camera) {
  DepthSource* depth = sources_.depth;
  OcclusionQueries* queries = sources_.queries;
  if (depth) {
    if (Status begun = depth->beginFrame(camera); !begun) return begun;
  }
  if (queries) {
    if (Status begun = queries->beginQueryFrame(camera); !begun) return begun;
  }
  depth_before_ = depth ? depth->counters() : ReadCounters{};
  queries_before_ = queries ? queries->queryCounters() : QueryCounters{};
  return {};
}

void Culler::clearFrameState() {
  stats_ = {};
  grid_counts_ = {};
  drawn_back_ = kNothingDrawn;
  test_list_.clear();
  draw_list_.clear();
  pending_.clear();
  deferred_.clear();
  testing_.reset();
  resolve_due_ = false;
  batch_.clear();
  batch_areas_.clear();
  batch_rects_.clear();
  culled_undrawn_.clear();
  after_draw_.clear();
  visible_drawn_.clear();
  drawn_first_.clear();
  unordered_.clear();
}

Status Culler::beginOccluders(const Camera& camera) {
  // Selected for this camera. What a source draws of them is drawn out of order, like
  // drawn_before.
  const OccluderUse use = method_->info.occluders;
  occluder_areas_.clear();
  Result<std::uint64_t> occluders = sources_.occluders->beginFrame(
      camera, desc_.projection, use == OccluderUse::Recorded, occluder_areas_);
  if (!occluders) return occluders.status();
  stats_.occluders = *occluders;
  for (const DrawnArea& area : occluder_areas_) noteDrawnWith(area, false);
  // What the CPU knows of them: the cells a quad covers entirely are hidden behind it,
  // drawn or not (grid.hpp, coverage.hpp).
  if (use == OccluderUse::Recorded) {
    const CoverageRule rule = coverageRule(camera, desc_.projection);
    for (const DrawnQuad& quad : sources_.occluders->drawnQuads()) {
      stats_.occluder_tiles += tester_->recordCovered(quad, rule);
    }
  }
  return {};
}

void Culler::beginSchedule(const Hierarchy& hierarchy) {
  if (schedule_hierarchy_ != &hierarchy || schedule_revision_ != hierarchy.revision()) {
    schedule_->forget();
    schedule_hierarchy_ = &hierarchy;
    schedule_revision_ = hierarchy.revision();
  }
  if (method_->info.grid) {
    prefilter_ = std::make_unique<detail::GridPrefilter>(*tester_, grid_counts_);
  }
  detail::QueryFrame::Wiring wiring;
  wiring.hierarchy = &hierarchy;
  wiring.projector = projector_.get();
  wiring.queries = sources_.queries;
  wiring.prefilter = prefilter_.get();
  wiring.shape = desc_.queries.shape;
  wiring.stats = &stats_;
  wiring.clear_epoch = &clear_epoch_;
  wiring.undrawn = &batch_;
  wiring.draw = [this](const detail::QueryNode& n) { drawEntry({n.order, n.id, n.projection}); };
  if (observer_) {
    wiring.observe = [this](const detail::QueryNode& n, Visibility v) {
      observer_->onTested(n.id, n.projection, v);
    };
  }
  query_frame_ = std::make_unique<detail::QueryFrame>(wiring, ++schedule_frame_);
  schedule_->begin(*query_frame_);
  phase_ = Phase::Schedule;
}

Status Culler::failFrame(Status status) {
  abandonFrame();
  return status;
}

Result<DrawBatch> Culler::tryNextBatch() {
  if (Status in_frame = requireFrame("nextBatch"); !in_frame) return in_frame;
  const AbandonOnThrow guard([this] { abandonFrame(); });
  // The last batch is drawn: what waited for it can go on.
  batch_.clear();
  batch_areas_.clear();
  batch_rects_.clear();
  culled_undrawn_.clear();
  SourceAccess access(sources_);
  if (query_frame_) query_frame_->flushDeferred();
  advance();
  // A request that failed was answered as if nothing were drawn over it (visible), and
  // its source reports the error here.
  if (Status accessed = access.end(); !accessed) return failFrame(accessed);
  if (!batch_.empty()) handOutBatch();
  return DrawBatch{batch_.data(), batch_.size()};
}

Result<FrameStats> Culler::tryEndFrame() {
  if (Status in_frame = requireFrame("endFrame"); !in_frame) return in_frame;
  if (phase_ != Phase::Done || !batch_.empty()) {
    return failFrame(Status(ErrorCode::InvalidArgument,
                            "Culler::endFrame: the frame is not done; call nextBatch() until it "
                            "returns an empty batch (the frame is abandoned)"));
  }
  DepthSource* depth = sources_.depth;
  OcclusionQueries* queries = sources_.queries;
  {
    const AbandonOnThrow guard([this] { abandonFrame(); });
    Status ended = depth ? depth->endFrame() : Status{};
    Status queries_ended = queries ? queries->endQueryFrame() : Status{};
    if (!ended) return failFrame(ended);
    if (!queries_ended) return failFrame(queries_ended);
  }
  // Next frame's coherent set: the nodes with objects this frame found visible.
  if (record_visible_) {
    stats_.visible_leaves = visible_drawn_.size();
    stats_.visible_kept = countKept();
    coherent_.swap(visible_drawn_);
    coherent_hierarchy_ = hierarchy_;
    coherent_revision_ = hierarchy_->revision();
  }
  stats_.tiles_tested = grid_counts_.tiles_tested;
  stats_.tiles_read = grid_counts_.tiles_read;
  if (depth) {
    const ReadCounters& after = depth->counters();
    stats_.reads = after.reads - depth_before_.reads;
    stats_.pixels_read = after.pixels - depth_before_.pixels;
    stats_.bytes_read = after.bytes - depth_before_.bytes;
    stats_.queries = after.queries - depth_before_.queries;
    stats_.batches = after.batches - depth_before_.batches;
    stats_.flushes = after.flushes - depth_before_.flushes;
    stats_.state_queries = after.state_queries - depth_before_.state_queries;
    stats_.read_seconds = after.seconds - depth_before_.seconds;
  }
  if (queries) {
    const QueryCounters& q = queries->queryCounters();
    stats_.queries += q.queries - queries_before_.queries;
    stats_.query_boxes = q.boxes - queries_before_.boxes;
    stats_.query_polls = q.polls - queries_before_.polls;
    stats_.query_waits = q.waits - queries_before_.waits;
    stats_.flushes += q.flushes - queries_before_.flushes;
    stats_.state_queries += q.state_queries - queries_before_.state_queries;
    stats_.read_seconds += q.seconds - queries_before_.seconds;
  }
  stats_.seconds = secondsSince(start_);
  if (desc_.frame_clock == FrameClock::ReportedFrame) {
    unreported_ = stats_;  // learnt from when its whole time is reported
  } else {
    learnFrom(stats_);
  }
  abandonFrame();  // the frame's state is let go of
  return stats_;
}

const GridApproximation& Culler::frameApproximation() const {
  return budget_ ? budget_->current() : desc_.approximation;
}

void Culler::learnFrom(const FrameStats& frame) {
  // Not from auto's probes: a setting's first frame can pay once for what later frames
  // reuse (the city's first coherent frame took 2.5x its neighbours), and the estimate,
  // moved by that one time, judged the probe that paid it (costs clamped at their
  // limits: flushes 16x cheaper, triangles 16x dearer).
  if (!frame.setting.probe) estimate_.update(frame);
  if (auto_) auto_->endFrame(frame, estimate_.costs());
  if (budget_) budget_->endFrame(frame.seconds);
}

Status Culler::tryReportFrameTime(double seconds) {
  if (!(std::isfinite(seconds) && seconds >= 0)) {
    std::ostringstream out;
    out << "Culler::reportFrameTime: " << seconds
        << " s is not a frame time; pass the seconds the whole frame took (finite, >= 0)";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  if (desc_.frame_clock != FrameClock::ReportedFrame) return {};
  if (in_frame_ || !unreported_) {
    return Status(ErrorCode::InvalidArgument,
                  in_frame_ ? "Culler::reportFrameTime: called inside a frame; report a frame's "
                              "time after its endFrame()"
                            : "Culler::reportFrameTime: no frame ended since the last report; "
                              "report each frame once, after its endFrame()");
  }
  FrameStats frame = *unreported_;
  unreported_.reset();
  frame.seconds = seconds;
  learnFrom(frame);
  return {};
}

void Culler::abandonFrame() {
  in_frame_ = false;
  phase_ = Phase::Done;
  sources_ = {};
  hierarchy_ = nullptr;
  query_frame_.reset();
  prefilter_.reset();
  testing_.reset();
}

void Culler::advance() {
  for (;;) {
    if (!afterBatchDrawn()) return;
    switch (phase_) {
      case Phase::Coherent:
        drawCoherent();
        phase_ = Phase::CoherentRefresh;
        break;
      case Phase::CoherentRefresh:
        // Refreshes the tiles the coherent nodes made outdated: after they are drawn.
        if (!drawn_first_.empty()) {
          if (!batch_.empty()) return;
          tester_->refreshOutdated(grid_counts_);
        }
        phase_ = Phase::Traverse;
        break;
      case Phase::Traverse:
        if (!traverse()) return;
        phase_ = Phase::Done;
        break;
      case Phase::Schedule:
        if (!schedule_->resume(*query_frame_)) {
          assert(!batch_.empty() && "Culler: a schedule waits although nothing is to be drawn");
          return;
        }
        phase_ = Phase::Done;
        break;
      case Phase::Done: return;
    }
  }
}

bool Culler::afterBatchDrawn() {
  if (after_draw_.empty()) return true;
  if (!batch_.empty()) return false;
  for (const PixelRect& r : after_draw_) tester_->afterDraw(r);
  after_draw_.clear();
  return true;
}

bool Culler::traverse() {
  for (;;) {
    // What must wait until the batch is drawn: a busy refresh, a batch of reads, a test
    // that reads.
    if (!afterBatchDrawn()) return false;
    if (resolve_due_) {
      if (!batch_.empty() && tester_->batchReadsUnder(batch_rects_)) return false;
      resolve_due_ = false;
      resolvePending();
      continue;
    }
    if (testing_) {
      if (!testHeld()) return false;
      continue;
    }
    if (drawFrontmost()) continue;
    if (!test_list_.empty() && pending_.size() < lookahead_) {
      visitNext();
      continue;
    }
    if (!pending_.empty()) {
      resolve_due_ = true;
      continue;
    }
    if (test_list_.empty()) return true;
  }
}

inline bool Culler::testHeld() {
  // The threshold from what is drawn now: the batch may have announced more.
  const Entry entry = *testing_;
  bool by_state = false;
  const float threshold = thresholdFor(entry, by_state);
  const float hidden = entry.projection.occlusionThreshold();
  // A test that reads where the batch may draw waits for it to be drawn. One that reads
  // elsewhere reads now what it would read then, and the batch may grow: the renderer
  // is waited for once for both. One that reads both reads away from the batch first:
  // a box shown there is visible without the wait.
  const std::uint64_t read_before = grid_counts_.tiles_read;
  if (!batch_.empty() &&
      tester_->readsUnder(entry.projection.rect, threshold, hidden, batch_rects_)) {
    if (!tester_->testAwayFrom(entry.projection.rect, threshold, hidden, grid_counts_,
                               batch_rects_)) {
      return false;
    }
    testing_.reset();
    countFallback(by_state);
    decided(entry, Visibility::Visible, grid_counts_.tiles_read > read_before);
    return true;
  }
  testing_.reset();
  countFallback(by_state);
  const Visibility v = tester_->test(entry.projection.rect, threshold, hidden, grid_counts_);
  decided(entry, v, v == Visibility::Occluded || grid_counts_.tiles_read > read_before);
  return true;
}

inline bool Culler::drawFrontmost() {
  // Two-list order (LOG §3, fig. 2): draw the frontmost visible node once it lies in
  // front of the frontmost node still to be tested, or set aside for the next batch.
  if (draw_list_.empty()) return false;
  float gate =
      test_list_.empty() ? std::numeric_limits<float>::infinity() : test_list_.front().order;
  if (!pending_.empty()) gate = std::min(gate, pending_.front().order);
  if (!(draw_list_.front().order < gate)) return false;
  std::pop_heap(draw_list_.begin(), draw_list_.end(), LaterFirst{});
  const Entry entry = draw_list_.back();
  draw_list_.pop_back();
  drawEntry(entry);
  return true;
}

inline void Culler::visitNext() {
  std::pop_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
  const Entry entry = test_list_.back();
  test_list_.pop_back();
  ++stats_.nodes_visited;
  Visibility v = Visibility::Visible;
  if (forced(entry, v) || untestedByCost(entry)) {
    finish(entry, v);
    return;
  }
  if (waitsForColliding(entry)) return;
  ++stats_.boxes_tested;
  if (lookahead_ == 1) {
    testing_ = entry;  // tested at the top, once the batch is drawn if it reads
    return;
  }
  planTest(entry);
}

inline bool Culler::untestedByCost(const Entry& entry) {
  if (!auto_ ||
      auto_->worthTesting(entry.node, double(entry.projection.rect.area()), estimate_.costs())) {
    return false;
  }
  // Drawing it (or opening it) is expected to cost less than testing it: visible,
  // untested (NOHC §4.1's reasonability test; always conservative).
  ++stats_.boxes_untested;
  return true;
}

inline bool Culler::waitsForColliding(const Entry& entry) {
  const bool waits = lookahead_ > 1 && desc_.detect_colliding && !pending_.empty() &&
                     collidesWithPending(entry.projection.rect);
  if (!waits) return false;
  // §3.5: wait for the nearer boxes' answers (and draws) before asking about this one;
  // it comes off the test-list again after the batch.
  --stats_.nodes_visited;
  ++stats_.colliding_waits;
  test_list_.push_back(entry);
  std::push_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
  resolve_due_ = true;
  return true;
}

inline void Culler::planTest(const Entry& entry) {
  bool by_state = false;
  const float threshold = thresholdFor(entry, by_state);
  countFallback(by_state);
  const bool holds_objects = hierarchy_->objectCount(entry.node) > 0;
  std::optional<Visibility> planned =
      tester_->plan(entry.projection.rect, threshold, entry.projection.occlusionThreshold(),
                    grid_counts_, holds_objects);
  if (!planned) {
    if (holds_objects) {
      pending_.push_back(entry);
      pending_.back().by_state = by_state;
      return;
    }
    // A node without objects the records cannot decide is opened rather than waited for:
    // its children are tested instead (what a visible answer would do anyway), so
    // a descent through the hierarchy costs no batch per level.
    ++stats_.nodes_opened;
    planned = Visibility::Visible;
  } else if (*planned == Visibility::Visible && holds_objects && !pending_.empty()) {
    // Visible by the records, but nodes with objects in front of it are still
    // undecided, and what they hold back from drawing may hide it: tested again after.
    deferred_.push_back(entry);
    return;
  }
  decided(entry, *planned, *planned == Visibility::Occluded);  // from the records
}

void Culler::pushChildren(NodeId node) {
  // One call for the children's ids and boxes, one for their projections.
  const std::uint32_t count = hierarchy_->childCount(node);
  if (count == 0) return;
  if (child_ids_.size() < count) {
    child_ids_.resize(count);
    child_boxes_.resize(count);
    child_projections_.resize(count);
  }
  hierarchy_->children(node, child_ids_.data(), child_boxes_.data());
  projector_->project(child_boxes_.data(), count, child_projections_.data());
  for (std::uint32_t c = 0; c < count; ++c) pushTest(child_ids_[c], child_projections_[c]);
}

void Culler::pushTest(NodeId node, const BoxProjection& projection) {
  Entry entry{0, node, projection};
  if (entry.projection.cls == ProjectionClass::Outside) {
    ++stats_.boxes_view_culled;  // children never visited
    return;
  }
  entry.order = entry.projection.near_key - entry.projection.margin;
  test_list_.push_back(entry);
  std::push_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
}
bool Culler::forced(const Entry& entry, Visibility& result) {
  switch (entry.projection.cls) {
    case ProjectionClass::Outside: result = Visibility::ViewCulled; return true;
    case ProjectionClass::Invalid:
      ++stats_.invalid_boxes;
      result = Visibility::Visible;
      return true;
    case ProjectionClass::CrossesNear:
      ++stats_.boxes_near;
      result = Visibility::Visible;
      return true;
    case ProjectionClass::Inside: break;
  }
  if (method_->info.semantics == TestSemantics::None) {
    result = Visibility::Visible;
    return true;
  }
  return false;
}

bool Culler::collidesWithPending(const PixelRect& r) const {
  // Pending boxes came off the test-list first, so they are the nearer ones.
  for (const Entry& e : pending_) {
    const PixelRect& p = e.projection.rect;
    if (r.x0 < p.x1 && p.x0 < r.x1 && r.y0 < p.y1 && p.y0 < r.y1) return true;
  }
  return false;
}

bool Culler::orderVouches(const Entry& entry) const {
  // The occlusion-state semantics (any drawn pixel occludes) hold only if everything
  // drawn so far lies in front of this box. The two-list order guarantees it up to the
  // rounding of margins between parent and child boxes and for what the application
  // announced with a depth; where it does not, test by depth, which holds in any order.
  bool in_front = drawn_back_ < entry.order;
  for (std::size_t i = 0; in_front && i < unordered_.size(); ++i) {
    // NaN (unknown) is not in front; an area that shares no pixel with the box's
    // rectangle stores nothing the test looks at.
    const DrawnArea& a = unordered_[i];
    in_front = a.far_key < entry.order || !a.rect.meets(entry.projection.rect);
  }
  return in_front;
}

float Culler::thresholdFor(const Entry& entry, bool& by_state) const {
  by_state = method_->info.semantics == TestSemantics::OcclusionState && orderVouches(entry);
  return by_state ? projector_->clearKey() : entry.projection.occlusionThreshold();
}

void Culler::countFallback(bool by_state) {
  if (!by_state && method_->info.semantics == TestSemantics::OcclusionState) {
    ++stats_.order_fallbacks;
  }
}

void Culler::decided(const Entry& entry, Visibility v, bool evidence) {
  if (auto_) {
    auto_->noteAnswer(double(entry.projection.rect.area()), v == Visibility::Occluded, evidence);
  }
  if (v == Visibility::Occluded) {
    ++stats_.boxes_occluded;
    // Decided before the batch handed out is drawn: a depth clear while it is drawn
    // would take away what hides the box. Remembered until then (noteDepthCleared).
    if (!batch_.empty()) culled_undrawn_.push_back(entry);
  }
  finish(entry, v);
}

void Culler::finish(const Entry& entry, Visibility v) {
  const Hierarchy& hierarchy = *hierarchy_;
  if (observer_) observer_->onTested(entry.node, entry.projection, v);
  if (v != Visibility::Visible) return;
  if (hierarchy.objectCount(entry.node) > 0) {
    if (record_visible_) visible_drawn_.push_back(entry.node);
    if (method_->info.traversal == Traversal::TwoList) {
      Entry drawn = entry;
      drawn.order = entry.projection.far_key + entry.projection.margin;
      draw_list_.push_back(drawn);
      std::push_heap(draw_list_.begin(), draw_list_.end(), LaterFirst{});
    } else {
      drawEntry(entry);
    }
  }
  pushChildren(entry.node);
}

void Culler::resolvePending() {
  // One batch for every box set aside: the renderer is waited for once.
  tester_->submitBatch();
  sources_.depth->collect();
  tester_->applyBatch();
  // finish() may draw and push children, but never sets boxes aside: resolve them all.
  std::vector<Entry> batch;
  batch.swap(pending_);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    Visibility v = tester_->resolve(i);
    if (v == Visibility::Occluded && batch[i].by_state && !orderVouches(batch[i])) {
      // Planned as "any drawn pixel hides it", but something was drawn behind it since
      // (announced out of order): no longer sound. Tested again, by depth.
      test_list_.push_back(batch[i]);
      std::push_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
      continue;
    }
    decided(batch[i], v, true);  // read
  }
  tester_->clearBatch();
  batch.clear();
  batch.swap(pending_);  // keep the capacity
  for (const Entry& e : deferred_) {
    test_list_.push_back(e);
    std::push_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
  }
  deferred_.clear();
}

void Culler::batchObjects(NodeId node) {
  const std::uint32_t n = hierarchy_->objectCount(node);
  for (std::uint32_t i = 0; i < n; ++i) {
    const ObjectId id = hierarchy_->object(node, i);
    batch_.push_back(id);
    stats_.triangles_drawn += hierarchy_->objectTriangles(id);
  }
  stats_.objects_drawn += n;
  ++stats_.leaves_drawn;
}

void Culler::drawEntry(const Entry& entry) {
  if (!drawn_first_.empty() &&
      std::binary_search(drawn_first_.begin(), drawn_first_.end(), entry.node)) {
    return;  // drawn before the traversal (temporal coherence)
  }
  batchObjects(entry.node);
  noteDrawnWith({entry.projection.rect, entry.projection.far_key + entry.projection.margin}, true,
                true);
  if (observer_) observer_->onDrawn(entry.node, entry.projection);
}

void Culler::drawCoherent() {
  const Hierarchy& hierarchy = *hierarchy_;
  if (coherent_hierarchy_ != &hierarchy || coherent_revision_ != hierarchy.revision()) {
    coherent_.clear();
  }
  for (NodeId node : coherent_) {
    const BoxProjection p = projector_->project(hierarchy.bounds(node));
    if (p.cls == ProjectionClass::Outside) continue;
    batchObjects(node);
    ++stats_.coherent_leaves;
    drawn_first_.push_back(node);
    // Drawn out of order: later occlusion-state tests of boxes in front of it go by depth.
    noteDrawnWith({p.rect, p.far_key + p.margin}, false, true);
    if (observer_) observer_->onDrawn(node, p);
  }
  std::sort(drawn_first_.begin(), drawn_first_.end());
}

std::uint64_t Culler::countKept() {
  if (coherent_hierarchy_ != hierarchy_ || coherent_revision_ != hierarchy_->revision()) {
    return 0;
  }
  kept_scratch_.assign(coherent_.begin(), coherent_.end());
  std::sort(kept_scratch_.begin(), kept_scratch_.end());
  std::uint64_t kept = 0;
  for (NodeId node : visible_drawn_) {
    kept += std::binary_search(kept_scratch_.begin(), kept_scratch_.end(), node);
  }
  return kept;
}

void Culler::noteDrawnWith(const DrawnArea& area, bool ordered, bool batched) {
  const PixelRect r{std::max(area.rect.x0, 0), std::max(area.rect.y0, 0),
                    std::min(area.rect.x1, std::int32_t(projector_->camera().width)),
                    std::min(area.rect.y1, std::int32_t(projector_->camera().height))};
  if (!ordered && !r.empty() && unordered_.size() < kMaxUnorderedAreas) {
    unordered_.push_back({r, area.far_key});
  } else {
    // NaN is "unknown" as well.
    drawn_back_ = area.far_key >= drawn_back_  ? area.far_key
                  : area.far_key < drawn_back_ ? drawn_back_
                                               : std::numeric_limits<float>::infinity();
  }
  if (batched) batch_areas_.push_back({area, ordered});
  if (r.empty()) return;
  if (batched) {
    batch_rects_.push_back(r);
  } else {
    if (sources_.depth) sources_.depth->noteDraw();
    if (sources_.queries) sources_.queries->noteDraw();
  }
  tester_->noteDrawn(r);
  if (tester_->readsAfterDraw()) after_draw_.push_back(r);
}

void Culler::handOutBatch() {
  ++stats_.draw_batches;
  if (batch_rects_.empty()) return;  // draws no pixel
  if (sources_.depth) sources_.depth->noteDraw();
  if (sources_.queries) sources_.queries->noteDraw();
}

Status Culler::requireFrame(const char* who) const {
  if (in_frame_) return {};
  return Status(ErrorCode::InvalidArgument, std::string("Culler::") + who +
                                                ": call it only inside a frame (between "
                                                "beginFrame() and endFrame(), or from "
                                                "cullFrame()'s draw callback)");
}

Status Culler::tryNoteDrawn(const DrawnArea& area) {
  if (Status in_frame = requireFrame("noteDrawn"); !in_frame) return in_frame;
  noteDrawnWith(area, false);
  return {};
}

Status Culler::tryNoteDrawn(const Aabb& box) {
  if (Status in_frame = requireFrame("noteDrawn"); !in_frame) return in_frame;
  const BoxProjection p = projector_->project(box);
  if (p.cls == ProjectionClass::Outside) return {};  // draws no pixel
  noteDrawnWith({p.rect, p.cls == ProjectionClass::Inside ? p.far_key + p.margin
                                                          : std::numeric_limits<float>::infinity()},
                false);
  return {};
}

Status Culler::tryNoteDepthCleared() {
  if (Status in_frame = requireFrame("noteDepthCleared"); !in_frame) return in_frame;
  return tryNoteDepthCleared(
      windowDepth(projector_->camera().depth.convention, projector_->clearKey()));
}

Status Culler::tryNoteDepthCleared(float window_depth) {
  if (Status in_frame = requireFrame("noteDepthCleared"); !in_frame) return in_frame;
  if (!(window_depth >= 0.0f && window_depth <= 1.0f)) {
    return Status(ErrorCode::InvalidArgument,
                  "Culler::noteDepthCleared: window depth " + std::to_string(window_depth) +
                      " is outside [0, 1], which glClearDepth clamps to");
  }
  const float key = depthKey(projector_->camera().depth.convention, window_depth);
  tester_->noteCleared(key);
  ++clear_epoch_;  // query answers issued before now no longer hold
  // What was drawn before is gone. A clear to a nearer value is itself "drawn" at that
  // depth: occlusion-state tests of boxes in front of it must go by depth.
  drawn_back_ = key < projector_->clearKey() ? key : kNothingDrawn;
  unordered_.clear();
  // The batch being drawn may be drawn partly after the clear: it counts as drawn again.
  for (const BatchArea& b : batch_areas_) noteDrawnWith(b.area, b.ordered);
  // What was found hidden while it waited to be drawn is placed after it: tested again,
  // also when the traversal had finished with the batch being drawn.
  bool again = !culled_undrawn_.empty();
  for (const Entry& e : culled_undrawn_) {
    test_list_.push_back(e);
    std::push_heap(test_list_.begin(), test_list_.end(), LaterFirst{});
  }
  culled_undrawn_.clear();
  if (query_frame_) again |= query_frame_->reconsiderCulled(*schedule_);
  if (again && phase_ == Phase::Done) phase_ = schedule_ ? Phase::Schedule : Phase::Traverse;
  return {};
}

void Culler::forgetCoherence() {
  coherent_.clear();
  if (schedule_) schedule_->forget();
}

Result<BoxProjection> Culler::tryProject(const Aabb& box) const {
  if (Status in_frame = requireFrame("project"); !in_frame) return in_frame;
  return projector_->project(box);
}

}  // namespace logrid
