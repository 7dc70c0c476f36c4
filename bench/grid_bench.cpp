// The grid's per-box test (OcclusionGrid::test) on a synthetic depth buffer: ns per
// test, by variant, by box size in tiles, with the tiles' records up to date (decided
// without reading) or outdated (each test reads its tiles from a software buffer).
//
// The buffer (1024 x 1024, 32-pixel tiles) holds an occluder at window depth 0.25
// everywhere and every tested box lies behind it, so each test answers Occluded after
// examining every tile under the box: the expensive, common case of a culled box. The
// box is n x n tiles large, offset by half a tile, so it covers (n + 1)^2 tiles: n^2
// internal-sized, the rest border tiles.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "logrid/camera.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/grid.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kSize = 1024;
constexpr std::uint32_t kTile = 32;

void BM_GridTest(benchmark::State& state) {
  const auto variant = static_cast<GridVariant>(state.range(0));
  const bool outdated = state.range(1) != 0;
  const auto tiles = static_cast<std::int32_t>(state.range(2));

  cpu::SoftwareDepthBuffer depth(kSize, kSize, DepthConvention::Standard);
  const PixelRect viewport{0, 0, std::int32_t(kSize), std::int32_t(kSize)};
  depth.clear();
  depth.fillRect(viewport, 0.25f);
  Camera camera;
  camera.width = kSize;
  camera.height = kSize;
  depth.beginFrame(camera);

  OcclusionGrid grid({kSize, kSize, kTile, variant});
  grid.reset(1.0f);
  grid.markOutdated(viewport);
  GridTestCounts counts;
  if (!outdated) grid.refreshOutdated(depth, counts);

  // Occlusion state asks for a free pixel; zfar for a pixel at or beyond the box's depth.
  const float threshold = variant == GridVariant::OcclusionState ? 1.0f : 0.5f;
  // Boxes at 16 positions, cycled.
  const std::int32_t tile = std::int32_t(kTile);
  const std::int32_t side = tiles * tile;
  const std::int32_t room = std::int32_t(kSize) / tile - tiles - 1;  // in tiles
  PixelRect rects[16];
  for (int i = 0; i < 16; ++i) {
    const std::int32_t x = tile / 2 + tile * (room * (i % 4) / 3);
    const std::int32_t y = tile / 2 + tile * (room * (i / 4) / 3);
    rects[i] = {x, y, x + side, y + side};
  }

  counts = {};
  const std::uint64_t pixels_before = depth.counters().pixels;
  std::size_t i = 0;
  std::int64_t visible = 0;
  for (auto _ : state) {
    const PixelRect& rect = rects[i++ & 15];
    if (outdated) grid.markOutdated(rect);
    visible += grid.test(rect, threshold, depth, counts) == Visibility::Visible;
  }
  if (visible != 0) state.SkipWithError("a box behind the occluder was found visible");
  const double tests = double(state.iterations());
  state.counters["tiles/test"] = double(counts.tiles_tested) / tests;
  state.counters["pixels_read/test"] = double(depth.counters().pixels - pixels_before) / tests;
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::string(toString(variant)) + (outdated ? ", outdated" : ", up to date"));
}
BENCHMARK(BM_GridTest)
    ->ArgNames({"variant", "outdated", "tiles"})
    ->ArgsProduct({{0, 1}, {0, 1}, {1, 2, 4, 8, 16}});

// Marking a box's tiles outdated (what the traversal does after each draw), for
// subtracting from the outdated tests above.
void BM_GridMarkOutdated(benchmark::State& state) {
  const auto tiles = static_cast<std::int32_t>(state.range(0));
  OcclusionGrid grid({kSize, kSize, kTile, GridVariant::Zfar});
  grid.reset(1.0f);
  const std::int32_t side = tiles * std::int32_t(kTile);
  const PixelRect rect{16, 16, 16 + side, 16 + side};
  for (auto _ : state) {
    grid.markOutdated(rect);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_GridMarkOutdated)->ArgName("tiles")->Arg(1)->Arg(4)->Arg(16);

}  // namespace
}  // namespace logrid
