// The native-depth kernels against brute force, for every native type and convention.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "logrid/depth_kernels.hpp"

namespace logrid {
namespace {

template <typename T>
void checkType(NativeDepth native, DepthConvention convention, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const DepthEncoding enc{native, convention};
  const double scale = native == NativeDepth::Float32 ? 1.0 : double(std::numeric_limits<T>::max());
  const bool reversed = convention == DepthConvention::Reversed;
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + int(rng() % 13), h = 1 + int(rng() % 9), stride = w + int(rng() % 4);
    std::vector<T> data(std::size_t(stride) * h);
    for (T& v : data) {
      if (native == NativeDepth::Float32) {
        // Clear value, exact depths and random ones.
        const int pick = int(rng() % 4);
        v = T(pick == 0 ? (reversed ? 0.0 : 1.0) : std::ldexp(double(rng() % 1000), -10));
      } else {
        const int pick = int(rng() % 4);
        v = pick == 0 ? (reversed ? T(0) : std::numeric_limits<T>::max()) : T(rng());
      }
    }
    double lo = INFINITY, hi = -INFINITY;
    std::uint32_t free = 0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const T v = data[std::size_t(y) * stride + x];
        const double key = (reversed ? -1.0 : 1.0) * double(v) / scale;
        lo = std::min(lo, key), hi = std::max(hi, key);
        free += (key == (reversed ? -0.0 : 1.0));
      }
    }
    const AreaDepth a = summarizeDepth(enc, data.data(), w, h, std::size_t(stride));
    EXPECT_LE(double(a.min_key), lo);  // rounded outwards, by at most one float step
    EXPECT_GE(double(a.max_key), hi);
    EXPECT_NEAR(a.min_key, lo, 1e-7);
    EXPECT_NEAR(a.max_key, hi, 1e-7);
    EXPECT_EQ(a.free_pixels, free);

    // Thresholds at, just above and just below stored values count conservatively.
    for (int k = 0; k < 8; ++k) {
      const T pick = data[rng() % data.size()];
      const double key = (reversed ? -1.0 : 1.0) * double(pick) / scale;
      for (float t :
           {float(key), std::nextafter(float(key), 2.0f), std::nextafter(float(key), -2.0f)}) {
        std::uint32_t exact = 0, slack = 0;
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) {
            const double kk =
                (reversed ? -1.0 : 1.0) * double(data[std::size_t(y) * stride + x]) / scale;
            exact += kk >= double(t);
            // The documented slack: half a float ulp of t, and 1e-3 of a unit.
            const double half_ulp =
                0.5 * (double(std::nextafter(std::fabs(t), 2.0f)) - std::fabs(double(t)));
            slack += kk >= double(t) - half_ulp - 1e-3 / scale - 1e-12;
          }
        }
        const std::uint32_t got =
            countDepthAtOrBeyond(enc, data.data(), w, h, std::size_t(stride), t);
        EXPECT_GE(got, exact) << "a pixel at or beyond the threshold was not counted";
        EXPECT_LE(got, slack);
      }
    }
  }
}

TEST(KernelsTest, Float32) {
  checkType<float>(NativeDepth::Float32, DepthConvention::Standard, 1);
  checkType<float>(NativeDepth::Float32, DepthConvention::Reversed, 2);
}
TEST(KernelsTest, Unorm16) {
  checkType<std::uint16_t>(NativeDepth::Unorm16, DepthConvention::Standard, 3);
  checkType<std::uint16_t>(NativeDepth::Unorm16, DepthConvention::Reversed, 4);
}
TEST(KernelsTest, Unorm32) {
  checkType<std::uint32_t>(NativeDepth::Unorm32, DepthConvention::Standard, 5);
  checkType<std::uint32_t>(NativeDepth::Unorm32, DepthConvention::Reversed, 6);
}

TEST(KernelsTest, NanDepthCountsAsNotOccluded) {
  const float data[2] = {std::nanf(""), 0.25f};
  const DepthEncoding enc{NativeDepth::Float32, DepthConvention::Standard};
  EXPECT_EQ(countDepthAtOrBeyond(enc, data, 2, 1, 2, 0.5f), 1u);
}

}  // namespace
}  // namespace logrid
