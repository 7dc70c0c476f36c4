// The conservative box projection (Projector::project): boxes per second for a
// 1280 x 960 camera, per depth convention, over 4096 random boxes in front of the eye
// (each projected to a pixel rectangle, a depth-key range and its margin).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "logrid/projection.hpp"

namespace logrid {
namespace {

void BM_Project(benchmark::State& state) {
  const bool reversed = state.range(0) != 0;
  Camera camera;
  camera.width = 1280;
  camera.height = 960;
  camera.depth =
      reversed ? DepthSetup{DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D32F}
               : DepthSetup{};
  camera.view_projection = multiply(perspective(1.0, 1280.0 / 960.0, 0.1, 1000.0, camera.depth),
                                    lookAt({0, 2, 0}, {0, 2, -1}, {0, 1, 0}));
  camera.render_origin = {0, 2, 0};
  const Projector projector(camera);

  std::mt19937 rng(11);
  std::uniform_real_distribution<float> x(-60, 60), z(-200, -1), size(0.2f, 4.0f);
  std::vector<Aabb> boxes(4096);
  for (Aabb& b : boxes) {
    const Vec3 lo{x(rng), x(rng) * 0.2f, z(rng)};
    b = {lo, {lo.x + size(rng), lo.y + size(rng), lo.z + size(rng)}};
  }
  std::size_t i = 0;
  for (auto _ : state) {
    BoxProjection p = projector.project(boxes[i++ & 4095]);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(reversed ? "reversed 32f" : "standard 32f");
}
BENCHMARK(BM_Project)->ArgName("reversed")->Arg(0)->Arg(1);

}  // namespace
}  // namespace logrid
