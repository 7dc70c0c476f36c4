// The depth kernels (depth_kernels.hpp) every pixel-reading source answers with: pixels
// per second for a summary (nearest key, farthest key, free pixels) and for a threshold
// count, per native depth format, over square areas of 8, 32 and 128 pixels a side
// (32: a tile of LOG §5).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "logrid/depth_kernels.hpp"

namespace logrid {
namespace {

// Random stored values of the format, about a tenth of them cleared.
template <typename T>
std::vector<T> randomValues(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<T> values(count);
  for (T& v : values) {
    const double d = unit(rng) < 0.1 ? 1.0 : unit(rng);
    if constexpr (std::is_floating_point_v<T>) {
      v = static_cast<T>(d);
    } else {
      v = static_cast<T>(d * double(std::numeric_limits<T>::max()));
    }
  }
  return values;
}

template <typename T, NativeDepth kNative>
void BM_Summarize(benchmark::State& state) {
  const auto side = static_cast<std::int32_t>(state.range(0));
  const std::vector<T> values = randomValues<T>(std::size_t(side) * std::size_t(side), 7);
  const DepthEncoding encoding{kNative, DepthConvention::Standard};
  for (auto _ : state) {
    AreaDepth area = summarizeDepth(encoding, values.data(), side, side, std::size_t(side));
    benchmark::DoNotOptimize(area);
  }
  state.SetItemsProcessed(state.iterations() * side * side);
}

template <typename T, NativeDepth kNative>
void BM_CountAtOrBeyond(benchmark::State& state) {
  const auto side = static_cast<std::int32_t>(state.range(0));
  const std::vector<T> values = randomValues<T>(std::size_t(side) * std::size_t(side), 7);
  const DepthEncoding encoding{kNative, DepthConvention::Standard};
  for (auto _ : state) {
    std::uint32_t count =
        countDepthAtOrBeyond(encoding, values.data(), side, side, std::size_t(side), 0.5f);
    benchmark::DoNotOptimize(count);
  }
  state.SetItemsProcessed(state.iterations() * side * side);
}

BENCHMARK_TEMPLATE(BM_Summarize, float, NativeDepth::Float32)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);
BENCHMARK_TEMPLATE(BM_Summarize, std::uint16_t, NativeDepth::Unorm16)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);
BENCHMARK_TEMPLATE(BM_Summarize, std::uint32_t, NativeDepth::Unorm32)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);
BENCHMARK_TEMPLATE(BM_CountAtOrBeyond, float, NativeDepth::Float32)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);
BENCHMARK_TEMPLATE(BM_CountAtOrBeyond, std::uint16_t, NativeDepth::Unorm16)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);
BENCHMARK_TEMPLATE(BM_CountAtOrBeyond, std::uint32_t, NativeDepth::Unorm32)
    ->ArgName("side")
    ->Arg(8)
    ->Arg(32)
    ->Arg(128);

}  // namespace
}  // namespace logrid
