#include "city_hierarchy.hpp"

#include <random>
#include <vector>

namespace logrid {

const bvh::FlatHierarchy& cityHierarchy() {
  static const bvh::FlatHierarchy h = [] {
    constexpr int kBlocks = 34, kBlocksZ = 35;
    constexpr float kPitch = 100, kLot = 38, kGap = 2;  // a 76 m block and its street
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> storeys(4, 20);
    std::vector<Aabb> boxes;
    for (int bx = 0; bx < kBlocks; ++bx) {
      for (int bz = 0; bz < kBlocksZ; ++bz) {
        const float x0 = float(bx - kBlocks / 2) * kPitch;
        const float z0 = float(bz - kBlocksZ / 2) * kPitch;
        for (int lot = 0; lot < 4; ++lot) {
          const float lx = x0 + float(lot & 1) * kLot + kGap;
          const float lz = z0 + float(lot >> 1) * kLot + kGap;
          const float side = kLot - 2 * kGap, top = 3.5f * float(storeys(rng));
          const float t = 0.35f;  // walls' depth: the window boxes stand out
          boxes.push_back({{lx, 0, lz}, {lx + side, top, lz + t}});
          boxes.push_back({{lx, 0, lz + side - t}, {lx + side, top, lz + side}});
          boxes.push_back({{lx, 0, lz}, {lx + t, top, lz + side}});
          boxes.push_back({{lx + side - t, 0, lz}, {lx + side, top, lz + side}});
        }
      }
    }
    bvh::BuildArgs args;
    args.threads = 1;
    return bvh::buildOverBoxes(boxes, args);
  }();
  return h;
}

Camera cityCamera(const DepthSetup& depth) {
  constexpr std::uint32_t kWidth = 640, kHeight = 480;
  const DVec3 eye{-12, 1.7, -1650};
  Camera camera;
  camera.width = kWidth;
  camera.height = kHeight;
  camera.depth = depth;
  camera.view_projection = multiply(perspective(1.0, double(kWidth) / kHeight, 0.3, 4000, depth),
                                    lookAt(eye, {-12, 1.7, 0}, {0, 1, 0}));
  camera.render_origin = eye;
  return camera;
}

}  // namespace logrid
