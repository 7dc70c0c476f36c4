// The grid's per-box test (OcclusionGrid::test) on a synthetic depth buffer: ns per
// test, by grid variant, by box size in tiles, in two situations:
//   records  every tile's record is up to date: the test decides from the records and
//            reads nothing (the common case within a frame);
//   reads    every tile under the box was drawn over since it was last read (as right
//            after the frame's first draws): the test reads every internal tile whole
//            (refreshing its record) and the box's part of every border tile, through a
//            software depth buffer (the shared kernels of depth_kernels.hpp).
//
// The buffer holds an occluder at window depth 0.25 everywhere, and every tested box
// lies behind it, so each test answers Occluded after examining every tile under the
// box: the expensive, and the common, case of a culled box. Tiles are 32 pixels; the box
// is n x n tiles large, offset by half a tile, so it covers (n + 1)^2 tiles, (n - 1)^2
// of them internal. The grid and buffer are just large enough for the box, so that in
// "reads" the per-iteration reset of the grid (to make every tile outdated again) costs
// about a nanosecond a tile, against hundreds for reading it; BM_GridResetAndMark
// measures it.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include "logrid/camera.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/grid.hpp"

namespace logrid {
namespace {

constexpr std::int32_t kTile = 32;

struct BoxSetup {
  std::uint32_t size;  // viewport side: the box's tiles and half a tile either side
  PixelRect viewport;
  PixelRect box;
};

BoxSetup boxSetup(std::int32_t tiles) {
  const std::int32_t size = (tiles + 1) * kTile;
  return {std::uint32_t(size),
          {0, 0, size, size},
          {kTile / 2, kTile / 2, kTile / 2 + tiles * kTile, kTile / 2 + tiles * kTile}};
}

void BM_GridTest(benchmark::State& state) {
  const auto variant = static_cast<GridVariant>(state.range(0));
  const bool reads = state.range(1) != 0;
  const BoxSetup s = boxSetup(static_cast<std::int32_t>(state.range(2)));

  cpu::SoftwareDepthBuffer depth(s.size, s.size, DepthConvention::Standard);
  depth.clear();
  depth.fillRect(s.viewport, 0.25f);
  Camera camera;
  camera.width = s.size;
  camera.height = s.size;
  orThrow(depth.beginFrame(camera));

  OcclusionGrid grid({s.size, s.size, std::uint32_t(kTile), variant});
  GridTestCounts counts;
  grid.reset(1.0f);
  grid.markOutdated(s.viewport);
  grid.refreshOutdated(depth, counts);

  // Occlusion state asks for a free pixel; zfar for a pixel at or beyond the box's depth.
  const float threshold = variant == GridVariant::OcclusionState ? 1.0f : 0.5f;
  counts = {};
  const std::uint64_t pixels_before = depth.counters().pixels;
  std::int64_t visible = 0;
  for (auto _ : state) {
    if (reads) {
      grid.reset(1.0f);
      grid.markOutdated(s.viewport);
    }
    visible += grid.test(s.box, threshold, depth, counts) == Visibility::Visible;
  }
  if (visible != 0) state.SkipWithError("a box behind the occluder was found visible");
  const double tests = double(state.iterations());
  state.counters["tiles/test"] = double(counts.tiles_tested) / tests;
  state.counters["tiles_read/test"] = double(counts.tiles_read) / tests;
  state.counters["pixels_read/test"] = double(depth.counters().pixels - pixels_before) / tests;
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::string(toString(variant)) + (reads ? ", reads" : ", records"));
}
BENCHMARK(BM_GridTest)
    ->ArgNames({"variant", "reads", "tiles"})
    ->ArgsProduct({{0, 1}, {0, 1}, {1, 2, 4, 8, 16}});

// What "reads" adds to each test besides the test: resetting the grid and marking every
// tile outdated.
void BM_GridResetAndMark(benchmark::State& state) {
  const BoxSetup s = boxSetup(static_cast<std::int32_t>(state.range(0)));
  OcclusionGrid grid({s.size, s.size, std::uint32_t(kTile), GridVariant::Zfar});
  for (auto _ : state) {
    grid.reset(1.0f);
    grid.markOutdated(s.viewport);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_GridResetAndMark)->ArgName("tiles")->Arg(1)->Arg(4)->Arg(16);

}  // namespace
}  // namespace logrid
