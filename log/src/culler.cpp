#include "logrid/culler.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <limits>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid {

const char* toString(Method method) {
  switch (method) {
    case Method::LogState: return "log-state";
    case Method::LogZfar: return "log-zfar";
    case Method::Bog: return "bog";
    case Method::Hzb: return "hzb";
    case Method::Pq: return "pq";
    case Method::Vfc: return "vfc";
  }
  return "?";
}

std::optional<Method> parseMethod(const std::string& name) {
  for (Method m :
       {Method::LogState, Method::LogZfar, Method::Bog, Method::Hzb, Method::Pq, Method::Vfc}) {
    if (name == toString(m)) return m;
  }
  return std::nullopt;
}

std::string validateCullerDesc(const CullerDesc& desc) {
  if (!parseMethod(toString(desc.method))) {
    return "culler: method " + std::to_string(int(desc.method)) +
           " is unknown; use log-state, log-zfar, bog, hzb, pq or vfc";
  }
  const std::string projection = validateProjectionSettings(desc.projection);
  if (!projection.empty()) return "culler: " + projection;
  if (desc.tile_size < 1) {
    std::ostringstream out;
    out << "culler: tile size " << desc.tile_size << " is invalid; use 1 pixel or more";
    return out.str();
  }
  const GridApproximation& a = desc.approximation;
  const std::string method = toString(desc.method);
  if (!a.exact() && (desc.method == Method::Hzb || desc.method == Method::Vfc)) {
    return "culler: method " + method + " takes no approximation settings";
  }
  if (desc.method == Method::Pq && (a.full_free_fraction != 0 || a.row_stride != 1)) {
    return "culler: method pq takes only the visible-pixel threshold (it has no tiles)";
  }
  if (desc.method == Method::LogState || desc.method == Method::LogZfar ||
      desc.method == Method::Bog) {
    // The grid's own checks, with a viewport that is always valid.
    const GridVariant variant =
        desc.method == Method::LogZfar ? GridVariant::Zfar : GridVariant::OcclusionState;
    const std::string problem = validateGridDesc({1, 1, desc.tile_size, variant}, a);
    if (!problem.empty()) return "culler: " + problem;
  }
  return {};
}

Culler::Culler(const CullerDesc& desc) : desc_(desc) {
  const std::string problem = validateCullerDesc(desc);
  if (!problem.empty()) throw Error(ErrorCode::InvalidArgument, problem);
}

Culler::~Culler() = default;
Culler::Culler(Culler&&) noexcept = default;
Culler& Culler::operator=(Culler&&) noexcept = default;

bool Culler::usesTwoLists() const {
  return desc_.method != Method::LogZfar && desc_.method != Method::Vfc;
}

namespace {

// Min-heaps on Entry::order.
template <typename E>
bool laterFirst(const E& a, const E& b) {
  return a.order > b.order;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void Culler::prepare(const Camera& camera) {
  projector_.emplace(camera, desc_.projection);  // validates the camera
  const bool needs_grid = desc_.method == Method::LogState || desc_.method == Method::LogZfar ||
                          desc_.method == Method::Bog;
  if (needs_grid) {
    const GridDesc want{
        camera.width, camera.height, desc_.tile_size,
        desc_.method == Method::LogZfar ? GridVariant::Zfar : GridVariant::OcclusionState};
    if (!grid_ || grid_->desc().width != want.width || grid_->desc().height != want.height ||
        grid_->desc().tile_size != want.tile_size || grid_->desc().variant != want.variant) {
      grid_.emplace(want, desc_.approximation);
    }
    grid_->reset(projector_->clearKey());
  }
  if (desc_.method == Method::Hzb) {
    if (!pyramid_ || pyramid_->levels() == 0 || last_width_ != camera.width ||
        last_height_ != camera.height) {
      pyramid_ = std::make_unique<DepthPyramid>(camera.width, camera.height);
    }
    pyramid_->reset(projector_->clearKey());
  }
  last_width_ = camera.width;
  last_height_ = camera.height;
}

FrameStats Culler::cullFrame(const Camera& camera, const Hierarchy& hierarchy, DepthSource& depth,
                             const DrawCallback& draw) {
  const auto start = std::chrono::steady_clock::now();
  prepare(camera);
  const bool reads_pixels = depth.traits().reads_pixels;
  if (!reads_pixels && (desc_.method == Method::Hzb)) {
    throw Error(ErrorCode::InvalidArgument,
                std::string("culler: method hzb needs a depth source that reads pixels; '") +
                    depth.traits().name + "' only answers occlusion queries");
  }
  depth.beginFrame(camera);
  const ReadCounters before = depth.counters();
  stats_ = {};
  grid_counts_ = {};
  drawn_back_ = -std::numeric_limits<float>::infinity();
  test_list_.clear();
  draw_list_.clear();
  current_source_ = &depth;

  const NodeId root = hierarchy.root();
  if (root != kNoNode) pushTest(hierarchy, root);

  const bool two_lists = usesTwoLists();
  for (;;) {
    // Two-list order (LOG §3, fig. 2): draw the frontmost visible node once it lies in
    // front of the frontmost node still to be tested.
    if (!draw_list_.empty() &&
        (test_list_.empty() || draw_list_.front().order < test_list_.front().order)) {
      std::pop_heap(draw_list_.begin(), draw_list_.end(), laterFirst<Entry>);
      const Entry entry = draw_list_.back();
      draw_list_.pop_back();
      drawEntry(entry, hierarchy, depth, draw);
      continue;
    }
    if (test_list_.empty()) break;
    std::pop_heap(test_list_.begin(), test_list_.end(), laterFirst<Entry>);
    const Entry entry = test_list_.back();
    test_list_.pop_back();
    ++stats_.nodes_visited;

    const Visibility v = testEntry(entry, depth);
    if (observer_) observer_->onTested(entry.node, entry.projection, v);
    if (v != Visibility::Visible) continue;

    if (hierarchy.objectCount(entry.node) > 0) {
      if (two_lists) {
        Entry drawn = entry;
        drawn.order = entry.projection.far_key + entry.projection.margin;
        draw_list_.push_back(drawn);
        std::push_heap(draw_list_.begin(), draw_list_.end(), laterFirst<Entry>);
      } else {
        drawEntry(entry, hierarchy, depth, draw);
      }
    }
    const std::uint32_t children = hierarchy.childCount(entry.node);
    for (std::uint32_t c = 0; c < children; ++c)
      pushTest(hierarchy, hierarchy.child(entry.node, c));
  }
  current_source_ = nullptr;
  depth.endFrame();

  const ReadCounters& after = depth.counters();
  stats_.tiles_tested = grid_counts_.tiles_tested + stats_.tiles_tested;
  stats_.tiles_read = grid_counts_.tiles_read;
  stats_.reads = after.reads - before.reads;
  stats_.pixels_read = after.pixels - before.pixels;
  stats_.queries = after.queries - before.queries;
  stats_.flushes = after.flushes - before.flushes;
  stats_.read_seconds = after.seconds - before.seconds;
  stats_.seconds = secondsSince(start);
  return stats_;
}

void Culler::pushTest(const Hierarchy& hierarchy, NodeId node) {
  Entry entry{0, node, projector_->project(hierarchy.bounds(node))};
  if (entry.projection.cls == ProjectionClass::Outside) {
    ++stats_.boxes_view_culled;  // children never visited
    return;
  }
  entry.order = entry.projection.near_key - entry.projection.margin;
  test_list_.push_back(entry);
  std::push_heap(test_list_.begin(), test_list_.end(), laterFirst<Entry>);
}

Visibility Culler::testEntry(const Entry& entry, DepthSource& depth) {
  const BoxProjection& p = entry.projection;
  switch (p.cls) {
    case ProjectionClass::Outside: return Visibility::ViewCulled;
    case ProjectionClass::Invalid: ++stats_.invalid_boxes; return Visibility::Visible;
    case ProjectionClass::CrossesNear: ++stats_.boxes_near; return Visibility::Visible;
    case ProjectionClass::Inside: break;
  }
  if (desc_.method == Method::Vfc) return Visibility::Visible;

  // The occlusion-state semantics (any drawn pixel occludes) hold only if everything
  // drawn so far lies in front of this box. The two-list order guarantees it up to the
  // rounding of margins between parent and child boxes; where it does not, be visible.
  const bool state_semantics =
      desc_.method == Method::LogState || desc_.method == Method::Bog || desc_.method == Method::Pq;
  if (state_semantics && !(drawn_back_ < entry.order)) {
    ++stats_.order_fallbacks;
    return Visibility::Visible;
  }
  const float threshold = state_semantics ? projector_->clearKey() : p.occlusionThreshold();

  ++stats_.boxes_tested;
  Visibility v = Visibility::Visible;
  switch (desc_.method) {
    case Method::LogState:
    case Method::LogZfar:
    case Method::Bog: v = grid_->test(p.rect, threshold, depth, grid_counts_); break;
    case Method::Hzb: v = pyramid_->test(p.rect, threshold, stats_.tiles_tested); break;
    case Method::Pq: {
      const AreaQuery query{p.rect, threshold};
      std::uint32_t count = 0;
      depth.countAtOrBeyond(&query, 1, &count);
      ++grid_counts_.tiles_tested;
      v = count > desc_.approximation.visible_pixels ? Visibility::Visible : Visibility::Occluded;
      break;
    }
    case Method::Vfc: break;
  }
  if (v == Visibility::Occluded) ++stats_.boxes_occluded;
  return v;
}

void Culler::drawEntry(const Entry& entry, const Hierarchy& hierarchy, DepthSource& depth,
                       const DrawCallback& draw) {
  const std::uint32_t n = hierarchy.objectCount(entry.node);
  for (std::uint32_t i = 0; i < n; ++i) draw(hierarchy.object(entry.node, i));
  stats_.objects_drawn += n;
  ++stats_.leaves_drawn;
  drawn_back_ = std::max(drawn_back_, entry.projection.far_key + entry.projection.margin);
  depth.noteDraw();
  noteDrawnWith(entry.projection.rect, depth);
  if (observer_) observer_->onDrawn(entry.node, entry.projection);
}

void Culler::noteDrawn(const PixelRect& rect) {
  if (!current_source_) {
    throw Error(ErrorCode::InvalidArgument,
                "Culler::noteDrawn: call it only from inside cullFrame()'s draw callback");
  }
  noteDrawnWith(rect, *current_source_);
}

void Culler::noteDrawnWith(const PixelRect& rect, DepthSource& depth) {
  if (rect.empty()) return;
  switch (desc_.method) {
    case Method::LogState:
    case Method::LogZfar: grid_->markOutdated(rect); break;
    case Method::Bog: grid_->refreshNow(rect, depth); break;
    case Method::Hzb: pyramid_->update(rect, depth); break;
    case Method::Pq:
    case Method::Vfc: break;
  }
}

}  // namespace logrid
