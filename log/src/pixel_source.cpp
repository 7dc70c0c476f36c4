#include "logrid/pixel_source.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <limits>

#include "logrid/elapsed.hpp"

namespace logrid {

void PixelSource::submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) {
  if (count == 0) return;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    pending_.push_back(requests[i]);
    pending_answers_.push_back(answers + i);
  }
  ++counters_.batches;
  counters_.reads += count;
  const std::size_t bytes = nativeDepthBytes(encoding_.native);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t area = std::uint64_t(requests[i].rect.area());
    counters_.pixels += area;
    counters_.bytes += area * bytes;
  }
  // Reads issued after a draw wait for it, once per batch.
  if (drawn_since_read_) {
    ++counters_.flushes;
    drawn_since_read_ = false;
  }
  rects_.resize(count);
  for (std::size_t i = 0; i < count; ++i) rects_[i] = requests[i].rect;
  issue(rects_.data(), count);
  counters_.seconds += secondsSince(start);
  if (!traits().asynchronous) collect();
}

void PixelSource::collect() {
  if (pending_.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  answerPending();
  counters_.seconds += secondsSince(start);
}

void PixelSource::answerPending() {
  const std::size_t n = pending_.size();
  rects_.resize(n);
  data_.resize(n);
  strides_.resize(n);
  for (std::size_t i = 0; i < n; ++i) rects_[i] = pending_[i].rect;
  fetch(rects_.data(), n, data_.data(), strides_.data());
  for (std::size_t i = 0; i < n; ++i) {
    const AreaRequest& q = pending_[i];
    const std::int32_t w = q.rect.x1 - q.rect.x0, h = q.rect.y1 - q.rect.y0;
    AreaAnswer& a = *pending_answers_[i];
    if (!data_[i]) {  // fetch() failed and said why (fail())
      a = conservativeAnswer(q);
    } else if (q.ask == AreaAsk::Summary) {
      a.depth = summarizeDepth(encoding_, data_[i], w, h, strides_[i]);
    } else {
      a.count = countDepthAtOrBeyond(encoding_, data_[i], w, h, strides_[i], q.threshold);
    }
  }
  pending_.clear();
  pending_answers_.clear();
}

void PixelSource::readKeys(const PixelRect& rect, float* keys) {
  assert(pending_.empty() && "PixelSource::readKeys: collect() the submitted requests first");
  const auto start = std::chrono::steady_clock::now();
  issue(&rect, 1);
  data_.resize(1);
  strides_.resize(1);
  fetch(&rect, 1, data_.data(), strides_.data());
  ++counters_.reads;
  ++counters_.batches;
  counters_.pixels += std::uint64_t(rect.area());
  counters_.bytes += std::uint64_t(rect.area()) * nativeDepthBytes(encoding_.native);
  if (drawn_since_read_) {
    ++counters_.flushes;
    drawn_since_read_ = false;
  }
  const auto* data = static_cast<const unsigned char*>(data_[0]);
  const std::size_t bytes = nativeDepthBytes(encoding_.native);
  const std::int32_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
  if (!data) {  // fetch() failed and said why: nothing drawn, as far as anyone knows
    std::fill_n(keys, std::size_t(w) * std::size_t(h), std::numeric_limits<float>::infinity());
    counters_.seconds += secondsSince(start);
    return;
  }
  for (std::int32_t y = 0; y < h; ++y) {
    const unsigned char* row = data + std::size_t(y) * strides_[0] * bytes;
    for (std::int32_t x = 0; x < w; ++x) {
      *keys++ = nativeToKey(encoding_, row + std::size_t(x) * bytes);
    }
  }
  counters_.seconds += secondsSince(start);
}

}  // namespace logrid
