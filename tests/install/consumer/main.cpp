// A user of an installed logrid, core and bvh only (no GL): culls three boxes for a
// depth buffer nothing has been drawn into. The box in front of the camera must be
// drawn; the one behind the camera and the one far to the side must be view-culled.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/logrid.hpp"

namespace {

// The depth buffer of a renderer that draws nothing: every pixel holds the clear key.
class EmptyDepth : public logrid::DepthSource {
 public:
  logrid::DepthSourceTraits traits() const override { return {"empty", true, false}; }
  logrid::Status beginFrame(const logrid::Camera& camera) override {
    clear_ = logrid::clearKey(camera.depth);
    return {};
  }
  void submit(const logrid::AreaRequest* requests, std::size_t count,
              logrid::AreaAnswer* answers) override {
    for (std::size_t i = 0; i < count; ++i) {
      const auto area = static_cast<std::uint32_t>(requests[i].rect.area());
      answers[i].depth = {clear_, clear_, area};
      answers[i].count = clear_ >= requests[i].threshold ? area : 0u;
    }
  }

 private:
  float clear_ = 1.0f;
};

}  // namespace

int main() {
  const std::vector<logrid::Aabb> boxes = {
      {{-1, -1, -1}, {1, 1, 1}},     // 0: in front of the camera
      {{-1, -1, 20}, {1, 1, 22}},    // 1: behind the camera
      {{100, -1, -1}, {102, 1, 1}},  // 2: far outside the field of view
  };
  const logrid::bvh::FlatHierarchy hierarchy = logrid::bvh::buildOverBoxes(boxes);

  logrid::Camera camera;
  camera.width = 64;
  camera.height = 48;
  camera.view_projection =
      logrid::multiply(logrid::perspective(1.0, 64.0 / 48.0, 0.5, 100.0, camera.depth),
                       logrid::lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0}));
  camera.render_origin = {0, 0, 10};
  if (const std::string why = logrid::validateCamera(camera); !why.empty()) {
    std::printf("consumer_core: FAIL: validateCamera: %s\n", why.c_str());
    return 1;
  }

  EmptyDepth depth;
  logrid::Culler culler;  // lazy occlusion grid, occlusion-state variant
  std::vector<logrid::ObjectId> drawn;
  const logrid::FrameStats stats =
      culler.cullFrame(camera, hierarchy, depth, [&](logrid::ObjectId id) { drawn.push_back(id); });

  std::printf("consumer_core: %s drew %llu of %zu objects, %llu boxes view-culled\n",
              logrid::toString(culler.desc().method),
              static_cast<unsigned long long>(stats.objects_drawn), boxes.size(),
              static_cast<unsigned long long>(stats.boxes_view_culled));
  if (drawn != std::vector<logrid::ObjectId>{0} || stats.boxes_view_culled < 1) {
    std::printf("consumer_core: FAIL: expected exactly object 0 drawn and a view-culled box\n");
    return 1;
  }
  std::printf("consumer_core: OK\n");
  return 0;
}
