// A world of boxes for testing the culler without GL: random boxes behind a row of
// walls over a ground slab, drawn by the software rasteriser, and the object-ID oracle
// that says which boxes a full render shows.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/culler.hpp"
#include "test_sources.hpp"

namespace logrid::test {

struct BoxWorld {
  std::vector<Aabb> boxes;
  bvh::FlatHierarchy hierarchy;
};

// Walls near the camera hide most of a field of boxes behind them.
inline BoxWorld makeBoxWorld(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> x(-40, 40), z(-120, -15), s(0.2f, 3.0f), y(-2, 4);
  BoxWorld world;
  for (int i = 0; i < 600; ++i) {
    const Vec3 lo{x(rng), y(rng), z(rng)};
    world.boxes.push_back({lo, {lo.x + s(rng), lo.y + s(rng), lo.z + s(rng)}});
  }
  for (int i = 0; i < 6; ++i) {  // occluders
    const float cx = -12.0f + 5.0f * float(i);
    world.boxes.push_back({{cx, -3, -12}, {cx + 4.2f, 6, -11}});
  }
  world.boxes.push_back({{-100, -4, -200}, {100, -3, 0}});  // ground slab
  world.hierarchy = bvh::buildOverBoxes(world.boxes, {1, 2, 1});
  return world;
}

inline Camera boxCamera(std::uint32_t w, std::uint32_t h, DepthConvention convention, double yaw) {
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = {convention,
               convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                       : ClipDepthRange::NegativeOneToOne,
               DepthFormat::D32F};
  const DVec3 eye{0, 1, 0};
  const DVec3 target{std::sin(yaw) * 10, 0.5, -std::cos(yaw) * 10};
  cam.view_projection = multiply(perspective(1.0, double(w) / h, 0.3, 300, cam.depth),
                                 lookAt(eye, target, {0, 1, 0}));
  return cam;
}

inline void drawBox(cpu::SoftwareRasterizer& raster, const Aabb& box, std::uint32_t id) {
  std::vector<float> p;
  std::vector<std::uint32_t> idx;
  cpu::appendBox(box, p, idx);
  raster.draw(p, idx, id);
}

// The oracle: the ids a full render of `boxes` shows.
inline std::set<ObjectId> visibleBoxes(const std::vector<Aabb>& boxes, const Camera& cam) {
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  std::vector<std::uint32_t> ids(std::size_t(cam.width) * cam.height, cpu::kNoId);
  cpu::SoftwareRasterizer raster(cam, depth, &ids);
  for (std::uint32_t i = 0; i < boxes.size(); ++i) drawBox(raster, boxes[i], i);
  std::set<ObjectId> visible;
  for (std::uint32_t id : ids) {
    if (id != cpu::kNoId) visible.insert(id);
  }
  return visible;
}

enum class SourceKind {
  Software,   // synchronous, reads depth
  Batched,    // asynchronous, reads depth (like the PBO ring)
  CountOnly,  // asynchronous, counts only (like occlusion queries)
};

inline const char* toString(SourceKind k) {
  return k == SourceKind::Software ? "software" : k == SourceKind::Batched ? "batched" : "count";
}

struct CulledFrame {
  std::set<ObjectId> drawn;
  FrameStats stats;
};

// Culls and draws one frame of `world` through the software rasteriser into `depth`
// (cleared first). `extra` runs after each object is drawn, with the rasteriser.
inline CulledFrame cullBoxes(
    Culler& culler, const BoxWorld& world, const Camera& cam, cpu::SoftwareDepthBuffer& depth,
    SourceKind kind, const std::function<void(ObjectId, cpu::SoftwareRasterizer&)>& extra = {},
    const std::vector<DrawnArea>& drawn_before = {}) {
  CulledFrame out;
  BatchedSource batched(depth);
  CountOnlySource counts(depth);
  DepthSource& source = kind == SourceKind::Software  ? static_cast<DepthSource&>(depth)
                        : kind == SourceKind::Batched ? static_cast<DepthSource&>(batched)
                                                      : static_cast<DepthSource&>(counts);
  cpu::SoftwareRasterizer raster(cam, depth, nullptr);
  out.stats = culler.cullFrame(
      cam, world.hierarchy, source,
      [&](ObjectId id) {
        drawBox(raster, world.boxes[id], id);
        EXPECT_TRUE(out.drawn.insert(id).second) << "drawn twice: " << id;
        if (extra) extra(id, raster);
      },
      drawn_before);
  return out;
}

}  // namespace logrid::test
