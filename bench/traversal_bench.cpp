// The traversal's overhead per hierarchy node (Culler::cullFrame without rendering):
// frustum test, projection, grid test and the two lists, over a synthetic hierarchy (20,000
// random boxes, or the 19,040 walls of a city-like street grid, city_hierarchy.hpp) and a 640 x 480
// software depth buffer. The draw callback draws nothing, so what is measured is logrid's own cost;
// the depth buffer is the same every frame:
//   empty     nothing drawn: every box in view is visible (tests decided by free tiles,
//             and by reads of the tiles under boxes drawn earlier in the frame);
//   occluder  a wall, drawn before the frame (announced as drawn_before), covers the
//             middle half of the view, so the boxes behind it are culled with their
//             subtrees.
// Methods: vfc (no occlusion test), log-state (two lists), log-zfar (one list).
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "city_hierarchy.hpp"
#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/culler.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kWidth = 640, kHeight = 480;

// Boxes scattered over a 400 x 400 ground area, from 0.5 to 3 units large.
const bvh::FlatHierarchy& hierarchy() {
  static const bvh::FlatHierarchy h = [] {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> ground(-200, 200), height(0, 4), size(0.5f, 3.0f);
    std::vector<Aabb> boxes(20000);
    for (Aabb& b : boxes) {
      const Vec3 lo{ground(rng), height(rng), ground(rng)};
      b = {lo, {lo.x + size(rng), lo.y + size(rng), lo.z + size(rng)}};
    }
    bvh::BuildArgs args;
    args.threads = 1;
    return bvh::buildOverBoxes(boxes, args);
  }();
  return h;
}

void BM_Traversal(benchmark::State& state) {
  const auto method = static_cast<Method>(state.range(0));
  const bool occluder = state.range(1) != 0;
  const bool city = state.range(2) != 0;

  // Random boxes: from outside the field, looking across it. City: at eye height in a
  // street, looking along it (cityCamera()).
  Camera camera;
  if (city) {
    camera = cityCamera({});
  } else {
    camera.width = kWidth;
    camera.height = kHeight;
    const DVec3 eye{0, 2, 190};
    camera.view_projection = multiply(perspective(1.0, double(kWidth) / kHeight, 0.3, 600, {}),
                                      lookAt(eye, {0, 2, 0}, {0, 1, 0}));
    camera.render_origin = eye;
  }
  const bvh::FlatHierarchy& boxes = city ? cityHierarchy() : hierarchy();

  cpu::SoftwareDepthBuffer depth(kWidth, kHeight, DepthConvention::Standard);
  depth.clear();
  std::vector<DrawnArea> drawn_before;
  if (occluder) {
    // The wall's window depth: about 20 units in front of the eye.
    const PixelRect wall{int(kWidth / 4), int(kHeight / 4), int(3 * kWidth / 4),
                         int(3 * kHeight / 4)};
    depth.fillRect(wall, 0.99f);
    drawn_before.push_back({wall, 0.99f});
  }

  CullerDesc desc;
  desc.method = method;
  Culler culler(desc);
  FrameStats total;
  for (auto _ : state) {
    const FrameStats s = culler.cullFrame(
        camera, boxes, depth, [](ObjectId) {}, drawn_before);
    total.nodes_visited += s.nodes_visited;
    total.boxes_tested += s.boxes_tested;
    total.boxes_occluded += s.boxes_occluded;
    total.objects_drawn += s.objects_drawn;
    total.pixels_read += s.pixels_read;
  }
  const double frames = double(state.iterations());
  state.counters["nodes/frame"] = double(total.nodes_visited) / frames;
  state.counters["tested/frame"] = double(total.boxes_tested) / frames;
  state.counters["occluded/frame"] = double(total.boxes_occluded) / frames;
  state.counters["drawn/frame"] = double(total.objects_drawn) / frames;
  state.counters["pixels/frame"] = double(total.pixels_read) / frames;
  // Time per visited node: seconds of the whole run over the nodes visited.
  state.counters["per_node"] = benchmark::Counter(
      double(total.nodes_visited), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetLabel(std::string(toString(method)) + (occluder ? ", occluder" : ", empty") +
                 (city ? ", city" : ", random"));
}
BENCHMARK(BM_Traversal)
    ->ArgNames({"method", "occluder", "city"})
    ->ArgsProduct({{int(Method::Vfc), int(Method::LogState), int(Method::LogZfar)}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace logrid
