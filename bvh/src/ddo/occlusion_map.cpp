#include "logrid/ddo/occlusion_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace logrid::ddo {

void OcclusionMap::reset(std::uint32_t width, std::uint32_t height, float clear_key) {
  if (width != width_ || height != height_) {
    width_ = width;
    height_ = height;
    tiles_x_ = (width + kTile - 1) / kTile;
    tiles_y_ = (height + kTile - 1) / kTile;
    keys_.assign(std::size_t(width) * height, clear_key);
    tile_max_.assign(std::size_t(tiles_x_) * tiles_y_, clear_key);
    tile_dirty_.assign(tile_max_.size(), 0);
  } else {
    std::fill(keys_.begin(), keys_.end(), clear_key);
    std::fill(tile_max_.begin(), tile_max_.end(), clear_key);
  }
  clear_ = clear_key;
}

std::uint64_t OcclusionMap::insertQuad(const double window[4][2], double a, double b, double c) {
  double ylo = window[0][1], yhi = window[0][1];
  for (int i = 1; i < 4; ++i) ylo = std::min(ylo, window[i][1]), yhi = std::max(yhi, window[i][1]);
  // Rows whose centre y + 0.5 lies in [ylo, yhi].
  const long row0 = std::max(0L, long(std::ceil(ylo - 0.5)));
  const long row1 = std::min(long(height_) - 1, long(std::floor(yhi - 0.5)));
  std::uint64_t written = 0;
  for (long y = row0; y <= row1; ++y) {
    const double sy = double(y) + 0.5;
    double xl = HUGE_VAL, xr = -HUGE_VAL;
    for (int i = 0; i < 4; ++i) {
      const double* p = window[i];
      const double* q = window[(i + 1) % 4];
      if ((p[1] <= sy && sy <= q[1]) || (q[1] <= sy && sy <= p[1])) {
        if (p[1] == q[1]) {
          xl = std::min({xl, p[0], q[0]});
          xr = std::max({xr, p[0], q[0]});
        } else {
          const double x = p[0] + (sy - p[1]) * (q[0] - p[0]) / (q[1] - p[1]);
          xl = std::min(xl, x);
          xr = std::max(xr, x);
        }
      }
    }
    if (!(xl <= xr)) continue;
    const long col0 = std::max(0L, long(std::ceil(xl - 0.5)));
    const long col1 = std::min(long(width_) - 1, long(std::floor(xr - 0.5)));
    if (col0 > col1) continue;
    float* row = keys_.data() + std::size_t(y) * width_;
    for (long x = col0; x <= col1; ++x) {
      // The plane in double, rounded up to the next float: never nearer than the occluder.
      const double k = a + b * (double(x) + 0.5) + c * sy;
      float f = float(k);
      if (double(f) < k) f = std::nextafter(f, std::numeric_limits<float>::infinity());
      if (f < row[x]) {
        row[x] = f;
        ++written;
      }
    }
    for (long tx = col0 / long(kTile); tx <= col1 / long(kTile); ++tx) {
      const std::size_t t = std::size_t(y / long(kTile)) * tiles_x_ + std::size_t(tx);
      if (!tile_dirty_[t]) {
        tile_dirty_[t] = 1;
        dirty_list_.push_back(std::uint32_t(t));
      }
    }
  }
  for (std::uint32_t t : dirty_list_) {
    tile_dirty_[t] = 0;
    refreshTile(t % tiles_x_, t / tiles_x_);
  }
  dirty_list_.clear();
  return written;
}

void OcclusionMap::refreshTile(std::uint32_t tx, std::uint32_t ty) {
  const std::uint32_t x0 = tx * kTile, y0 = ty * kTile;
  const std::uint32_t x1 = std::min(width_, x0 + kTile), y1 = std::min(height_, y0 + kTile);
  float m = -std::numeric_limits<float>::infinity();
  for (std::uint32_t y = y0; y < y1; ++y) {
    const float* row = keys_.data() + std::size_t(y) * width_;
    for (std::uint32_t x = x0; x < x1; ++x) m = std::max(m, row[x]);
  }
  tile_max_[std::size_t(ty) * tiles_x_ + tx] = m;
}

bool OcclusionMap::occludes(const PixelRect& r, float threshold) const {
  const std::int32_t x0 = std::max(0, r.x0), y0 = std::max(0, r.y0);
  const std::int32_t x1 = std::min(std::int32_t(width_), r.x1);
  const std::int32_t y1 = std::min(std::int32_t(height_), r.y1);
  if (x0 >= x1 || y0 >= y1) return false;
  if (!(threshold > -std::numeric_limits<float>::infinity())) return false;
  const std::uint32_t tx0 = std::uint32_t(x0) / kTile, tx1 = std::uint32_t(x1 - 1) / kTile;
  const std::uint32_t ty0 = std::uint32_t(y0) / kTile, ty1 = std::uint32_t(y1 - 1) / kTile;
  for (std::uint32_t ty = ty0; ty <= ty1; ++ty) {
    for (std::uint32_t tx = tx0; tx <= tx1; ++tx) {
      if (tile_max_[std::size_t(ty) * tiles_x_ + tx] < threshold) continue;
      // The tile holds a pixel at or beyond the threshold; is it under the rectangle?
      const std::int32_t px0 = std::max(x0, std::int32_t(tx * kTile));
      const std::int32_t px1 = std::min(x1, std::int32_t((tx + 1) * kTile));
      const std::int32_t py0 = std::max(y0, std::int32_t(ty * kTile));
      const std::int32_t py1 = std::min(y1, std::int32_t((ty + 1) * kTile));
      for (std::int32_t y = py0; y < py1; ++y) {
        const float* row = keys_.data() + std::size_t(y) * width_;
        for (std::int32_t x = px0; x < px1; ++x) {
          if (!(row[x] < threshold)) return false;
        }
      }
    }
  }
  return true;
}

}  // namespace logrid::ddo
