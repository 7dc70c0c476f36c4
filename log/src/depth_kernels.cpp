#include "logrid/depth_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "rounding.hpp"

namespace logrid {
namespace {

using detail::roundDown;
using detail::roundUp;

template <typename T>
constexpr double unormScale() {
  return double(std::numeric_limits<T>::max());
}

// Min, max and clear count of the raw values; the clear value is the largest value for
// the standard convention and zero for the reversed one.
template <typename T>
void scanRange(const T* data, std::int32_t width, std::int32_t height, std::size_t stride, T clear,
               T& lo, T& hi, std::uint32_t& clear_count) {
  T mn = data[0], mx = data[0];
  std::uint32_t n = 0;
  for (std::int32_t y = 0; y < height; ++y) {
    const T* row = data + std::size_t(y) * stride;
    for (std::int32_t x = 0; x < width; ++x) {
      const T v = row[x];
      mn = v < mn ? v : mn;
      mx = v > mx ? v : mx;
      n += (v == clear);
    }
  }
  lo = mn, hi = mx, clear_count = n;
}

template <typename T>
AreaDepth summarizeUnorm(const T* data, std::int32_t w, std::int32_t h, std::size_t stride,
                         bool reversed) {
  T lo, hi;
  std::uint32_t free_count;
  const T clear = reversed ? T(0) : std::numeric_limits<T>::max();
  scanRange(data, w, h, stride, clear, lo, hi, free_count);
  const double dlo = double(lo) / unormScale<T>(), dhi = double(hi) / unormScale<T>();
  AreaDepth out;
  out.free_pixels = free_count;
  if (reversed) {
    out.min_key = roundDown(-dhi);
    out.max_key = roundUp(-dlo);
  } else {
    out.min_key = roundDown(dlo);
    out.max_key = roundUp(dhi);
  }
  return out;
}

AreaDepth summarizeFloat(const float* data, std::int32_t w, std::int32_t h, std::size_t stride,
                         bool reversed) {
  float lo, hi;
  std::uint32_t free_count;
  scanRange(data, w, h, stride, reversed ? 0.0f : 1.0f, lo, hi, free_count);
  AreaDepth out;
  out.free_pixels = free_count;
  out.min_key = reversed ? -hi : lo;
  out.max_key = reversed ? -lo : hi;
  return out;
}

// Counts values v with v >= lo (or v <= hi when `below`): branch-free for vectorising.
template <typename T>
std::uint32_t countCompare(const T* data, std::int32_t width, std::int32_t height,
                           std::size_t stride, T bound, bool below) {
  std::uint32_t n = 0;
  for (std::int32_t y = 0; y < height; ++y) {
    const T* row = data + std::size_t(y) * stride;
    if (below) {
      for (std::int32_t x = 0; x < width; ++x) n += !(row[x] > bound);
    } else {
      for (std::int32_t x = 0; x < width; ++x) n += !(row[x] < bound);
    }
  }
  return n;
}

// Keys are floats, so a threshold stands for every depth that rounds to it: the count
// must include any stored value whose float key equals or exceeds the threshold. The
// bound is therefore taken from the lower edge of the threshold's rounding interval
// (half a float ulp below), and the product's own error (2^-52 relative) is covered by a
// further 1e-3 of a unit. This may count a stored value within half an ulp below the
// threshold as well: an extra pixel counted is conservative, a dropped one is not.
template <typename T>
std::uint32_t countUnorm(const T* data, std::int32_t w, std::int32_t h, std::size_t stride,
                         bool reversed, float threshold) {
  const double scale = unormScale<T>();
  const double half_ulp =
      0.5 * (double(std::nextafter(std::fabs(threshold), 2.0f)) - double(std::fabs(threshold)));
  if (!reversed) {
    // depth >= t  <=>  v >= t * scale
    const double bound = std::ceil((double(threshold) - half_ulp) * scale - 1e-3);
    if (bound <= 0) return std::uint32_t(w) * std::uint32_t(h);
    if (bound > scale) return 0;
    return countCompare<T>(data, w, h, stride, T(bound), false);
  }
  // -depth >= t  <=>  v <= -t * scale
  const double bound = std::floor((-double(threshold) + half_ulp) * scale + 1e-3);
  if (bound >= scale) return std::uint32_t(w) * std::uint32_t(h);
  if (bound < 0) return 0;
  return countCompare<T>(data, w, h, stride, T(bound), true);
}

}  // namespace

AreaDepth summarizeDepth(const DepthEncoding& enc, const void* data, std::int32_t width,
                         std::int32_t height, std::size_t stride) {
  const bool reversed = enc.convention == DepthConvention::Reversed;
  switch (enc.native) {
    case NativeDepth::Float32:
      return summarizeFloat(static_cast<const float*>(data), width, height, stride, reversed);
    case NativeDepth::Unorm16:
      return summarizeUnorm(static_cast<const std::uint16_t*>(data), width, height, stride,
                            reversed);
    case NativeDepth::Unorm32:
      return summarizeUnorm(static_cast<const std::uint32_t*>(data), width, height, stride,
                            reversed);
  }
  return {};
}

std::uint32_t countDepthAtOrBeyond(const DepthEncoding& enc, const void* data, std::int32_t width,
                                   std::int32_t height, std::size_t stride, float threshold) {
  const bool reversed = enc.convention == DepthConvention::Reversed;
  switch (enc.native) {
    case NativeDepth::Float32: {
      // key >= t  <=>  depth >= t (standard) or depth <= -t (reversed). NaN counts.
      const auto* f = static_cast<const float*>(data);
      return reversed ? countCompare(f, width, height, stride, -threshold, true)
                      : countCompare(f, width, height, stride, threshold, false);
    }
    case NativeDepth::Unorm16:
      return countUnorm(static_cast<const std::uint16_t*>(data), width, height, stride, reversed,
                        threshold);
    case NativeDepth::Unorm32:
      return countUnorm(static_cast<const std::uint32_t*>(data), width, height, stride, reversed,
                        threshold);
  }
  return std::uint32_t(width) * std::uint32_t(height);
}

float nativeToKey(const DepthEncoding& enc, const void* value) {
  double depth = 0;
  switch (enc.native) {
    case NativeDepth::Float32: {
      float f;
      std::memcpy(&f, value, sizeof f);
      depth = f;
      break;
    }
    case NativeDepth::Unorm16: {
      std::uint16_t v;
      std::memcpy(&v, value, sizeof v);
      depth = v / unormScale<std::uint16_t>();
      break;
    }
    case NativeDepth::Unorm32: {
      std::uint32_t v;
      std::memcpy(&v, value, sizeof v);
      depth = v / unormScale<std::uint32_t>();
      break;
    }
  }
  return static_cast<float>(enc.convention == DepthConvention::Reversed ? -depth : depth);
}

}  // namespace logrid
