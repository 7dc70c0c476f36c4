#include "testers.hpp"

#include <cassert>
#include <optional>
#include <string>
#include <vector>

#include "logrid/depth_pyramid.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"

namespace logrid::detail {

std::optional<Visibility> BoxTester::plan(const PixelRect&, float, float, GridTestCounts&, bool) {
  assert(false && "BoxTester::plan: this method does not batch its tests");
  return Visibility::Visible;
}

Visibility BoxTester::resolve(std::size_t) { return Visibility::Visible; }

namespace {

// log-state, log-zfar, log+hwq, ddo+log (lazy: tiles marked outdated after a draw) and bog
// (busy: tiles refreshed right after each draw, LOG §5).
class GridTester final : public BoxTester {
 public:
  GridTester(const CullerDesc& desc, GridVariant variant, GridRefresh refresh)
      : desc_(desc), variant_(variant), refresh_(refresh) {}

  Status beginFrame(const Camera& camera, float clear_key, const CullSources& sources) override {
    source_ = sources.depth;
    assert(source_ && "GridTester: the culler checks that the method's depth source is given");
    const GridDesc want{camera.width, camera.height, desc_.tile_size, variant_};
    if (!grid_ || grid_->desc().width != want.width || grid_->desc().height != want.height) {
      Result<OcclusionGrid> grid = OcclusionGrid::create(want, desc_.approximation);
      if (!grid) return grid.status();
      grid_.emplace(std::move(grid).value());
    }
    grid_->reset(clear_key);
    batch_.clear();
    return {};
  }
  void setApproximation(const GridApproximation& a) override {
    const GridApproximation& now = desc_.approximation;
    if (a.visible_pixels == now.visible_pixels && a.full_free_fraction == now.full_free_fraction &&
        a.row_stride == now.row_stride) {
      return;
    }
    desc_.approximation = a;
    grid_.reset();  // made again with the new knobs in beginFrame
  }
  Visibility test(const PixelRect& rect, float threshold, float hidden,
                  GridTestCounts& counts) override {
    return grid_->test(rect, threshold, *source_, counts, hidden);
  }
  bool readsUnder(const PixelRect& rect, float threshold, float hidden,
                  const std::vector<PixelRect>& undrawn) override {
    return grid_->readsUnder(rect, threshold, source_->traits(), hidden, undrawn.data(),
                             undrawn.size());
  }
  bool batchReadsUnder(const std::vector<PixelRect>& undrawn) override {
    return grid_->readsUnder(batch_, undrawn.data(), undrawn.size());
  }
  std::optional<Visibility> testAwayFrom(const PixelRect& rect, float threshold, float hidden,
                                         GridTestCounts& counts,
                                         const std::vector<PixelRect>& undrawn) override {
    return grid_->testAwayFrom(rect, threshold, *source_, counts, hidden, undrawn.data(),
                               undrawn.size());
  }
  std::optional<Visibility> plan(const PixelRect& rect, float threshold, float hidden,
                                 GridTestCounts& counts, bool read) override {
    return grid_->plan(rect, threshold, source_->traits(), read ? &batch_ : nullptr, counts,
                       hidden);
  }
  void submitBatch() override { grid_->submit(batch_, *source_); }
  void applyBatch() override { grid_->apply(batch_); }
  Visibility resolve(std::size_t index) override { return grid_->resolve(batch_, index); }
  void clearBatch() override { batch_.clear(); }
  void noteDrawn(const PixelRect& rect) override {
    if (refresh_ == GridRefresh::Lazy) grid_->markOutdated(rect);
  }
  std::uint64_t recordCovered(const DrawnQuad& quad, const CoverageRule& rule) override {
    return grid_->recordCovered(quad, rule);
  }
  bool readsAfterDraw() const override { return refresh_ == GridRefresh::Busy; }
  void afterDraw(const PixelRect& rect) override { grid_->refreshNow(rect, *source_); }
  void noteCleared(float key) override { grid_->fill(key); }
  void refreshOutdated(GridTestCounts& counts) override {
    grid_->refreshOutdated(*source_, counts);
  }
  std::optional<Visibility> decide(const PixelRect& rect, float threshold,
                                   GridTestCounts& counts) override {
    return grid_->decide(rect, threshold, counts);
  }
  void refreshUnder(const std::vector<PixelRect>& rects, GridTestCounts& counts) override {
    grid_->refreshOutdated(rects.data(), rects.size(), *source_, counts);
  }
  const OcclusionGrid* grid() const override { return grid_ ? &*grid_ : nullptr; }

 private:
  CullerDesc desc_;
  GridVariant variant_;
  GridRefresh refresh_;
  DepthSource* source_ = nullptr;
  std::optional<OcclusionGrid> grid_;
  GridBatch batch_;
};

// hzb: a CPU pyramid over the depth buffer, updated from the drawn box's area after
// each draw; tests read nothing.
class PyramidTester final : public BoxTester {
 public:
  Status beginFrame(const Camera& camera, float clear_key, const CullSources& sources) override {
    assert(sources.depth &&
           "PyramidTester: the culler checks that the method's depth source is given");
    source_ = dynamic_cast<KeyReader*>(sources.depth);
    if (!source_) {
      return Status(
          ErrorCode::InvalidArgument,
          std::string("culler: method hzb builds its pyramid from the keys of whole areas; "
                      "the depth source '") +
              sources.depth->traits().name +
              "' is not a logrid::KeyReader (depth_source.hpp); derive it from "
              "logrid::PixelSource, or pick a method of the lazy grid");
    }
    if (!pyramid_ || width_ != camera.width || height_ != camera.height) {
      pyramid_ = std::make_unique<DepthPyramid>(camera.width, camera.height);
      width_ = camera.width;
      height_ = camera.height;
    }
    pyramid_->reset(clear_key);
    return {};
  }
  Visibility test(const PixelRect& rect, float threshold, float, GridTestCounts& counts) override {
    return pyramid_->test(rect, threshold, counts.tiles_tested);
  }
  void noteDrawn(const PixelRect&) override {}
  bool readsAfterDraw() const override { return true; }
  void afterDraw(const PixelRect& rect) override { pyramid_->update(rect, *source_); }
  void noteCleared(float key) override { pyramid_->reset(key); }

 private:
  KeyReader* source_ = nullptr;
  std::unique_ptr<DepthPyramid> pyramid_;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
};

// pq: one pixel-level count over the box's whole rectangle.
class RectCountTester final : public BoxTester {
 public:
  explicit RectCountTester(std::uint32_t visible_pixels) : visible_pixels_(visible_pixels) {}

  Status beginFrame(const Camera&, float, const CullSources& sources) override {
    source_ = sources.depth;
    assert(source_ && "RectCountTester: the culler checks that the method's depth source is given");
    clearBatch();
    return {};
  }
  bool readsUnder(const PixelRect& rect, float, float,
                  const std::vector<PixelRect>& undrawn) override {
    return meetsAny(rect, undrawn.data(), undrawn.size());
  }
  bool batchReadsUnder(const std::vector<PixelRect>& undrawn) override {
    for (const AreaRequest& request : requests_) {
      if (meetsAny(request.rect, undrawn.data(), undrawn.size())) return true;
    }
    return false;
  }
  Visibility test(const PixelRect& rect, float threshold, float, GridTestCounts& counts) override {
    std::uint32_t count = 0;
    source_->countAtOrBeyond(&rect, 1, threshold, &count);
    ++counts.tiles_tested;
    return shows(count);
  }
  std::optional<Visibility> plan(const PixelRect& rect, float threshold, float,
                                 GridTestCounts& counts, bool read) override {
    if (!read) return std::nullopt;  // no records: every answer is a read
    requests_.push_back({rect, AreaAsk::Count, threshold});
    ++counts.tiles_tested;
    return std::nullopt;
  }
  void submitBatch() override {
    answers_.assign(requests_.size(), AreaAnswer{});
    source_->submit(requests_.data(), requests_.size(), answers_.data());
  }
  Visibility resolve(std::size_t index) override { return shows(answers_[index].count); }
  void clearBatch() override {
    requests_.clear();
    answers_.clear();
  }
  void noteDrawn(const PixelRect&) override {}
  void noteCleared(float) override {}

 private:
  Visibility shows(std::uint32_t count) const {
    return count > visible_pixels_ ? Visibility::Visible : Visibility::Occluded;
  }
  std::uint32_t visible_pixels_;
  DepthSource* source_ = nullptr;
  std::vector<AreaRequest> requests_;
  std::vector<AreaAnswer> answers_;
};

// ddo: the occluders' CPU map. The map holds only occluders valid for the viewpoint, so a
// box behind them at every pixel is hidden by the scene; draws and clears change nothing.
class OccluderMapTester final : public BoxTester {
 public:
  Status beginFrame(const Camera&, float, const CullSources& sources) override {
    occluders_ = sources.occluders;
    assert(occluders_ && "OccluderMapTester: the culler checks that the occluders are given");
    return {};
  }
  Visibility test(const PixelRect& rect, float threshold, float, GridTestCounts& counts) override {
    ++counts.tiles_tested;
    return occluders_->occludes(rect, threshold) ? Visibility::Occluded : Visibility::Visible;
  }
  void noteDrawn(const PixelRect&) override {}
  void noteCleared(float) override {}

 private:
  const OccluderSource* occluders_ = nullptr;
};

// vfc and the query schedules: the culler never calls test() for them.
class NoTester final : public BoxTester {
 public:
  Status beginFrame(const Camera&, float, const CullSources&) override { return {}; }
  Visibility test(const PixelRect&, float, float, GridTestCounts&) override {
    return Visibility::Visible;
  }
  void noteDrawn(const PixelRect&) override {}
  void noteCleared(float) override {}
};

}  // namespace

std::unique_ptr<BoxTester> makeGridTester(const CullerDesc& desc, GridVariant variant,
                                          GridRefresh refresh) {
  return std::make_unique<GridTester>(desc, variant, refresh);
}

std::unique_ptr<BoxTester> makePyramidTester() { return std::make_unique<PyramidTester>(); }

std::unique_ptr<BoxTester> makeRectCountTester(std::uint32_t visible_pixels) {
  return std::make_unique<RectCountTester>(visible_pixels);
}

std::unique_ptr<BoxTester> makeOccluderMapTester() { return std::make_unique<OccluderMapTester>(); }

std::unique_ptr<BoxTester> makeNoTester() { return std::make_unique<NoTester>(); }

}  // namespace logrid::detail
