// The conservative box projection (Projector::project): boxes per second for a
// 1280 x 960 camera, per depth convention, over 4096 random boxes in front of the eye
// (each projected to a pixel rectangle, a depth-key range and its margin): one box a
// call, batches of a node's children, and the frustum-only test; and the same two
// batch calls over the nodes a traversal opens on the city's hierarchy.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "city_hierarchy.hpp"
#include "logrid/hierarchy.hpp"
#include "logrid/projection.hpp"

namespace logrid {
namespace {

// 4096 random boxes in front of a 1280 x 960 camera, per depth convention; some lie
// outside the view frustum (about one in three).
struct ProjectionSetup {
  Camera camera;
  std::vector<Aabb> boxes;

  explicit ProjectionSetup(bool reversed) {
    camera.width = 1280;
    camera.height = 960;
    camera.depth = reversed ? DepthSetup{DepthConvention::Reversed, ClipDepthRange::ZeroToOne,
                                         DepthFormat::D32F}
                            : DepthSetup{};
    camera.view_projection = multiply(perspective(1.0, 1280.0 / 960.0, 0.1, 1000.0, camera.depth),
                                      lookAt({0, 2, 0}, {0, 2, -1}, {0, 1, 0}));
    camera.render_origin = {0, 2, 0};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> x(-60, 60), z(-200, -1), size(0.2f, 4.0f);
    boxes.resize(4096);
    for (Aabb& b : boxes) {
      const Vec3 lo{x(rng), x(rng) * 0.2f, z(rng)};
      b = {lo, {lo.x + size(rng), lo.y + size(rng), lo.z + size(rng)}};
    }
  }
  const char* label(bool reversed) const { return reversed ? "reversed 32f" : "standard 32f"; }
};

// One box a call.
void BM_Project(benchmark::State& state) {
  const bool reversed = state.range(0) != 0;
  const ProjectionSetup setup(reversed);
  const Projector projector(setup.camera);
  std::size_t i = 0;
  for (auto _ : state) {
    BoxProjection p = projector.project(setup.boxes[i++ & 4095]);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(setup.label(reversed));
}
BENCHMARK(BM_Project)->ArgName("reversed")->Arg(0)->Arg(1);

// A batch of `batch` boxes a call (a node's children: 2, 4 or 8 in bvh/'s hierarchies),
// items are boxes.
void BM_ProjectBatch(benchmark::State& state) {
  const bool reversed = state.range(0) != 0;
  const auto batch = static_cast<std::size_t>(state.range(1));
  const ProjectionSetup setup(reversed);
  const Projector projector(setup.camera);
  std::vector<BoxProjection> out(batch);
  std::size_t i = 0;
  for (auto _ : state) {
    projector.project(setup.boxes.data() + i, batch, out.data());
    benchmark::DoNotOptimize(out.data());
    i = (i + batch) & 4095;
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(batch));
  state.SetLabel(setup.label(reversed));
}
BENCHMARK(BM_ProjectBatch)->ArgNames({"reversed", "batch"})->ArgsProduct({{0, 1}, {4, 8}});

// Frustum only (Projector::outsideFrustum), a batch of 8 boxes a call; items are boxes.
void BM_Frustum(benchmark::State& state) {
  const bool reversed = state.range(0) != 0;
  const ProjectionSetup setup(reversed);
  const Projector projector(setup.camera);
  for (const Aabb& b : setup.boxes) {
    if (projector.outsideFrustum(b) && projector.project(b).cls != ProjectionClass::Outside) {
      state.SkipWithError("outsideFrustum() culls a box that project() keeps");
      return;
    }
  }
  std::uint8_t outside[8];
  std::size_t i = 0, culled = 0, tested = 0;
  for (auto _ : state) {
    projector.outsideFrustum(setup.boxes.data() + i, 8, outside);
    benchmark::DoNotOptimize(outside);
    for (std::uint8_t o : outside) culled += o;
    tested += 8;
    i = (i + 8) & 4095;
  }
  state.SetItemsProcessed(state.iterations() * 8);
  state.counters["outside"] = tested ? double(culled) / double(tested) : 0.0;
  state.SetLabel(setup.label(reversed));
}
BENCHMARK(BM_Frustum)->ArgName("reversed")->Arg(0)->Arg(1);

// The city's hierarchy seen from its street camera (city_hierarchy.hpp): the nodes whose
// children a view-frustum-culling traversal projects (every node it opens: those whose
// box is not outside the view), found once. An iteration asks the hierarchy for one such
// node's children in one call (Hierarchy::children, through the interface as the
// traversal asks) and tests them in one call; items are boxes.
struct CitySetup {
  Projector projector;
  std::vector<NodeId> opened;
  std::size_t boxes = 0, outside = 0;  // over all opened nodes' children

  explicit CitySetup(bool reversed)
      : projector(cityCamera(reversed ? DepthSetup{DepthConvention::Reversed,
                                                   ClipDepthRange::ZeroToOne, DepthFormat::D32F}
                                      : DepthSetup{})) {
    const Hierarchy& h = cityHierarchy();
    std::vector<NodeId> stack{h.root()}, ids;
    std::vector<Aabb> child_boxes;
    std::vector<BoxProjection> out;
    while (!stack.empty()) {
      const NodeId node = stack.back();
      stack.pop_back();
      const std::uint32_t count = h.childCount(node);
      if (count == 0) continue;
      ids.resize(count), child_boxes.resize(count), out.resize(count);
      h.children(node, ids.data(), child_boxes.data());
      projector.project(child_boxes.data(), count, out.data());
      opened.push_back(node);
      for (std::uint32_t c = 0; c < count; ++c) {
        ++boxes;
        if (out[c].cls == ProjectionClass::Outside) {
          ++outside;
        } else {
          stack.push_back(ids[c]);
        }
      }
    }
  }
  const char* label(bool reversed) const { return reversed ? "city, reversed" : "city, standard"; }
};

constexpr std::uint32_t kMaxChildren = 8;  // bvh/'s largest node

// Runs `test(projector, boxes, count)` over the children of the opened nodes of the city,
// one node an iteration; items are the boxes tested.
template <typename Test>
void overCityChildren(benchmark::State& state, Test test) {
  const bool reversed = state.range(0) != 0;
  const CitySetup setup(reversed);
  const Hierarchy& hierarchy = cityHierarchy();
  NodeId ids[kMaxChildren];
  Aabb boxes[kMaxChildren];
  std::size_t i = 0;
  std::int64_t tested = 0;
  for (auto _ : state) {
    const std::uint32_t count = hierarchy.children(setup.opened[i], ids, boxes);
    test(setup.projector, boxes, count);
    tested += count;
    i = i + 1 == setup.opened.size() ? 0 : i + 1;
  }
  state.SetItemsProcessed(tested);
  state.counters["nodes"] = double(setup.opened.size());
  state.counters["outside"] = double(setup.outside) / double(setup.boxes);
  state.SetLabel(setup.label(reversed));
}

// Projector::project over the children of the opened nodes of the city.
void BM_ProjectCity(benchmark::State& state) {
  BoxProjection out[kMaxChildren];
  overCityChildren(state, [&](const Projector& projector, const Aabb* boxes, std::uint32_t n) {
    projector.project(boxes, n, out);
    benchmark::DoNotOptimize(out);
  });
}
BENCHMARK(BM_ProjectCity)->ArgName("reversed")->Arg(0)->Arg(1);

// The same children's boxes gathered once into one array and projected `batch` a call
// with no hierarchy between (reversed: 0): the per-box cost of the city's boxes apart
// from the hierarchy's call and a node's share of the kernel's entry; a batch of 2 is
// what BM_ProjectCity asks, 8 the largest node.
void BM_ProjectCityBoxes(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(0));
  const CitySetup setup(false);
  const Hierarchy& hierarchy = cityHierarchy();
  std::vector<Aabb> boxes;
  for (const NodeId node : setup.opened) {
    NodeId ids[8];
    Aabb children[8];
    const std::uint32_t count = hierarchy.children(node, ids, children);
    boxes.insert(boxes.end(), children, children + count);
  }
  const std::size_t end = boxes.size() / 8 * 8;
  BoxProjection out[8];
  std::size_t i = 0;
  for (auto _ : state) {
    setup.projector.project(boxes.data() + i, batch, out);
    benchmark::DoNotOptimize(out);
    i = i + 2 * batch > end ? 0 : i + batch;
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(batch));
  state.SetLabel("city, standard");
}
BENCHMARK(BM_ProjectCityBoxes)->ArgName("batch")->Arg(2)->Arg(8);

// Projector::outsideFrustum (frustum only) over the same children.
void BM_FrustumCity(benchmark::State& state) {
  std::uint8_t outside[kMaxChildren];
  overCityChildren(state, [&](const Projector& projector, const Aabb* boxes, std::uint32_t n) {
    projector.outsideFrustum(boxes, n, outside);
    benchmark::DoNotOptimize(outside);
  });
}
BENCHMARK(BM_FrustumCity)->ArgName("reversed")->Arg(0)->Arg(1);

}  // namespace
}  // namespace logrid
