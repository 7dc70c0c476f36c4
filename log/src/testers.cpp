#include "testers.hpp"

#include <cassert>
#include <optional>
#include <vector>

#include "logrid/depth_pyramid.hpp"

namespace logrid::detail {

std::optional<Visibility> BoxTester::plan(const PixelRect&, float, const DepthSourceTraits&,
                                          GridTestCounts&, bool) {
  assert(false && "BoxTester::plan: this method does not batch its tests");
  return Visibility::Visible;
}

void BoxTester::submitBatch(DepthSource&) {}

Visibility BoxTester::resolve(std::size_t, GridTestCounts&) { return Visibility::Visible; }

namespace {

// log-state, log-zfar (lazy: tiles marked outdated after a draw) and bog (busy: tiles
// refreshed right after each draw, LOG §5).
class GridTester final : public BoxTester {
 public:
  GridTester(const CullerDesc& desc, bool busy) : desc_(desc), busy_(busy) {}

  void beginFrame(const Camera& camera, float clear_key) override {
    // log+hwq draws what the queries find visible at once: depth tests, as the zfar variant.
    const bool zfar = desc_.method == Method::LogZfar || desc_.method == Method::LogHwq;
    const GridDesc want{camera.width, camera.height, desc_.tile_size,
                        zfar ? GridVariant::Zfar : GridVariant::OcclusionState};
    if (!grid_ || grid_->desc().width != want.width || grid_->desc().height != want.height) {
      grid_.emplace(want, desc_.approximation);
    }
    grid_->reset(clear_key);
    batch_.clear();
  }
  Visibility test(const PixelRect& rect, float threshold, DepthSource& source,
                  GridTestCounts& counts) override {
    return grid_->test(rect, threshold, source, counts);
  }
  std::optional<Visibility> plan(const PixelRect& rect, float threshold,
                                 const DepthSourceTraits& source, GridTestCounts& counts,
                                 bool read) override {
    return grid_->plan(rect, threshold, source, read ? &batch_ : nullptr, counts);
  }
  void submitBatch(DepthSource& source) override { grid_->submit(batch_, source); }
  void applyBatch() override { grid_->apply(batch_); }
  Visibility resolve(std::size_t index, GridTestCounts& counts) override {
    return grid_->resolve(batch_, index, counts);
  }
  void clearBatch() override { batch_.clear(); }
  void noteDrawn(const PixelRect& rect, DepthSource& source) override {
    if (busy_) {
      grid_->refreshNow(rect, source);
    } else {
      grid_->markOutdated(rect);
    }
  }
  void noteCleared(float key) override { grid_->fill(key); }
  void refreshOutdated(DepthSource& source, GridTestCounts& counts) override {
    grid_->refreshOutdated(source, counts);
  }
  std::optional<Visibility> decide(const PixelRect& rect, float threshold,
                                   GridTestCounts& counts) override {
    return grid_->decide(rect, threshold, counts);
  }
  void refreshUnder(const std::vector<PixelRect>& rects, DepthSource& source,
                    GridTestCounts& counts) override {
    grid_->refreshOutdated(rects.data(), rects.size(), source, counts);
  }
  const OcclusionGrid* grid() const override { return grid_ ? &*grid_ : nullptr; }

 private:
  CullerDesc desc_;
  bool busy_;
  std::optional<OcclusionGrid> grid_;
  GridBatch batch_;
};

// hzb: a CPU pyramid over the depth buffer, updated from the drawn box's area after
// each draw; tests read nothing.
class PyramidTester final : public BoxTester {
 public:
  void beginFrame(const Camera& camera, float clear_key) override {
    if (!pyramid_ || width_ != camera.width || height_ != camera.height) {
      pyramid_ = std::make_unique<DepthPyramid>(camera.width, camera.height);
      width_ = camera.width;
      height_ = camera.height;
    }
    pyramid_->reset(clear_key);
  }
  Visibility test(const PixelRect& rect, float threshold, DepthSource&,
                  GridTestCounts& counts) override {
    return pyramid_->test(rect, threshold, counts.tiles_tested);
  }
  void noteDrawn(const PixelRect& rect, DepthSource& source) override {
    pyramid_->update(rect, source);
  }
  void noteCleared(float key) override { pyramid_->reset(key); }

 private:
  std::unique_ptr<DepthPyramid> pyramid_;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
};

// pq: one pixel-level count over the box's whole rectangle.
class RectCountTester final : public BoxTester {
 public:
  explicit RectCountTester(std::uint32_t visible_pixels) : visible_pixels_(visible_pixels) {}

  void beginFrame(const Camera&, float) override { clearBatch(); }
  Visibility test(const PixelRect& rect, float threshold, DepthSource& source,
                  GridTestCounts& counts) override {
    std::uint32_t count = 0;
    source.countAtOrBeyond(&rect, 1, threshold, &count);
    ++counts.tiles_tested;
    return shows(count);
  }
  std::optional<Visibility> plan(const PixelRect& rect, float threshold, const DepthSourceTraits&,
                                 GridTestCounts& counts, bool read) override {
    if (!read) return std::nullopt;  // no records: every answer is a read
    requests_.push_back({rect, AreaAsk::Count, threshold});
    ++counts.tiles_tested;
    return std::nullopt;
  }
  void submitBatch(DepthSource& source) override {
    answers_.assign(requests_.size(), AreaAnswer{});
    source.submit(requests_.data(), requests_.size(), answers_.data());
  }
  Visibility resolve(std::size_t index, GridTestCounts&) override {
    return shows(answers_[index].count);
  }
  void clearBatch() override {
    requests_.clear();
    answers_.clear();
  }
  void noteDrawn(const PixelRect&, DepthSource&) override {}
  void noteCleared(float) override {}

 private:
  Visibility shows(std::uint32_t count) const {
    return count > visible_pixels_ ? Visibility::Visible : Visibility::Occluded;
  }
  std::uint32_t visible_pixels_;
  std::vector<AreaRequest> requests_;
  std::vector<AreaAnswer> answers_;
};

// vfc: no occlusion test (the culler never calls test() for it).
class NoTester final : public BoxTester {
 public:
  void beginFrame(const Camera&, float) override {}
  Visibility test(const PixelRect&, float, DepthSource&, GridTestCounts&) override {
    return Visibility::Visible;
  }
  void noteDrawn(const PixelRect&, DepthSource&) override {}
  void noteCleared(float) override {}
};

}  // namespace

std::unique_ptr<BoxTester> makeTester(const CullerDesc& desc) {
  switch (desc.method) {
    case Method::LogState:
    case Method::LogZfar:
    case Method::LogHwq: return std::make_unique<GridTester>(desc, false);
    case Method::Bog: return std::make_unique<GridTester>(desc, true);
    case Method::Hzb: return std::make_unique<PyramidTester>();
    case Method::Pq: return std::make_unique<RectCountTester>(desc.approximation.visible_pixels);
    case Method::Vfc:
    case Method::Hwq:
    case Method::Chc:
    case Method::Stat:
    case Method::Nohc: return std::make_unique<NoTester>();
  }
  return std::make_unique<NoTester>();
}

}  // namespace logrid::detail
