#include "logrid/cpu/pixel_reader.hpp"

#include <chrono>

namespace logrid::cpu {

void PixelReader::timedFetch(const PixelRect* rects, std::size_t count) {
  data_.resize(count);
  strides_.resize(count);
  const auto start = std::chrono::steady_clock::now();
  fetch(rects, count, data_.data(), strides_.data());
  counters_.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  counters_.reads += count;
  for (std::size_t i = 0; i < count; ++i) counters_.pixels += std::uint64_t(rects[i].area());
  if (drawn_since_read_) {
    ++counters_.flushes;
    drawn_since_read_ = false;
  }
}

void PixelReader::summarize(const PixelRect* rects, std::size_t count, AreaDepth* out) {
  timedFetch(rects, count);
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    out[i] = summarizeDepth(encoding_, data_[i], r.x1 - r.x0, r.y1 - r.y0, strides_[i]);
  }
}

void PixelReader::countAtOrBeyond(const AreaQuery* queries, std::size_t count, std::uint32_t* out) {
  rects_.resize(count);
  for (std::size_t i = 0; i < count; ++i) rects_[i] = queries[i].rect;
  timedFetch(rects_.data(), count);
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects_[i];
    out[i] = countDepthAtOrBeyond(encoding_, data_[i], r.x1 - r.x0, r.y1 - r.y0, strides_[i],
                                  queries[i].threshold);
  }
}

void PixelReader::readKeys(const PixelRect& rect, float* keys) {
  timedFetch(&rect, 1);
  const auto* data = static_cast<const unsigned char*>(data_[0]);
  const std::size_t bytes = nativeDepthBytes(encoding_.native);
  const std::int32_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
  for (std::int32_t y = 0; y < h; ++y) {
    const unsigned char* row = data + std::size_t(y) * strides_[0] * bytes;
    for (std::int32_t x = 0; x < w; ++x) {
      *keys++ = nativeToKey(encoding_, row + std::size_t(x) * bytes);
    }
  }
}

}  // namespace logrid::cpu
