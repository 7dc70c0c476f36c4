#include "logrid/depth_pyramid.hpp"

#include <algorithm>
#include <cassert>

namespace logrid {

DepthPyramid::DepthPyramid(std::uint32_t width, std::uint32_t height) {
  std::uint32_t w = std::max(width, 1u), h = std::max(height, 1u);
  for (;;) {
    levels_.push_back({w, h, std::vector<float>(std::size_t(w) * h, 1.0f)});
    if (w == 1 && h == 1) break;
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
}

void DepthPyramid::reset(float clear_key) {
  for (Level& level : levels_) std::fill(level.keys.begin(), level.keys.end(), clear_key);
}

void DepthPyramid::update(const PixelRect& rect, KeyReader& source) {
  Level& base = levels_[0];
  PixelRect r{std::max(rect.x0, 0), std::max(rect.y0, 0),
              std::min(rect.x1, std::int32_t(base.width)),
              std::min(rect.y1, std::int32_t(base.height))};
  if (r.empty()) return;
  const std::size_t w = std::size_t(r.x1 - r.x0);
  scratch_.resize(std::size_t(r.area()));
  source.readKeys(r, scratch_.data());
  for (std::int32_t y = r.y0; y < r.y1; ++y) {
    std::copy_n(scratch_.data() + std::size_t(y - r.y0) * w, w,
                base.keys.data() + std::size_t(y) * base.width + std::size_t(r.x0));
  }
  // Propagate the farthest key of each 2x2 block upwards over the touched cells.
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    const Level& fine = levels_[l - 1];
    Level& coarse = levels_[l];
    r = {r.x0 / 2, r.y0 / 2, (r.x1 + 1) / 2, (r.y1 + 1) / 2};
    for (std::int32_t y = r.y0; y < r.y1; ++y) {
      const std::uint32_t fy0 = std::uint32_t(y) * 2, fy1 = std::min(fy0 + 1, fine.height - 1);
      for (std::int32_t x = r.x0; x < r.x1; ++x) {
        const std::uint32_t fx0 = std::uint32_t(x) * 2, fx1 = std::min(fx0 + 1, fine.width - 1);
        const float* row0 = fine.keys.data() + std::size_t(fy0) * fine.width;
        const float* row1 = fine.keys.data() + std::size_t(fy1) * fine.width;
        coarse.keys[std::size_t(y) * coarse.width + std::size_t(x)] =
            std::max(std::max(row0[fx0], row0[fx1]), std::max(row1[fx0], row1[fx1]));
      }
    }
  }
}

Visibility DepthPyramid::test(const PixelRect& rect, float threshold,
                              std::uint64_t& cells_tested) const {
  assert(!rect.empty() && "DepthPyramid::test: empty rect");
  // Start at the coarsest level where the rectangle spans at most 2 cells per axis.
  std::uint32_t start = 0;
  while (start + 1 < levels_.size()) {
    const std::int32_t s = start + 1;
    if (((rect.x1 - 1) >> s) - (rect.x0 >> s) > 1 || ((rect.y1 - 1) >> s) - (rect.y0 >> s) > 1) {
      break;
    }
    ++start;
  }
  // Depth-first over cells that intersect the rectangle: (level, x, y) packed in 64 bits.
  auto pack = [](std::uint32_t level, std::uint32_t x, std::uint32_t y) {
    return std::uint64_t(level) << 56 | std::uint64_t(x) << 28 | y;
  };
  work_.clear();
  for (std::int32_t y = rect.y0 >> start; y <= (rect.y1 - 1) >> start; ++y) {
    for (std::int32_t x = rect.x0 >> start; x <= (rect.x1 - 1) >> start; ++x) {
      work_.push_back(pack(start, std::uint32_t(x), std::uint32_t(y)));
    }
  }
  while (!work_.empty()) {
    const std::uint64_t cell = work_.back();
    work_.pop_back();
    const std::uint32_t level = std::uint32_t(cell >> 56);
    const std::uint32_t x = std::uint32_t(cell >> 28) & 0xFFFFFFFu,
                        y = std::uint32_t(cell) & 0xFFFFFFFu;
    const Level& lv = levels_[level];
    ++cells_tested;
    if (lv.keys[std::size_t(y) * lv.width + x] < threshold) continue;  // all in front
    if (level == 0) return Visibility::Visible;
    // Children that exist and intersect the rectangle.
    const std::uint32_t child = level - 1;
    const Level& fine = levels_[child];
    for (std::uint32_t cy = y * 2; cy <= y * 2 + 1 && cy < fine.height; ++cy) {
      const std::int64_t py0 = std::int64_t(cy) << child, py1 = std::int64_t(cy + 1) << child;
      if (py1 <= rect.y0 || py0 >= rect.y1) continue;
      for (std::uint32_t cx = x * 2; cx <= x * 2 + 1 && cx < fine.width; ++cx) {
        const std::int64_t px0 = std::int64_t(cx) << child, px1 = std::int64_t(cx + 1) << child;
        if (px1 <= rect.x0 || px0 >= rect.x1) continue;
        work_.push_back(pack(child, cx, cy));
      }
    }
  }
  return Visibility::Occluded;
}

}  // namespace logrid
